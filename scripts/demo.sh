#!/usr/bin/env bash
# README command one: bootstrap the environment, then run the main job on a small default:
# train the Swarm-Robot planner with both frameworks (quick config), evaluate both best
# genomes on the unseen environment (bags/unseen/swarm) and write the report with its figures.
# Usage: scripts/demo.sh [OUT_DIR] [SEED]      (default out/demo, seed 1)
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
bash "$ROOT/scripts/bootstrap.sh"
cd "$ROOT"
export NUMBA_CACHE_DIR="${NUMBA_CACHE_DIR:-$ROOT/.venv/numba-cache}"
OUT="${1:-$ROOT/out/demo}"
SEED="${2:-1}"
BIN="$ROOT/.venv/bin"
mkdir -p "$OUT"
for fw in single dual; do
  run="$OUT/swarm-$fw"
  # a finished run is kept; an interrupted one continues where it stopped
  resume=()
  [ -n "$(ls -A "$run" 2>/dev/null)" ] && resume=(--resume)
  echo "== training the Swarm-Robot planner, $fw-stage (quick config)" >&2
  if ! "$BIN/mentor-train" --robot swarm --framework "$fw" --config quick --seed "$SEED" \
    --out "$run" "${resume[@]}"; then
    [ ${#resume[@]} -gt 0 ] && echo "demo: $run holds an earlier run that this config or" \
      "version cannot continue; remove it, or give another OUT_DIR (scripts/demo.sh OUT_DIR)" >&2
    exit 1
  fi
done
echo "== evaluating both best genomes on the unseen environment bags/unseen/swarm" \
  "(as trained, and as the shipped planners are deployed)" >&2
# --force: the evaluation of an earlier demo in OUT is redone from its runs
"$BIN/mentor-eval" "$OUT/swarm-single/best_genome.json" "$OUT/swarm-dual/best_genome.json" \
  --bag "$ROOT/bags/unseen/swarm" --label single --label dual \
  --deployment none --deployment shipped \
  --out "$OUT/eval_unseen.json" --force
echo "== writing the report" >&2
# --force: the report of an earlier demo in OUT is replaced
"$BIN/mentor-report" "$OUT/swarm-single" "$OUT/swarm-dual" --eval "$OUT/eval_unseen.json" \
  --out "$OUT/report" --force
echo "demo: report at $OUT/report/report.md" >&2
