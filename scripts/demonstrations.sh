#!/usr/bin/env bash
# The five demonstrations from scratch (README, "Demonstrations"): each adversarial object made by
# its config's attack, then judged by `rbaa evaluate` on its demonstration scene (reference,
# adversarial and soft control, rigid and deformable: summary.md's outcome table) and exported for
# PolyFEM, and the five outcome tables gathered into one (scripts/outcome_table.py) in
# OUT/outcomes.md. The cube stack's cubes are meshed at 1500 tets (RBAA_STACK_TETS; the config's
# 10164 take ~50 min per deformable run). Measured 2026-11-28 on two shared cores, two at a time:
# 67 min in all; the attacks ball 34 min, bat 43, bunny 23, cube and star under a minute; the
# evaluations 7 s (star) to 8 min (bin). Run end to end on 2026-11-29 beside other work: 84 min.
# A demonstration whose command fails is reported and left out of the table; the script then exits
# 1, as it does when the table cannot be made. Attacks resume from their checkpoints when run again.
#
#   bash scripts/demonstrations.sh [--out=DIR] [--jobs=N] [--only=hoop,bin,stack,star,bat] [--dry-run]
#
# --out: where everything goes (default out/demos); --jobs: demonstrations run side by side
# (default 2, each on one thread); --only: a subset; --dry-run: print each demonstration's
# commands, one per line after its name, and run nothing. RBAA: the binary (default
# $RBAA_BUILD_DIR/src/rbaa, build/src/rbaa without it; no spaces in the path).
set -uo pipefail
cd "$(dirname "$0")/.."

OUT=out/demos
JOBS=2
ONLY=hoop,bin,stack,star,bat
DRY=0
for arg in "$@"; do
  case "$arg" in
    --out=*) OUT=${arg#--out=} ;;
    --jobs=*) JOBS=${arg#--jobs=} ;;
    --only=*) ONLY=${arg#--only=} ;;
    --dry-run) DRY=1 ;;
    *) echo "demonstrations.sh: unknown argument '$arg' (see the script's head)" >&2; exit 2 ;;
  esac
done
if ! [[ "$JOBS" =~ ^[1-9][0-9]*$ ]]; then
  echo "demonstrations.sh: --jobs=$JOBS must be a whole number of at least 1" >&2
  exit 2
fi
case "$OUT" in
  *[[:space:]]*) echo "demonstrations.sh: --out='$OUT' holds a space; choose a folder without" >&2
                 exit 2 ;;
esac
RBAA=${RBAA:-${RBAA_BUILD_DIR:-build}/src/rbaa}
TETS=${RBAA_STACK_TETS:-1500}
case "$RBAA" in  # the commands are split into words when run
  *[[:space:]]*) echo "demonstrations.sh: RBAA='$RBAA' holds a space; use a path without" >&2
                 exit 2 ;;
esac

# A demonstration's commands, one per line: the attack of ATTACK_CONFIG into OUT/ATTACK_DIR, the
# evaluation of its object on configs/demos/DEMO.yaml into OUT/NAME and its export into
# OUT/polyfem_NAME; SETS go to all three, EVAL_FLAGS to the evaluation alone.
three() {  # ATTACK_CONFIG ATTACK_DIR DEMO NAME [SETS [EVAL_FLAGS]]
  local object=$OUT/$2/adversarial.msh sets=${5:+ $5} eval_flags=${6:+ $6}
  echo "$RBAA attack --config=configs/$1$sets --out=$OUT/$2"
  echo "$RBAA evaluate --config=configs/demos/$3.yaml --adversarial=$object$sets$eval_flags --out=$OUT/$4"
  echo "$RBAA export --format=polyfem --config=configs/demos/$3.yaml --adversarial=$object$sets --out=$OUT/polyfem_$4"
}

# Each demonstration's commands.
commands() {
  case "$1" in
    hoop) three ball_accurate.yaml ball_accurate ball_hoop hoop ;;
    bin) three bunny_accurate.yaml bunny_accurate bunny_bin bin ;;
    stack) three cube_strike.yaml cube cube_stack stack "--set=mesh.target_tets=$TETS" ;;
    star) three star.yaml star_attack star star ;;
    bat) three bat_accurate.yaml bat_accurate bat bat "" "--duration=0.5" ;;
    *) return 1 ;;
  esac
}

# Longest first, so that two at a time finish together.
DEMOS=()
IFS=, read -r -a asked <<< "$ONLY"
for d in bat hoop bin stack star; do
  for a in "${asked[@]}"; do [ "$a" = "$d" ] && DEMOS+=("$d") && break; done
done
for a in "${asked[@]}"; do
  if ! commands "$a" > /dev/null; then
    echo "demonstrations.sh: --only names '$a', not one of hoop, bin, stack, star, bat" >&2
    exit 2
  fi
done

if [ "$DRY" = 1 ]; then
  for d in "${DEMOS[@]}"; do
    echo "$d"
    commands "$d"
  done
  exit 0
fi

if [ ! -x "$RBAA" ]; then
  echo "demonstrations.sh: no rbaa binary at $RBAA (build first: bash scripts/build.sh)" >&2
  exit 2
fi
mkdir -p "$OUT/logs"
LOG=$OUT/times.log
rm -f "$OUT/outcomes.md"  # an earlier run's table is not this one's

run_demo() {
  local d=$1 step=0 line
  while IFS= read -r line; do
    step=$((step + 1))
    local t0=$SECONDS
    echo "[$(date +%T)] $d $step: $line" >> "$LOG"
    if ! OMP_NUM_THREADS=1 $line > "$OUT/logs/$d.$step.log" 2>&1; then
      echo "[$(date +%T)] $d $step FAILED after $((SECONDS - t0)) s (log: $OUT/logs/$d.$step.log)" | tee -a "$LOG" >&2
      return 1
    fi
    echo "[$(date +%T)] $d $step done in $((SECONDS - t0)) s" >> "$LOG"
  done < <(commands "$d")
}

declare -A pid_of
for d in "${DEMOS[@]}"; do
  while [ "$(jobs -rp | wc -l)" -ge "$JOBS" ]; do wait -n; done
  echo "demonstrations.sh: $d (log: $LOG)" >&2
  run_demo "$d" &
  pid_of[$d]=$!
done
failed=0
tables=()
for d in "${DEMOS[@]}"; do
  if wait "${pid_of[$d]}"; then
    tables+=("$d=$OUT/$d")
  else
    failed=1
  fi
done
if [ ${#tables[@]} -gt 0 ]; then
  # A table that cannot be made (a report without outcomes) fails the run; no empty table stays.
  if python3 scripts/outcome_table.py "${tables[@]}" --out="$OUT/outcomes.md"; then
    cat "$OUT/outcomes.md"
  else
    rm -f "$OUT/outcomes.md"
    failed=1
  fi
fi
exit $failed
