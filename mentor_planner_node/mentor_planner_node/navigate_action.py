"""The planner node's ``navigate_to_pose`` action server: Nav2's ``NavigateToPose``, beside the
plain goal topics.

A goal is the node's own goal (:meth:`PlannerNode.request_goal`): refused goals (outside the
map, in an obstacle, a frame TF cannot link) are aborted with the reason in ``error_msg``;
while it is driven, feedback after each decision gives the pose, the distance remaining and
the time spent; it ends ``SUCCEEDED`` when reached, ``ABORTED`` when the progress checker, the
time limit or the map gives it up (or a new goal preempts it), ``CANCELED`` on a cancel
request. ``error_code`` is 0 (``NONE``) on success, else :data:`ERROR_CODE` (Jazzy's message
defines only ``NONE``; later Nav2 releases name 9000 ``UNKNOWN``); ``behavior_tree`` is
ignored. The server exists where ``nav2_msgs`` imports (a full install, or generated in the
workspace: ``interfaces/README.md``).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from rclpy.action import ActionServer, CancelResponse, GoalResponse
from rclpy.task import Future

from mentor_planner_node import conversions

if TYPE_CHECKING:
    from mentor_planner_node.planner import PlannerNode

try:  # a full install, or generated in the workspace (interfaces/README.md)
    from nav2_msgs.action import NavigateToPose
except ImportError:  # pragma: no cover - depends on the installation
    NavigateToPose = None

ACTION = "navigate_to_pose"
#: error_code of a goal that did not succeed (Nav2 Kilted's NavigateToPose.UNKNOWN)
ERROR_CODE = 9000
_NS_PER_S = 1_000_000_000


class NavigateServer:
    """``navigate_to_pose`` for ``node`` (module docstring)."""

    def __init__(self, node: PlannerNode) -> None:
        self._node = node
        self._active: tuple[Any, Future] | None = None  # goal handle, its end
        self._requesting = False  # the node takes this server's new goal
        self._waiting = False  # this server's goal waits for TF
        self._started_ns = 0
        node.on_goal_end = self._on_end
        node.on_decision = self._feedback
        self._server = ActionServer(
            node, NavigateToPose, ACTION, execute_callback=self._execute,
            goal_callback=lambda _: GoalResponse.ACCEPT,
            cancel_callback=self._on_cancel,
        )  # fmt: skip

    def destroy(self) -> None:
        """Take the server down (with its node)."""
        self._server.destroy()

    def _on_cancel(self, handle: Any) -> CancelResponse:
        if self._active is not None and self._active[0] is handle:
            self._node.cancel_goal()
        return CancelResponse.ACCEPT

    def _on_end(self, outcome: str, text: str) -> None:
        if self._requesting and outcome == "preempted":
            return  # the goal it preempts is ended already (by this server's new goal)
        if outcome == "refused" and not self._waiting:
            return  # a goal of the goal topic that waited for TF
        self._waiting = False
        if self._active is not None and not self._active[1].done():
            self._active[1].set_result((outcome, text))

    def _feedback(self, pose: Any, distance: float) -> None:
        if self._active is None:
            return
        handle, _ = self._active
        msg = NavigateToPose.Feedback()
        now = self._node.get_clock().now()
        msg.current_pose = conversions.pose_stamped(pose, self._node.frames.odom_frame,
                                                    now.to_msg())  # fmt: skip
        elapsed = now.nanoseconds - self._started_ns
        msg.navigation_time.sec, msg.navigation_time.nanosec = divmod(max(elapsed, 0),
                                                                      _NS_PER_S)  # fmt: skip
        msg.distance_remaining = float(distance)
        handle.publish_feedback(msg)

    async def _execute(self, handle: Any) -> Any:
        """Drive to the goal until it ends; its result."""
        if self._active is not None:  # a new goal preempts the one driven to
            self._on_end("preempted", "a new goal came")
        ended: Future = Future()
        self._active = (handle, ended)
        self._started_ns = self._node.get_clock().now().nanoseconds
        try:
            frame, xy, yaw = conversions.goal_request(handle.request.pose)
            self._requesting = True
            why = self._node.request_goal(frame, xy, yaw, renew=True)
        except ValueError as err:
            why = f"goal refused: {err}"
        finally:
            self._requesting = False
        self._waiting = not why and self._node.goal_waits
        if why:
            self._on_end("aborted", why)
        outcome, text = await ended
        if self._active is not None and self._active[0] is handle:
            self._active = None
        result = NavigateToPose.Result()
        if outcome == "reached":
            handle.succeed()
            return result
        result.error_code, result.error_msg = ERROR_CODE, text
        if outcome == "canceled":
            handle.canceled()
        else:
            handle.abort()
        return result


def attach(node: PlannerNode) -> NavigateServer | None:
    """The action server where ``nav2_msgs`` is installed, else None."""
    return None if NavigateToPose is None else NavigateServer(node)
