"""ROS arguments checked before rcl sees them (mentor_core.runtime.ros_arguments)."""

from __future__ import annotations

import json
import re

import pytest
import rclpy
from rclpy.context import Context
from rclpy.node import Node

from mentor_core.errors import MentorError
from mentor_core.runtime.ros_arguments import (
    launch_count,
    launch_flag,
    launch_number,
    parameter_fault,
)

pytestmark = pytest.mark.ros


@pytest.mark.parametrize(
    "argv",
    [
        ["sim", "--ros-args", "-p", "robots:=[a, b]", "-p", "seed:=3", "-p", "world:=w.yaml"],
        ["sim", "-p", "record_metadata:={}"],  # not a ROS argument: not this check's business
        ["sim", "--ros-args", "-r", "__ns:=/x", "--param", 'record_metadata:="{}"'],
    ],
)
def test_good_rules_pass(argv: list[str]) -> None:
    assert parameter_fault(argv) == ""


def test_a_mapping_is_refused_with_a_hint_that_works() -> None:
    fault = parameter_fault(
        ["sim", "--ros-args", "-p", 'record_metadata:={"who": "review"}']
    )
    assert fault.startswith('-p record_metadata: {"who": "review"} is a YAML mapping')
    assert "\n" not in fault
    hint = re.search(r"-p '(.*)'$", fault)
    assert hint is not None
    context = Context()
    rclpy.init(args=["sim", "--ros-args", "-p", hint.group(1)], context=context)
    try:
        node = Node("sim", context=context, automatically_declare_parameters_from_overrides=True)
        assert json.loads(node.get_parameter("record_metadata").value) == {"who": "review"}
        node.destroy_node()
    finally:
        rclpy.try_shutdown(context=context)
    assert "nested list" in parameter_fault(["x", "--ros-args", "-p", "a:=[[1], [2]]"])
    assert "is not YAML" in parameter_fault(["x", "--ros-args", "-p", "a:=[1"])


@pytest.mark.parametrize("text, flag", [("true", True), (" True", True), ("1", True),
                                        ("yes", True), ("FALSE", False), ("0", False),
                                        ("no", False)])  # fmt: skip
def test_a_launch_flag_reads_as_ros_launch_conditions_do(text: str, flag: bool) -> None:
    assert launch_flag("rviz", text) is flag


@pytest.mark.parametrize("text", ["ture", "", "2", "on"])
def test_a_mistyped_launch_flag_is_one_line_naming_it(text: str) -> None:
    """Before, anything but true/1/yes read as false: ``collision_guard:=ture`` (a launch
    argument then) ran unguarded, ``continuous:=ture`` runs in lockstep."""
    with pytest.raises(MentorError, match=f"continuous:={text}: expected true or false"):
        launch_flag("continuous", text)


def test_launch_numbers_and_counts_are_refused_in_one_line_naming_them() -> None:
    assert launch_number("real_time_factor", "0.75") == 0.75
    assert launch_count("lidar_rays", "360") == 360
    for text in ("fast", "nan", "inf", ""):
        with pytest.raises(MentorError, match=f"real_time_factor:={text}: expected a number"):
            launch_number("real_time_factor", text)
    for text in ("-1", "3.5", "many"):
        with pytest.raises(MentorError, match=f"lidar_rays:={text}: expected a whole number"):
            launch_count("lidar_rays", text)
