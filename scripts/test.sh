#!/usr/bin/env bash
# README command two: bootstrap the environment, then lint, type-check and run the test suite.
# Extra arguments go to pytest (e.g. scripts/test.sh -k ranking).
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
bash "$ROOT/scripts/bootstrap.sh"
cd "$ROOT"
# DDS discovery stays on this machine; a domain of our own (tests pick their own per worker).
export ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST
export ROS_DOMAIN_ID="${ROS_DOMAIN_ID:-42}"
export NUMBA_CACHE_DIR="${NUMBA_CACHE_DIR:-$ROOT/.venv/numba-cache}"
# the generated tf2_msgs and nav2_msgs, where bootstrap could make them (interfaces/README.md)
if [ -f "$ROOT/ros2_ws/interfaces/install/local_setup.bash" ]; then
  set +u; source "$ROOT/ros2_ws/interfaces/install/local_setup.bash"; set -u
fi
echo "== ruff" >&2
.venv/bin/ruff check mentor_core tests benchmarks scripts mentor_sim_node mentor_planner_node \
  mentor_ros_common mentor_bringup
echo "== lint-imports (the import contracts of docs/architecture.md, in pyproject.toml)" >&2
PYTHONPATH="$ROOT/mentor_sim_node:$ROOT/mentor_planner_node:$ROOT/mentor_ros_common:$ROOT/mentor_bringup" \
  .venv/bin/lint-imports --no-cache
echo "== mypy --strict mentor_core" >&2
.venv/bin/mypy --strict mentor_core/src/mentor_core
echo "== pytest" >&2
# two workers unless told otherwise (-n 0: one process): the suite's ROS tests each take a
# domain of their worker's (tests/conftest.py), so they run side by side
case " $* " in *" -n "*|*" -n"[0-9a]*|*" --numprocesses"*) exec .venv/bin/python -m pytest "$@" ;; esac
exec .venv/bin/python -m pytest -n 2 "$@"
