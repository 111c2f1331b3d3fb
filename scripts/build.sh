#!/usr/bin/env bash
# Configures and builds rbaa (Release, OpenMP) into build/ with every core.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${RBAA_BUILD_DIR:-build}
cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$BUILD_DIR" -j"$(nproc)"
