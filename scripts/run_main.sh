#!/usr/bin/env bash
# The main job: installs the dependencies, builds, and runs the default job with progress on
# stderr. Until the attack lands (issue 4) the default job meshes the reference ball with CGAL and
# prints its mass moments. Outputs go to out/ball/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
bash scripts/build.sh
OUT=${RBAA_OUT:-out/ball}
mkdir -p "$OUT"
./build/src/rbaa mesh --shape=sphere --target_tets=9056 --out="$OUT/ball.msh"
./build/src/rbaa moments --mesh="$OUT/ball.msh" | tee "$OUT/moments.json"
