"""The planner node's robot presets, launch arguments and setup checks: each preset starts the
node with a shipped planner named, not pathed; an argument given replaces the preset's value;
a footprint as Nav2 writes it; parameters that would hurt are one line (issue 56, point 4)."""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import pytest
import yaml
from ros_support import ROOT, Graph, params

from mentor_core.errors import MentorError
from mentor_planner_node.params import PlannerSetupError, resolve_genome
from mentor_planner_node.planner import PlannerNode
from mentor_planner_node.presets import (
    PARAMETERS,
    ROBOTS,
    SOURCE_CONFIG,
    launch_parameters,
    preset_file,
    preset_values,
)

pytestmark = pytest.mark.ros


def _node(graph: Graph, **values: Any) -> PlannerNode:
    return graph.add(PlannerNode(context=graph.context, parameter_overrides=params(**values)))


@pytest.mark.parametrize("robot", ROBOTS)
def test_every_preset_starts_the_node_with_a_shipped_planner(graph: Graph, robot: str) -> None:
    values = preset_values(preset_file(robot, SOURCE_CONFIG.parent))
    node = _node(graph, **values, genome=str(ROOT / "planners" / "ugv-paper-dual-s1.json"))
    declared = {name for name in values if node.has_parameter(name)}
    assert declared == set(values), f"{robot}: keys no parameter takes"
    # one deployment mechanism: no preset sets what a deployment sets
    assert not {"scan_map", "rotation_shim_deg", "collision_guard", "turn_gain"} & set(values)
    assert node.planner is not None and node.profile.name == "ugv"


def test_the_turtlebot_presets_set_the_robots_limits_and_footprint(graph: Graph) -> None:
    burger = _node(graph, **preset_values(SOURCE_CONFIG / "turtlebot3_burger.yaml"),
                   genome=str(ROOT / "planners" / "ugv-paper-dual-s1.json"))  # fmt: skip
    p = burger.params
    assert (p.limits.max_vel_x, p.limits.max_vel_theta) == (0.22, 2.84)
    assert p.decide_on_timer and p.scan_kind == "lidar" and p.goal_radius == 0.5
    assert p.deployed is not None and p.deployed.profile.length == pytest.approx(0.21)
    assert p.deployed.guide is not None  # the shipped deployment's scan map
    waffle = preset_values(SOURCE_CONFIG / "turtlebot3_waffle.yaml")
    assert yaml.safe_load(waffle["footprint"])[0] == [-0.205, -0.155]


def test_launch_arguments_replace_the_presets_values_and_a_bad_one_is_one_line() -> None:
    given = {name: "" for name in PARAMETERS}
    assert launch_parameters(given) == {}  # all the preset's
    given.update(goal_radius="0.3", cmd_vel_stamped="true", lidar_mount="[0.1, 0, 0]",
                 genome="ugv-paper-dual-s1")
    assert launch_parameters(given) == {"goal_radius": 0.3, "cmd_vel_stamped": True,
                                        "lidar_mount": [0.1, 0.0, 0.0],
                                        "genome": "ugv-paper-dual-s1"}  # fmt: skip
    for name, text, fault in (("goal_radius", "far", "expected a number"),
                              ("cmd_vel_stamped", "ture", "expected true or false"),
                              ("scan_map_origin", "[1, x]", "expected a list of numbers")):
        with pytest.raises(MentorError, match=re.escape(f"{name}:={text}: {fault}")):
            launch_parameters({name: text})
    with pytest.raises(MentorError, match="robot:=tb4: no preset of that name"):
        preset_file("tb4", SOURCE_CONFIG.parent)


def test_a_shipped_planner_is_found_by_name_where_the_package_is_installed() -> None:
    assert resolve_genome("") == ""
    here = str(ROOT / "planners" / "ugv-paper-dual-s1.json")
    assert resolve_genome(here) == here  # a file that exists is taken as given
    installed = resolve_genome("ugv-paper-dual-s1")
    if installed != "ugv-paper-dual-s1":  # run from the colcon install (AMENT_PREFIX_PATH)
        assert installed.endswith("share/mentor_planner_node/planners/ugv-paper-dual-s1.json")
        assert Path(installed).read_bytes() == Path(here).read_bytes()
    assert resolve_genome("no-such-planner") == "no-such-planner"  # loading names it


@pytest.mark.parametrize(("values", "fault"), [
    ({"footprint": "[[0, 0], [1, 1]]"}, "footprint '[[0, 0], [1, 1]]' is not a polygon"),
    ({"repeat_rate": 500.0}, "repeat_rate: a period of 0.002 s is shorter than the floor"),
    ({"scan_map_size": 20.0, "deployment": "shipped",
      "deployment_set": ["scan_map.resolution=0.001"]}, "scan_map_size: the scan map of 20 x 20"),
])  # fmt: skip
def test_parameters_that_would_hurt_are_refused_in_one_line(
    graph: Graph, values: dict[str, Any], fault: str
) -> None:
    with pytest.raises(MentorError) as err:
        _node(graph, genome=str(ROOT / "planners" / "ugv-paper-dual-s1.json"), **values)
    assert str(err.value).startswith(fault) or fault in str(err.value), str(err.value)
    assert "\n" not in str(err.value)
    assert isinstance(err.value, (PlannerSetupError, MentorError))
