"""The MENTOR planner node (skeleton; behaviour comes with issue 6)."""

from __future__ import annotations

import rclpy
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node


class PlannerNode(Node):
    """Runs an evolved genome as a path planner."""

    def __init__(self) -> None:
        super().__init__("mentor_planner")


def main(args: list[str] | None = None) -> None:
    """Run the node until shutdown."""
    rclpy.init(args=args)
    node = PlannerNode()
    try:
        rclpy.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        node.destroy_node()
        rclpy.try_shutdown()
