#!/usr/bin/env bash
# README command one: bootstrap the environment, then run the main job on a small default.
# Until the trainer lands (issue 5) the main job is the classic NEAT XOR benchmark.
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
bash "$ROOT/scripts/bootstrap.sh"
cd "$ROOT"
export NUMBA_CACHE_DIR="${NUMBA_CACHE_DIR:-$ROOT/.venv/numba-cache}"
OUT="${1:-$ROOT/out/demo}"
mkdir -p "$OUT"
echo "== XOR benchmark (10 seeded runs, population 150)" >&2
.venv/bin/mentor-xor --runs 10 --seed 0 | tee "$OUT/xor.json"
echo "== drawing a UGV training world" >&2
.venv/bin/mentor-draw --robot ugv --seed 0 --scenario 0 --out "$OUT/world_ugv.png"
echo "demo: results in $OUT" >&2
