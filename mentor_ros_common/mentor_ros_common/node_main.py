"""The ``main`` of both MENTOR nodes: the ROS arguments checked, the node made, then spun until
shutdown. A bad setup (ROS arguments, parameters, files) is one line on stderr, ``<name>:
<fault>``, and exit status 2, as ``ros2 run`` users expect of a node that cannot start."""

from __future__ import annotations

import sys
from collections.abc import Callable
from typing import NoReturn

import rclpy
from rclpy.exceptions import NameValidationException, ParameterException
from rclpy.executors import ExternalShutdownException
from rclpy.impl.implementation_singleton import rclpy_implementation
from rclpy.node import Node

from mentor_core import MentorError, parameter_fault


def _fail(name: str, text: str) -> NoReturn:
    print(f"{name}: {text}", file=sys.stderr)
    sys.exit(2)


def run_node(name: str, make_node: Callable[[], Node], args: list[str] | None = None) -> None:
    """Run the node ``make_node()`` (logging as ``name``) until shutdown (module docstring);
    ``args``: the command line, ``sys.argv`` when None."""
    fault = parameter_fault(sys.argv if args is None else args)
    if fault:
        _fail(name, f"bad ROS arguments: {fault}")
    try:
        rclpy.init(args=args)
    except rclpy_implementation.RCLError as err:  # other arguments rcl cannot parse
        _fail(name, f"bad ROS arguments: {' '.join(str(err).split()).split(', at /')[0]}")
    try:
        node = make_node()
    except (MentorError, ValueError, ParameterException, NameValidationException) as err:
        rclpy.try_shutdown()
        _fail(name, " ".join(str(err).split()))
    try:
        rclpy.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        node.destroy_node()
        rclpy.try_shutdown()
