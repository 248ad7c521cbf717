#!/usr/bin/env bash
# Create or refresh the project's environment: .venv from requirements.lock (hash-pinned),
# mentor_core installed editable, and the colcon workspace ros2_ws/ built.
# Idempotent and quick when nothing changed. Sourced by scripts/demo.sh and scripts/test.sh.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
VENV="$ROOT/.venv"

find_python() {
  for cand in "${PYTHON:-}" python3.11 python3; do
    [ -n "$cand" ] || continue
    if command -v "$cand" >/dev/null 2>&1 &&
       "$cand" -c 'import sys; sys.exit(sys.version_info[:2] != (3, 11))' 2>/dev/null; then
      echo "$cand"; return 0
    fi
  done
  echo "bootstrap: Python 3.11 is required (set PYTHON=/path/to/python3.11)" >&2
  return 1
}

if [ ! -x "$VENV/bin/python" ]; then
  PY="$(find_python)"
  if ! "$PY" -m venv "$VENV" 2>/dev/null; then
    rm -rf "$VENV"
    # Debian ships venv/ensurepip separately; install it when we may.
    if command -v apt-get >/dev/null 2>&1 && [ "$(id -u)" = 0 ]; then
      echo "bootstrap: installing python3-venv with apt-get" >&2
      apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq python3-venv >/dev/null
      "$PY" -m venv "$VENV"
    else
      echo "bootstrap: '$PY -m venv' failed; install python3-venv (Debian: sudo apt-get install python3-venv)" >&2
      exit 1
    fi
  fi
fi

STAMP="$VENV/.mentor-stamp"
want="$(cat "$ROOT/requirements.lock" "$ROOT/mentor_core/pyproject.toml" | sha256sum | cut -d' ' -f1)"
if [ "$(cat "$STAMP" 2>/dev/null)" != "$want" ]; then
  echo "bootstrap: installing locked dependencies into .venv (first run takes a minute)" >&2
  # The lock is complete (every transitive pin, hashed), so pip installs it as listed with
  # --no-deps: its resolver then cannot reach past a pin (pip 23.2 did, for an extra such as
  # pytest-cov's coverage[toml], as soon as a newer coverage was on the index), and
  # `pip check` proves the pins agree. (grep drops the noise of local pip mirrors.)
  "$VENV/bin/python" -m pip install -q --disable-pip-version-check --require-hashes --no-deps \
    -r "$ROOT/requirements.lock" 2> >(grep -v 'is ignored: it is neither' >&2)
  "$VENV/bin/python" -m pip check --disable-pip-version-check >/dev/null ||
    { "$VENV/bin/python" -m pip check >&2; echo "bootstrap: requirements.lock is inconsistent" >&2
      exit 1; }
  "$VENV/bin/python" -m pip install -q --disable-pip-version-check --no-deps \
    --no-build-isolation -e "$ROOT/mentor_core"
  echo "$want" > "$STAMP"
fi

# Build the ROS 2 workspace when a node package changed since the last build.
WS="$ROOT/ros2_ws"
WSTAMP="$WS/install/.mentor-stamp"
wwant="$(cd "$ROOT" && find mentor_sim_node mentor_planner_node mentor_ros_common mentor_bringup -type f \
  -not -path '*/__pycache__/*' -print0 | sort -z | xargs -0 sha256sum | sha256sum | cut -d' ' -f1)"
if [ "$(cat "$WSTAMP" 2>/dev/null)" != "$wwant" ]; then
  echo "bootstrap: building the colcon workspace ros2_ws/" >&2
  # colcon's output is kept for a failure only (setuptools warns on every clean build).
  blog="$(mktemp)"
  (cd "$WS" && rm -rf build install log &&
   PATH="$VENV/bin:$PATH" "$VENV/bin/colcon" --log-base log build \
     --event-handlers console_direct- >"$blog" 2>&1) ||
    { cat "$blog" >&2; echo "bootstrap: colcon build failed; see ros2_ws/log/latest_build" >&2
      exit 1; }
  rm -f "$blog"
  for pkg in mentor_sim_node mentor_planner_node mentor_ros_common mentor_bringup; do
    [ -d "$WS/install/$pkg" ] ||
      { echo "bootstrap: colcon built no $pkg (is ros2_ws/src/$pkg a symlink?)" >&2; exit 1; }
  done
  echo "$wwant" > "$WSTAMP"
fi

# tf2_msgs and nav2_msgs have no wheel: generate them (interfaces/README.md) where a C compiler
# and Python's headers are here, into ros2_ws/interfaces/install (scripts/test.sh sources it).
IWS="$WS/interfaces"
ISTAMP="$IWS/install/.mentor-stamp"
iwant="$(cd "$ROOT" && find interfaces -type f -print0 | sort -z | xargs -0 sha256sum |
  cat - requirements.lock | sha256sum | cut -d' ' -f1)"
if [ "$(cat "$ISTAMP" 2>/dev/null)" != "$iwant" ]; then
  pyinc="$("$VENV/bin/python" -c 'import sysconfig; print(sysconfig.get_paths()["include"])')"
  if ! command -v cc >/dev/null 2>&1 || ! command -v c++ >/dev/null 2>&1 ||
     [ ! -f "$pyinc/Python.h" ]; then
    echo "bootstrap: no C/C++ compiler or Python.h here (Debian: apt-get install g++" \
      "python3.11-dev): tf2_msgs and nav2_msgs not generated; the tests of the live TF path" \
      "and the NavigateToPose action are skipped" >&2
  else
    echo "bootstrap: generating tf2_msgs and nav2_msgs in ros2_ws/interfaces/" >&2
    ilog="$(mktemp)"
    (rm -rf "$IWS" && mkdir -p "$IWS" && cd "$IWS" &&
     PATH="$VENV/bin:$PATH" AMENT_PREFIX_PATH="$VENV" CMAKE_PREFIX_PATH="$VENV" \
       "$VENV/bin/colcon" --log-base log build --base-paths "$ROOT/interfaces" \
       --event-handlers console_direct- --cmake-args -G Ninja \
       -DPython3_EXECUTABLE="$VENV/bin/python" -DBUILD_TESTING=OFF \
       -DCMAKE_PROJECT_INCLUDE="$ROOT/interfaces/fix_wheel_include_dirs.cmake" >"$ilog" 2>&1) ||
      { cat "$ilog" >&2; echo "bootstrap: generating the interfaces failed; see" \
          "ros2_ws/interfaces/log/latest_build" >&2; exit 1; }
    rm -f "$ilog"
    echo "$iwant" > "$ISTAMP"
  fi
fi
