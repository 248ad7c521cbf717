"""The planner node's ``navigate_to_pose`` action (Nav2's ``NavigateToPose``): a goal reached
succeeds with feedback on the way, a canceled one stops the robot, one out of time or that
cannot be taken is aborted with the reason (issue 56, point 3). ``nav2_msgs`` has no wheel:
``scripts/bootstrap.sh`` generates it where a compiler is (``interfaces/README.md``)."""

from __future__ import annotations

from typing import Any

import pytest
from action_msgs.msg import GoalStatus
from ros_support import Graph
from scripted_support import Burger, goal_msg

pytestmark = pytest.mark.ros
nav2_msgs = pytest.importorskip(
    "nav2_msgs.action",
    reason="nav2_msgs was not generated (no C compiler at bootstrap: interfaces/README.md)",
)
NavigateToPose = nav2_msgs.NavigateToPose


class Client:
    """An action client of ``navigate_to_pose`` beside the Burger."""

    def __init__(self, graph: Graph, burger: Burger) -> None:
        from rclpy.action import ActionClient

        self.burger = burger
        self.node = graph.probe("navigator")
        self.client = ActionClient(self.node, NavigateToPose, "navigate_to_pose")
        self.feedback: list[Any] = []
        assert self._until(lambda: self.client.server_is_ready(), 10.0)

    def _until(self, done: Any, sim_s: float) -> bool:
        end = self.burger.sim.time + sim_s
        while not done():
            if self.burger.sim.time > end:
                return False
            self.burger.run(self.burger.sim.spec.tick)
        return True

    def send(self, xy: tuple[float, float], frame: str = "odom") -> Any:
        goal = NavigateToPose.Goal(pose=goal_msg(xy, frame))
        sent = self.client.send_goal_async(goal, feedback_callback=self.feedback.append)
        assert self._until(sent.done, 5.0)
        handle = sent.result()
        assert handle.accepted
        return handle

    def result(self, handle: Any, sim_s: float = 90.0) -> Any:
        done = handle.get_result_async()
        assert self._until(done.done, sim_s), "no result"
        return done.result()


def test_a_goal_reached_succeeds_with_feedback_on_the_way(graph: Graph) -> None:
    burger = Burger(graph, (3.0, 2.5, 1.0))
    client = Client(graph, burger)
    out = client.result(client.send((5.0, 4.5)))
    assert out.status == GoalStatus.STATUS_SUCCEEDED
    assert out.result.error_code == 0 and burger.sim.collisions == 0
    distances = [f.feedback.distance_remaining for f in client.feedback]
    assert len(distances) > 5 and distances[0] > 2.5 and distances[-1] < 1.0
    assert client.feedback[-1].feedback.current_pose.header.frame_id == "odom"
    assert burger.statuses[-1] == "reached"


def test_a_canceled_goal_stops_the_robot(graph: Graph) -> None:
    burger = Burger(graph, (3.0, 2.5, 1.0))
    client = Client(graph, burger)
    handle = client.send((7.0, 5.5))
    assert client._until(lambda: burger.sim.velocity[0] > 0.1, 20.0)
    canceling = handle.cancel_goal_async()
    assert client._until(canceling.done, 5.0)
    out = client.result(handle, 5.0)
    assert out.status == GoalStatus.STATUS_CANCELED
    burger.run(1.0)
    assert burger.sim.velocity == (0.0, 0.0)


def test_a_goal_out_of_time_or_in_an_unknown_frame_is_aborted_with_the_reason(
    graph: Graph,
) -> None:
    burger = Burger(graph, (3.0, 2.5, 1.0), time_limit=3.0)
    client = Client(graph, burger)
    out = client.result(client.send((7.0, 5.5)), 10.0)
    assert out.status == GoalStatus.STATUS_ABORTED
    assert out.result.error_msg.startswith("out of time") and out.result.error_code != 0
    burger.run(1.0)
    assert burger.sim.velocity == (0.0, 0.0)
    out = client.result(client.send((7.0, 5.5), frame="nowhere"), 10.0)
    assert out.status == GoalStatus.STATUS_ABORTED
    assert "nowhere" in out.result.error_msg and "waited" in out.result.error_msg


def test_a_new_goal_preempts_the_one_driven_to(graph: Graph) -> None:
    burger = Burger(graph, (3.0, 2.5, 1.0))
    client = Client(graph, burger)
    first = client.send((7.0, 5.5))
    burger.run(2.0)
    second = client.send((3.0, 4.0))
    out = client.result(first, 5.0)
    assert out.status == GoalStatus.STATUS_ABORTED and "new goal" in out.result.error_msg
    assert client.result(second).status == GoalStatus.STATUS_SUCCEEDED
