#!/usr/bin/env bash
# The main job: installs the dependencies, builds, and runs the default attack (the paper's ball
# off the backboard, configs/ball.yaml, 50 Adam iterations and 30 polish iterations: about 4
# minutes on 2 cores) with progress on stderr. Outputs go to out/ball/ (report.json, adversarial.msh/.vtu, progress.csv);
# re-running it resumes from out/ball/checkpoint.json. Extra arguments go to `rbaa attack`
# (e.g. --iterations=200 for a paper-quality run).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
bash scripts/build.sh
OUT=${RBAA_OUT:-out/ball}
mkdir -p "$OUT"
"${RBAA_BUILD_DIR:-build}/src/rbaa" attack --config=configs/ball.yaml --out="$OUT" --resume "$@"
