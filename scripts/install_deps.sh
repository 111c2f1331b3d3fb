#!/usr/bin/env bash
# Installs every Debian 12 package rbaa needs to build, test and run, and makes OpenBLAS the
# BLAS/LAPACK that CHOLMOD actually runs with. Idempotent: safe to run again.
set -euo pipefail

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive

PACKAGES=(
  build-essential cmake pkg-config
  libceres-dev libeigen3-dev libsuitesparse-dev
  libgoogle-glog-dev libgflags-dev
  libcgal-dev libcgal-demo
  libbullet-dev libbullet-extras-dev
  libboost-graph-dev libyaml-cpp-dev nlohmann-json3-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libopenblas0-pthread libopenblas-pthread-dev
  gnuplot-nox
  python3                # scripts/outcome_table.py, make_obstacle_meshes.py and their tests
)
# A one-node Slurm for the real-engine test of `rbaa sweep --emit=slurm`
# (scripts/slurm_localhost.sh; the test skips without it): installed in CI, or when asked.
if [ "${CI:-}" = true ] || [ "${RBAA_WITH_SLURM:-}" = 1 ]; then
  PACKAGES+=(slurm-wlm munge)
fi
# OpenBLAS's OpenMP build, beside the pthread build rbaa uses, for the test that rbaa does not
# livelock in it (CliSimulate.OpenblasOpenmpBuildFinishes; it skips without it): installed in CI,
# or when asked. Its alternatives' priority (95) is below the pthread build's (100), and the
# loop below pins the BLAS and LAPACK alternatives to the pthread build by name.
if [ "${CI:-}" = true ] || [ "${RBAA_WITH_OPENBLAS_OPENMP:-}" = 1 ]; then
  PACKAGES+=(libopenblas0-openmp)
fi

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ "${#missing[@]}" -gt 0 ]; then
  echo "[rbaa] installing: ${missing[*]}" >&2
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

# libceres-dev pulls in ATLAS and Debian's alternatives may then pick it as the system BLAS and
# LAPACK; CHOLMOD factorised the ball's system ~3x slower under ATLAS than under OpenBLAS on two
# threads (SPEC section 9). Point every BLAS/LAPACK alternative at OpenBLAS's pthread build, by
# name, not by Debian's priorities (pthread 100, OpenMP 95, ATLAS 35 on Debian 12; a manual choice
# elsewhere would otherwise stay): the OpenMP build factorised 4-20x slower (bench_newton,
# 2026-11-29: ball 107 ms against 26 ms) and livelocked in rbaa's dynamic OpenMP teams
# (sim/threads.cpp). The serial build ties with the pthread build on one thread, which rbaa sets.
arch=$(dpkg-architecture -qDEB_HOST_MULTIARCH 2>/dev/null || echo x86_64-linux-gnu)
# libopenblas.so.0 too: librbaa links it directly (Ceres's and SuiteSparse's link interfaces), and
# its alternative is otherwise left to priorities (pthread 100 over OpenMP 95).
for name in libblas.so.3 liblapack.so.3 libblas.so liblapack.so libopenblas.so.0 libopenblas.so; do
  alt="${name}-${arch}"
  target=$(update-alternatives --list "$alt" 2>/dev/null | grep openblas-pthread | head -n1 || true)
  if [ -n "$target" ]; then
    $SUDO update-alternatives --set "$alt" "$target" >/dev/null
  fi
done
echo "[rbaa] dependencies ready; BLAS: $(readlink -f /usr/lib/${arch}/libblas.so.3)" >&2
