#!/usr/bin/env bash
# The paper-scale study (issues 5 and 15): configs x both robots x both frameworks x SEEDS.
# Every best genome is scored on the generalisation benchmark's TEST split (mentor-bench, 40
# pairs per family, beside the VFH+ and Bug2 baselines and the oracle; seeds summarised as
# mean +- sd) and on bags/unseen/<robot> (mentor-eval); one report over everything.
# Usage: scripts/study.sh [OUT_DIR] [SEEDS] [JOBS] [CONFIGS]
#   defaults: out/study, "1 2 3", 2, "original paper" (the paper's settings and the shipped
#   ones; a CONFIGS word is a shipped config name, a YAML file labelled by its stem, or a
#   folder holding <robot>.yaml for each robot, labelled by its name; ":dual" or ":single"
#   after a word trains that framework alone, e.g. benchmarks/configs/simplicity:dual).
#   JOBS: training runs side by side, and the benchmark's worker processes.
# Runs go to OUT/<config>/<robot>-<framework>-s<seed>; finished ones are kept, interrupted
# ones resume. Nothing here chooses a setting: the test split and the bags are only reported.
# The benchmark runs every genome as the shipped planners are deployed, and the baselines
# plain, guarded, on their scan map and both (STUDY_BENCH_FLAGS, default "--deployment
# shipped": the rows of benchmarks/RESULTS.md's headline tables; "--deployment shipped --set
# stages.turn_gain=null" without the Swarm-Robot's turn gain, "--deployment FILE" any other
# deployment; "" for the plain rows only), and the unseen bags are scored a second time that
# way (eval_unseen_<robot>_deployed.json, the runs labelled "deployed-..."); the networks
# alone are benched too (bench_<robot>_plain, no baselines). Last, the report of everything
# (OUT/report) and the paper's results side by side (OUT/report/reproduction.md, mentor-report
# --paper; docs/reproduction.md is that page of the study in benchmarks/RESULTS.md).
# Issue 55's study (benchmarks/RESULTS.md, "The paper side by side"): STUDY_PAIRS=0
#   scripts/study.sh out/study "1 2 3 4 5" 2 "original paper benchmarks/configs/simplicity:dual"
#   then benchmarks/tools/g_ablation.py out/study --bench for the test split.
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
bash "$ROOT/scripts/bootstrap.sh"
cd "$ROOT"
export NUMBA_CACHE_DIR="${NUMBA_CACHE_DIR:-$ROOT/.venv/numba-cache}"
OUT="${1:-$ROOT/out/study}"
SEEDS="${2:-1 2 3}"
JOBS="${3:-2}"
CONFIGS="${4:-original paper}"
PAIRS="${STUDY_PAIRS:-40}"  # benchmark pairs per family; 0: no benchmark (runs and bags only)
read -r -a BENCH_FLAGS <<< "${STUDY_BENCH_FLAGS---deployment shipped}"
BIN="$ROOT/.venv/bin"
mkdir -p "$OUT"
word() { echo "${1%%:*}"; }  # a CONFIGS word without its frameworks
label() { local w; w="$(word "$1")"; basename "${w%.yaml}"; }
frameworks() { [[ "$1" == *:* ]] && echo "${1##*:}" | tr ',' ' ' || echo "single dual"; }
config_for() {  # word robot: the --config value
  local w; w="$(word "$1")"
  if [ -d "$w" ]; then echo "$w/$2.yaml"; else echo "$w"; fi
}
train_one() {  # config robot framework seed
  local run="$OUT/$(label "$1")/$2-$3-s$4" resume=()
  mkdir -p "$(dirname "$run")"
  [ -n "$(ls -A "$run" 2>/dev/null)" ] && resume=(--resume)
  "$BIN/mentor-train" --robot "$2" --framework "$3" --config "$(config_for "$1" "$2")" \
    --seed "$4" --out "$run" --quiet "${resume[@]}" && echo "study: trained $run" >&2
}
export -f train_one label word config_for
export OUT BIN
for config in $CONFIGS; do for robot in ugv swarm; do for fw in $(frameworks "$config"); do
  for s in $SEEDS; do echo "$config $robot $fw $s"; done
done; done; done | xargs -P "$JOBS" -L 1 bash -c 'train_one "$@"' _
extra=() runs=()
for robot in ugv swarm; do
  genomes=() labels=()
  for config in $CONFIGS; do for fw in $(frameworks "$config"); do for s in $SEEDS; do
    run="$OUT/$(label "$config")/$robot-$fw-s$s"
    genomes+=("$run/best_genome.json"); labels+=(--label "$(label "$config")-$fw-s$s")
    runs+=("$run")
  done; done; done
  # --force: an earlier study's evaluation in OUT is redone from its runs
  "$BIN/mentor-eval" "${genomes[@]}" "${labels[@]}" --bag "$ROOT/bags/unseen/$robot" \
    --out "$OUT/eval_unseen_$robot.json" --force > "$OUT/eval_unseen_$robot.txt"
  extra+=(--eval "$OUT/eval_unseen_$robot.json")
  if [ "${#BENCH_FLAGS[@]}" -gt 0 ]; then
    deployed=()
    for ((i = 0; i < ${#labels[@]}; i += 2)); do deployed+=(--label "deployed-${labels[i + 1]}"); done
    "$BIN/mentor-eval" "${genomes[@]}" "${deployed[@]}" --bag "$ROOT/bags/unseen/$robot" \
      "${BENCH_FLAGS[@]}" --out "$OUT/eval_unseen_${robot}_deployed.json" --force \
      > "$OUT/eval_unseen_${robot}_deployed.txt"
    extra+=(--eval "$OUT/eval_unseen_${robot}_deployed.json")
  fi
  [ "$PAIRS" -gt 0 ] || continue
  rm -rf "$OUT/bench_$robot"
  "$BIN/mentor-bench" "${genomes[@]}" "${labels[@]}" --robot "$robot" --split test \
    --pairs-per-family "$PAIRS" "${BENCH_FLAGS[@]}" --workers "$JOBS" --out "$OUT/bench_$robot" \
    > "$OUT/bench_$robot.txt"
  extra+=(--bench "$OUT/bench_$robot/bench.json")
  if [ "${#BENCH_FLAGS[@]}" -gt 0 ]; then  # the networks alone too, without baselines
    rm -rf "$OUT/bench_${robot}_plain"
    "$BIN/mentor-bench" "${genomes[@]}" "${labels[@]}" --robot "$robot" --split test \
      --pairs-per-family "$PAIRS" --baselines none --no-oracle --workers "$JOBS" \
      --out "$OUT/bench_${robot}_plain" > "$OUT/bench_${robot}_plain.txt"
  fi
done
"$BIN/mentor-report" "${runs[@]}" "${extra[@]}" --out "$OUT/report" --force
"$BIN/mentor-report" --paper "$OUT" --out "$OUT/report/reproduction.md" --force
echo "study: report at $OUT/report/report.md, the paper side by side at" \
  "$OUT/report/reproduction.md" >&2
