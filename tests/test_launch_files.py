"""The launch files, the RViz2 config and the Foxglove layout shipped with the node packages.

``launch`` has no PyPI wheel: where it imports (a full ROS 2 Jazzy install) the launch files
are loaded and their descriptions built; here they are compiled, so that at least their
syntax is checked. The viewer configs are parsed and must show the topics the nodes publish.
"""

from __future__ import annotations

import importlib.util
import json
import py_compile
from pathlib import Path
from typing import Any

import pytest
import yaml

ROOT = Path(__file__).resolve().parents[1]
LAUNCH_FILES = [
    ROOT / "mentor_sim_node" / "launch" / "mentor.launch.py",
    ROOT / "mentor_planner_node" / "launch" / "planner.launch.py",
]
CONFIG = ROOT / "mentor_sim_node" / "config"
RVIZ = ROOT / "mentor_ros_common" / "config" / "mentor.rviz"
#: what a viewer must show for robot_0: topics the simulator and planner use, and the path
#: and scan map the planner publishes
ROBOT_TOPICS = {"scan", "lidar/scan", "odom", "goal", "plan", "global_plan", "scan_map"}
TOPICS = {"/mentor/obstacles", "/map"} | {f"/robot_0/{t}" for t in ROBOT_TOPICS}
_LAUNCH = importlib.util.find_spec("launch")
# the real package, not the namespace package the node packages' launch/ folders make of the
# name when the node packages' roots are on sys.path (tests/ros_support.py puts them there)
HAVE_LAUNCH = _LAUNCH is not None and _LAUNCH.origin is not None


@pytest.mark.parametrize("path", LAUNCH_FILES, ids=lambda p: p.name)
def test_launch_files_compile_and_build_where_launch_is_installed(
    path: Path, tmp_path: Path
) -> None:
    py_compile.compile(str(path), cfile=str(tmp_path / "launch.pyc"), doraise=True)
    if not HAVE_LAUNCH:
        return
    spec = importlib.util.spec_from_file_location(path.stem.replace(".", "_"), path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    assert module.generate_launch_description().entities  # pragma: no cover - full install


def test_launch_files_are_installed_with_the_packages() -> None:
    for pkg in ("mentor_sim_node", "mentor_planner_node"):
        assert "launch/" in (ROOT / pkg / "setup.py").read_text()
    assert "config/mentor.rviz" in (ROOT / "mentor_ros_common" / "setup.py").read_text()
    assert "<exec_depend>rviz2</exec_depend>" in (ROOT / "mentor_ros_common" /
                                                  "package.xml").read_text()


def _strings(node: Any) -> set[str]:
    if isinstance(node, dict):
        return set().union(*(_strings(v) for v in node.values()), *(_strings(k) for k in node))
    if isinstance(node, list):
        return set().union(*(_strings(v) for v in node)) if node else set()
    return {node} if isinstance(node, str) else set()


def test_the_rviz_config_shows_map_robots_scans_goals_and_paths_of_any_namespace() -> None:
    config = yaml.safe_load(RVIZ.read_text())
    manager = config["Visualization Manager"]
    assert manager["Global Options"]["Fixed Frame"] == "map"
    shown = _strings(manager["Displays"])
    assert {"/mentor/obstacles", "/map", "robot_description"} | ROBOT_TOPICS <= shown
    assert not any("robot_0" in text for text in shown)  # relative: rviz2 in the namespace
    classes = {d["Class"] for d in manager["Displays"]}
    assert {"rviz_default_plugins/TF", "rviz_default_plugins/RobotModel",
            "rviz_default_plugins/Map"} <= classes
    goal_tool = next(t for t in manager["Tools"] if t["Class"].endswith("SetGoal"))
    assert goal_tool["Topic"]["Value"] == "/goal_pose"


def test_the_foxglove_layout_shows_the_same() -> None:
    layout = json.loads((CONFIG / "foxglove_layout.json").read_text())
    panel = layout["configById"]["3D!mentor"]
    assert panel["followTf"] == "map"
    assert TOPICS <= set(panel["topics"])
    assert "/robot_0/robot_description" in _strings(panel["layers"])
    assert panel["publish"]["poseTopic"] == "/goal_pose"
