#!/usr/bin/env bash
# Mutation check: how many small bugs planted in the library does the test suite catch?
#
# NOT part of CI and not run by scripts/test.sh: it rebuilds and runs the suite once per mutant,
# about 1-2 minutes each on 2 cores (70 s on average measured: 5 s to rebuild, the rest ctest up to
# the first failure; a survivor runs the whole suite), so the default 40 mutants take 45-80
# minutes, plus about 11 minutes for the first build of the scratch copy and 2 for one baseline
# run of the suite.
#
#   bash scripts/mutation_check.sh [--count N] [--seed S] [--list [--all]] [--only ID,ID]
#                                  [--repo DIR] [--report FILE] [--work DIR] [--equivalent FILE]
#                                  [--jobs J] [--skip-baseline]
#
# Mutants are single edits to src/{sim,diff,geometry,opt,eval,rigid}/*.cpp (never in comments,
# string literals or preprocessor lines; headers are left alone, since changing one recompiles
# most of the tree):
#   arith       binary + <-> -, * <-> /, and += <-> -=, *= <-> /=
#   compare     < <-> <=, > <-> >=, == <-> !=
#   constant    a floating literal doubled (1.0 -> 1.1), an integer next to an operator doubled
#   loop-bound  for (...; i < n; ...) -> i < n - 1
#   drop-term   "a + b * c" -> "a", or a whole += / -= statement removed
#   sign        a unary minus removed, or -( ) put around a numeric value returned or assigned
# Every candidate is enumerated deterministically from the committed HEAD of --repo (default:
# the checkout holding this script; uncommitted changes are ignored), and --count of them
# (default 40) are sampled with --seed (default 1), spread over the six folders in proportion
# to their candidates. Ids are hashes of the file and the mutated line, so they survive edits
# elsewhere. --list prints the sample (--all: every candidate) without building anything.
#
# Each mutant is applied to a scratch copy (--work, default /tmp/rbaa-mutation: src-tree/ is
# git archive of HEAD, build/ one persistent Ninja build without the benchmarks), rebuilt with
# `nice cmake --build -j2`, tested with `nice ctest -j2 --timeout 300 --no-tests=error
# --stop-on-failure` (OMP_NUM_THREADS=2 OPENBLAS_NUM_THREADS=1), and the file is restored. The
# real checkout is only read. Before the first mutant the unmutated tree must pass the suite
# (checked once per commit). Per mutant one line: id, file:line, kind, "before -> after" (the
# whole source line) and KILLED (first failing tests) / TIMEOUT (counts as killed) / SURVIVED /
# BUILD-FAILED (killed by the compiler: not scored) / EQUIVALENT (listed in
# scripts/mutation_equivalent.txt with the reason: not run, not scored). At the end: the score,
# killed / (compiled, non-equivalent) mutants, and the survivors; the same report goes to
# --report (default ./mutation_report.txt); per-mutant build and ctest logs to WORK/logs/.
# Re-run one mutant with --only ID.
set -euo pipefail
exec python3 "$(dirname "$0")/mutation_check.py" "$@"
