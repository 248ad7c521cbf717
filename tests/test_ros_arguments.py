"""ROS arguments checked before rcl sees them (mentor_core.runtime.ros_arguments)."""

from __future__ import annotations

import json
import re

import pytest
import rclpy
from rclpy.context import Context
from rclpy.node import Node

from mentor_core.runtime.ros_arguments import parameter_fault

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
