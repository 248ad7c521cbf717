"""Robot presets of the planner node, and the launch arguments that change them.

A preset is a parameter file installed with the package (``config/<robot>.yaml``): the
topics' kinds, frames, limits, footprint, lidar mount and scan map of one robot, so that
``planner.launch.py robot:=turtlebot3_burger genome:=ugv-paper-dual-s1`` drives a TurtleBot3
with nothing else set. A launch argument left empty keeps the preset's value; one given
replaces it (:func:`launch_parameters`), each checked to one line.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

import yaml

from mentor_core import MentorError, launch_flag, launch_number, launch_numbers

ROBOTS = ("generic", "turtlebot3_burger", "turtlebot3_waffle", "mentor_sim")
#: the launch arguments that set a parameter, and how their text is read
_NUMBERS = ("goal_radius", "yaw_goal_tolerance", "sync_tolerance", "max_vel_x",
            "max_vel_theta", "acc_lim_x", "acc_lim_theta", "robot_radius", "scan_map_size",
            "repeat_rate", "time_limit")  # fmt: skip
_FLAGS = ("use_sim_time", "cmd_vel_stamped", "decide_on_timer")
_LISTS = ("lidar_mount", "scan_map_origin")
_TEXTS = ("genome", "profile", "deployment", "footprint")
PARAMETERS = _TEXTS + _NUMBERS + _FLAGS + _LISTS
#: the presets in the package's source (installed into share/mentor_planner_node/config)
SOURCE_CONFIG = Path(__file__).resolve().parents[1] / "config"


def preset_file(robot: str, share: str | Path) -> Path:
    """The parameter file of preset ``robot`` in the package's ``share`` folder; MentorError
    (one line) for a robot with no preset."""
    if robot not in ROBOTS:
        raise MentorError(f"robot:={robot}: no preset of that name ({', '.join(ROBOTS)})")
    return Path(share) / "config" / f"{robot}.yaml"


def preset_values(path: str | Path) -> dict[str, Any]:
    """The parameters a preset file sets (its ``/**: ros__parameters:`` mapping)."""
    doc = yaml.safe_load(Path(path).read_text(encoding="utf-8"))
    return dict(doc["/**"]["ros__parameters"])


def launch_parameters(values: Mapping[str, str]) -> dict[str, Any]:
    """The parameters that launch arguments ``values`` (name -> text; '' : the preset's)
    set, each as its type; MentorError (one line naming the argument) for a bad one."""
    out: dict[str, Any] = {}
    for name in PARAMETERS:
        text = values.get(name, "").strip()
        if not text:
            continue
        if name in _NUMBERS:
            out[name] = launch_number(name, text)
        elif name in _FLAGS:
            out[name] = launch_flag(name, text)
        elif name in _LISTS:
            out[name] = launch_numbers(name, text)
        else:
            out[name] = text
    return out
