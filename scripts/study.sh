#!/usr/bin/env bash
# The paper-scale study (issue 5): both robots x both frameworks x SEEDS, each best genome
# evaluated on bags/unseen/<robot>, one report over everything.
# Usage: scripts/study.sh [OUT_DIR] [SEEDS] [JOBS]     (default out/study, "1 2 3", 2)
# Runs already finished are kept; interrupted ones resume.
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
bash "$ROOT/scripts/bootstrap.sh"
cd "$ROOT"
export NUMBA_CACHE_DIR="${NUMBA_CACHE_DIR:-$ROOT/.venv/numba-cache}"
OUT="${1:-$ROOT/out/study}"
SEEDS="${2:-1 2 3}"
JOBS="${3:-2}"
BIN="$ROOT/.venv/bin"
mkdir -p "$OUT"
train_one() {  # robot framework seed
  local run="$OUT/$1-$2-s$3" resume=()
  [ -n "$(ls -A "$run" 2>/dev/null)" ] && resume=(--resume)
  "$BIN/mentor-train" --robot "$1" --framework "$2" --config paper --seed "$3" --out "$run" \
    --quiet "${resume[@]}" && echo "study: trained $run" >&2
}
export -f train_one
export OUT BIN
for robot in ugv swarm; do for fw in single dual; do for s in $SEEDS; do
  echo "$robot $fw $s"
done; done; done | xargs -P "$JOBS" -L 1 bash -c 'train_one "$@"' _
evals=()
for robot in ugv swarm; do
  genomes=() labels=()
  for fw in single dual; do for s in $SEEDS; do
    genomes+=("$OUT/$robot-$fw-s$s/best_genome.json"); labels+=(--label "$fw-s$s")
  done; done
  # --force: an earlier study's evaluation in OUT is redone from its runs
  "$BIN/mentor-eval" "${genomes[@]}" "${labels[@]}" --bag "$ROOT/bags/unseen/$robot" \
    --out "$OUT/eval_unseen_$robot.json" --force > "$OUT/eval_unseen_$robot.txt"
  evals+=(--eval "$OUT/eval_unseen_$robot.json")
done
"$BIN/mentor-report" "$OUT"/*-s*/ "${evals[@]}" --out "$OUT/report"
echo "study: report at $OUT/report/report.md" >&2
