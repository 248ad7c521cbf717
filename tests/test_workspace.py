"""The colcon workspace ros2_ws/ provides both executables where ``ros2 run`` looks for them.

``ros2 run <pkg> <exe>`` finds ``<pkg>``'s prefix in the ament index (``AMENT_PREFIX_PATH``,
set by sourcing ``install/setup.bash``) and runs ``<prefix>/lib/<pkg>/<exe>``. These tests do
the same lookup with ``ament_index_python`` and start the planner that way. The workspace is
built by ``scripts/bootstrap.sh``.
"""

from __future__ import annotations

import os
import signal
import subprocess
import time
import uuid
from pathlib import Path

import pytest
from ament_index_python.packages import get_package_prefix
from ros_support import workspace_env

ROOT = Path(__file__).resolve().parents[1]
INSTALL = ROOT / "ros2_ws" / "install"
EXECUTABLES = {"mentor_planner_node": "planner", "mentor_sim_node": "sim"}
UP_TIMEOUT_S = 15.0
EXIT_TIMEOUT_S = 10.0


@pytest.fixture(scope="module")
def ws_env() -> dict[str, str]:
    """The environment after ``source ros2_ws/install/local_setup.bash`` (plus ROS isolation)."""
    if not (INSTALL / "local_setup.bash").is_file():
        pytest.fail("ros2_ws/install is missing: run `bash scripts/bootstrap.sh` first")
    return workspace_env()


def resolve(pkg: str, exe: str, env: dict[str, str], monkeypatch: pytest.MonkeyPatch) -> Path:
    """``ros2 run``'s lookup: ament index prefix of ``pkg`` + ``lib/<pkg>/<exe>``."""
    monkeypatch.setenv("AMENT_PREFIX_PATH", env["AMENT_PREFIX_PATH"])
    return Path(get_package_prefix(pkg)) / "lib" / pkg / exe


@pytest.mark.parametrize(("pkg", "exe"), sorted(EXECUTABLES.items()))
def test_executables_resolve_like_ros2_run(
    pkg: str, exe: str, ws_env: dict[str, str], monkeypatch: pytest.MonkeyPatch
) -> None:
    prefixes = ws_env["AMENT_PREFIX_PATH"].split(os.pathsep)
    assert str(INSTALL / pkg) in prefixes
    path = resolve(pkg, exe, ws_env, monkeypatch)
    assert path == INSTALL / pkg / "lib" / pkg / exe
    assert path.is_file() and os.access(path, os.X_OK)
    assert (INSTALL / pkg / "share" / pkg / "package.xml").is_file()


@pytest.mark.ros
def test_planner_starts_joins_the_graph_and_stops_on_sigint(
    ws_env: dict[str, str], monkeypatch: pytest.MonkeyPatch
) -> None:
    import rclpy
    from rcl_interfaces.srv import ListParameters
    from rclpy.context import Context
    from rclpy.executors import SingleThreadedExecutor

    exe = resolve("mentor_planner_node", "planner", ws_env, monkeypatch)
    # a namespace of our own: other processes on this machine may run planners too
    namespace = f"/ws_test_{os.getpid()}_{uuid.uuid4().hex[:8]}"
    proc = subprocess.Popen(
        [str(exe), "--ros-args", "-r", f"__ns:={namespace}"],
        env=ws_env,
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
    )
    ctx = Context()
    rclpy.init(context=ctx)
    try:
        # "up" = spinning: its parameter service answers (rclpy creates it for every node)
        probe = rclpy.create_node("mentor_workspace_probe", context=ctx)
        executor = SingleThreadedExecutor(context=ctx)
        executor.add_node(probe)
        client = probe.create_client(ListParameters, f"{namespace}/mentor_planner/list_parameters")
        deadline = time.monotonic() + UP_TIMEOUT_S
        answered = False
        while not answered and time.monotonic() < deadline and proc.poll() is None:
            if client.wait_for_service(timeout_sec=0.2):
                future = client.call_async(ListParameters.Request())
                executor.spin_until_future_complete(future, timeout_sec=2.0)
                answered = future.done() and future.result() is not None
        assert proc.poll() is None, proc.communicate()[0].decode(errors="replace")
        assert answered, "the planner never answered on its parameter service"
        # the node list comes from discovery, which may lag the service answer a little
        listed = False
        while not listed and time.monotonic() < deadline:
            listed = ("mentor_planner", namespace) in probe.get_node_names_and_namespaces()
            if not listed:
                executor.spin_once(timeout_sec=0.1)
        assert listed, "the planner answered but never showed in the ROS graph"
        executor.shutdown()
        probe.destroy_node()
        proc.send_signal(signal.SIGINT)
        rc = proc.wait(timeout=EXIT_TIMEOUT_S)
        output = proc.communicate()[0].decode(errors="replace")
        assert rc == 0, output
        assert "Traceback" not in output
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
        rclpy.try_shutdown(context=ctx)
