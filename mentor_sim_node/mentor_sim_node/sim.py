"""The MENTOR simulator node (skeleton; behaviour comes with issue 6)."""

from __future__ import annotations

import rclpy
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node


class SimNode(Node):
    """Simulates MENTOR robots on a pymunk world."""

    def __init__(self) -> None:
        super().__init__("mentor_sim")


def main(args: list[str] | None = None) -> None:
    """Run the node until shutdown."""
    rclpy.init(args=args)
    node = SimNode()
    try:
        rclpy.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        node.destroy_node()
        rclpy.try_shutdown()
