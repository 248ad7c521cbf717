"""Helpers of the ROS tests: one rclpy context per test, its executor, and teardown.

Every node a test makes is added to a :class:`Graph`, which spins them on one
``SingleThreadedExecutor`` of its own context and destroys all of them (and shuts the context
down) in teardown, also when the test fails. Discovery stays on this machine, in this
worker's domain (``tests/conftest.py``).
"""

from __future__ import annotations

import os
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
INSTALL = ROOT / "ros2_ws" / "install"
REGRESSION = ROOT / "bags" / "regression"
for _pkg in ("mentor_sim_node", "mentor_planner_node", "mentor_ros_common", "mentor_bringup"):
    if str(ROOT / _pkg) not in sys.path:
        sys.path.insert(0, str(ROOT / _pkg))

import rclpy  # noqa: E402
from rclpy.context import Context  # noqa: E402
from rclpy.executors import SingleThreadedExecutor  # noqa: E402
from rclpy.node import Node  # noqa: E402
from rclpy.parameter import Parameter  # noqa: E402

#: wall-clock limit of any wait in the ROS tests, s
WAIT_S = 20.0


def params(**values: Any) -> list[Parameter]:
    """``parameter_overrides`` from keyword arguments."""
    return [Parameter(name, value=value) for name, value in values.items()]


class Graph:
    """A private rclpy context with an executor; owns every node added to it."""

    def __init__(self) -> None:
        self.context = Context()
        rclpy.init(context=self.context)
        self.executor = SingleThreadedExecutor(context=self.context)
        self.nodes: list[Node] = []

    def add(self, node: Any) -> Any:
        """Spin ``node`` with the others (and destroy it in :meth:`close`)."""
        self.nodes.append(node)
        self.executor.add_node(node)
        return node

    def probe(self, name: str = "probe") -> Node:
        """A plain node for the test's own publishers and subscriptions."""
        return self.add(rclpy.create_node(name, context=self.context))

    def spin_until(self, done: Callable[[], bool], timeout: float = WAIT_S) -> bool:
        """Spin until ``done()`` (called once per round) is true or ``timeout`` wall seconds
        have passed; returns whether it became true."""
        deadline = time.monotonic() + timeout
        while not done():
            if time.monotonic() > deadline:
                return False
            self.executor.spin_once(timeout_sec=0.02)
        return True

    def spin_for(self, seconds: float) -> None:
        """Spin for ``seconds`` wall seconds."""
        deadline = time.monotonic() + seconds
        while time.monotonic() < deadline:
            self.executor.spin_once(timeout_sec=0.02)

    def close(self) -> None:
        """Destroy every node, stop the executor, shut the context down."""
        for node in reversed(self.nodes):
            self.executor.remove_node(node)
            node.destroy_node()
        self.nodes.clear()
        self.executor.shutdown()
        rclpy.try_shutdown(context=self.context)


def workspace_env() -> dict[str, str]:
    """The environment after ``source ros2_ws/install/local_setup.bash`` (ROS isolation kept)."""
    out = subprocess.run(
        ["bash", "-c", f"source '{INSTALL}/local_setup.bash' && env -0"],
        capture_output=True,
        check=True,
        env=dict(os.environ),
        timeout=60,
    )
    env = dict(item.split("=", 1) for item in out.stdout.decode().split("\0") if "=" in item)
    env["ROS_AUTOMATIC_DISCOVERY_RANGE"] = "LOCALHOST"
    env["ROS_DOMAIN_ID"] = os.environ["ROS_DOMAIN_ID"]
    return env


def run_executable(pkg: str, exe: str, args: list[str], timeout: float = 30.0) -> tuple[int, str]:
    """Run an installed node executable as ``ros2 run`` would; ``(returncode, stderr)``."""
    if not (INSTALL / "local_setup.bash").is_file():
        raise RuntimeError("ros2_ws/install is missing: run `bash scripts/bootstrap.sh` first")
    path = INSTALL / pkg / "lib" / pkg / exe
    proc = subprocess.run(
        [str(path), *args],
        env=workspace_env(),
        capture_output=True,
        timeout=timeout,
    )
    return proc.returncode, proc.stderr.decode(errors="replace")
