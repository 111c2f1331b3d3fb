#!/usr/bin/env bash
# Installs the dependencies, builds, and runs the whole test suite with ctest.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
bash scripts/build.sh
# Thread counts are fixed so that results are reproducible (SPEC section 8).
export OMP_NUM_THREADS=${OMP_NUM_THREADS:-2} OPENBLAS_NUM_THREADS=${OPENBLAS_NUM_THREADS:-1}
cd "${RBAA_BUILD_DIR:-build}"
ctest --output-on-failure --no-tests=error --timeout 900 -j2
