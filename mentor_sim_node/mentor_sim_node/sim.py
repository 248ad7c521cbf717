"""The MENTOR simulator node: robots on the pymunk reference world, one decision per period.

Everything it computes is :class:`mentor_core.SimSession` (episodes, stepping, goals, events,
sim time, recording). This module only wires rclpy to it: parameters (:mod:`.params`, two of
them changeable at run time), publishers and subscriptions (:mod:`.topics`, the session's port;
messages from :mod:`.conversions`), one wall timer and the ``~/reset`` service. See
``docs/ros.md`` for the full contract.

Stepping ("lockstep", ``real_time_factor`` 0, the default): each driving robot's ``scan`` and
``odom`` go out, and the step follows as soon as each has answered with one ``cmd_vel``
(unanswered: published again every ``resend_period`` wall s; after ``answer_timeout`` > 0 the
robot holds still). With ``real_time_factor`` r > 0 the timer steps every ``dt / r`` wall s
with each robot's latest command (none: it holds still). With ``continuous`` the timer steps
the physics every ``physics_step / real_time_factor`` wall s (real time when the factor is 0)
with each robot's held velocity.

The world goes out once, latched, as markers on ``/mentor/obstacles`` and as an occupancy
grid on ``/map`` (:func:`mentor_core.source_map`).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from geometry_msgs.msg import PoseStamped, Twist
from nav_msgs.msg import OccupancyGrid as OccupancyGridMsg
from rcl_interfaces.msg import SetParametersResult
from rclpy.clock import Clock, ClockType
from rclpy.node import Node
from rclpy.parameter import Parameter
from std_srvs.srv import Trigger

from mentor_core import (
    EpisodeRecorder,
    OccupancyGrid,
    Outcome,
    SimSession,
    load_scenario_source,
    source_map,
)
from mentor_ros_common.messages import occupancy_grid_msg
from mentor_ros_common.node_main import run_node
from mentor_sim_node import conversions
from mentor_sim_node.params import SimSetupError, check_runtime, declare_parameters
from mentor_sim_node.topics import QOS_COMMAND, QOS_LATCHED, Topics, subscribe_goals

__all__ = ["NODE_NAME", "QOS_COMMAND", "QOS_LATCHED", "SimNode", "SimSetupError", "main"]

NODE_NAME = "mentor_sim"
MAP_TOPIC = "/map"
WARN_EVERY_S = 5.0
HOLD = (0.0, 0.0)


class SimNode(Node):
    """Simulates MENTOR robots on a pymunk world (module docstring; ``docs/ros.md``).

    Raises :class:`mentor_core.MentorError` (one line) for bad parameters, an unknown
    profile, a missing/corrupt/foreign world file or scenario bag, or scenarios none of
    which a robot can start from.
    """

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(NODE_NAME, **kwargs)
        try:
            self._setup()
        except BaseException:
            Node.destroy_node(self)
            raise

    def _setup(self) -> None:
        p = declare_parameters(self, NODE_NAME)
        cfg = p.session
        source = load_scenario_source(
            p.world, p.scenario_bag, cfg.robots[0][1], p.seed, map_yaml=p.map_yaml
        )
        self._topics = Topics(
            self, cfg.robots, cfg.wiring, self._command_callback, self._goal_callback
        )
        #: the episodes being run: everything the node computes
        self.session = session = SimSession(source, cfg, self._topics)
        self._goal_pose_subs = (
            subscribe_goals(self, p.goal_pose_topic, self._on_goal_pose, latched=False)
            if p.goal_pose_topic
            else []
        )
        self._reset_srv = self.create_service(Trigger, "~/reset", self._on_reset)
        self._wall = Clock(clock_type=ClockType.STEADY_TIME)
        self._timer = self.create_timer(self._period(cfg.real_time_factor), self._on_timer,
                                        clock=self._wall)
        self.add_on_set_parameters_callback(self._on_parameters)
        self._topics.markers_pub.publish(conversions.markers_from_world(session.world))
        try:
            grid = source_map(source, p.map_resolution)
        except ValueError as err:  # cells that would exhaust memory
            raise SimSetupError(f"map_resolution: {err}") from None
        self._publish_map(grid)
        self._topics.publish_description(session.time_ns)
        self._topics.clock(session.time_ns)
        rtf = cfg.real_time_factor
        self.get_logger().info(
            f"simulating {', '.join(f'{n} ({pr.name})' for n, pr in cfg.robots)} "
            f"on {source.origin}: {len(source.scenarios)} scenarios, "
            + ("continuous, " if session.continuous else "")
            + ("as fast as the planners answer" if rtf == 0.0 else f"{rtf}x real time")
        )

    def _publish_map(self, grid: OccupancyGrid) -> None:
        """The world as ``nav_msgs/OccupancyGrid`` on ``/map`` (latched), for planners' global
        plans and RViz."""
        self._map_pub = self.create_publisher(OccupancyGridMsg, MAP_TOPIC, QOS_LATCHED)
        self._map_pub.publish(occupancy_grid_msg(grid))

    def _period(self, real_time_factor: float) -> float:
        """Wall s between two timer ticks."""
        cfg = self.session.config
        if cfg.continuous is not None:
            return cfg.continuous.physics_step / (real_time_factor or 1.0)
        if real_time_factor > 0.0:
            return self.session.dt / real_time_factor
        return cfg.resend_period

    # ------------------------------------------------------------------ state, for callers

    @property
    def finished(self) -> bool:
        """All ``episodes`` have run (never with ``episodes`` 0)."""
        return self.session.finished

    @property
    def episodes_done(self) -> int:
        """Episodes that have ended."""
        return self.session.episodes_done

    @property
    def sim_time_ns(self) -> int:
        """Current simulation time, ns."""
        return self.session.time_ns

    @property
    def recorder(self) -> EpisodeRecorder | None:
        """What has been recorded (None without ``record``)."""
        return self.session.recorder

    @property
    def outcomes(self) -> list[Outcome]:
        """Every robot episode that has ended, in order."""
        return self.session.outcomes

    @property
    def rejections(self) -> list[str]:
        """Every scenario skipped and every robot that could not start, one line each."""
        return self.session.rejections

    # ------------------------------------------------------------------ callbacks

    def _command_callback(self, name: str) -> Callable[[Twist], None]:
        def callback(msg: Twist) -> None:
            self._on_command(name, msg)

        return callback

    def _on_command(self, name: str, msg: Twist) -> None:
        if not self.session.accepts(name):
            self.get_logger().debug(f"{name}/cmd_vel: no observation waits for it; dropped")
            return
        try:
            decision = conversions.twist_to_action(msg, self.session.dt)
        except ValueError as err:
            self.get_logger().warning(
                f"{name}/cmd_vel rejected: {err}; the robot holds still this period",
                throttle_duration_sec=WARN_EVERY_S,
            )
            self.session.command(name, HOLD)
        else:
            received = (float(msg.linear.x), float(msg.angular.z))
            self.session.command(name, decision, received)

    def _goal_callback(self, name: str) -> Callable[[PoseStamped], None]:
        def callback(msg: PoseStamped) -> None:
            if not self._topics.echo(name, msg):  # its own goal, coming back
                self._on_goal([name], msg)

        return callback

    def _on_goal_pose(self, msg: PoseStamped) -> None:
        self._on_goal([name for name, _ in self.session.config.robots], msg)

    def _on_goal(self, robots: list[str], msg: PoseStamped) -> None:
        """A goal for ``robots`` from a goal topic (its two subscriptions may both deliver
        it: the session takes a goal it already has as no change)."""
        try:
            frame, xy = conversions.goal_request(msg)
        except ValueError as err:
            self.get_logger().warning(f"goal refused: {err}")
            return
        self.session.give_goal(robots, frame, xy)

    def _on_parameters(self, params: list[Parameter]) -> SetParametersResult:
        """Run-time changes of ``real_time_factor`` and ``goal_radius`` (the rest is
        read-only: rclpy refuses those before this is called)."""
        for param in params:
            why = check_runtime(param.name, param.value, self.session.config)
            if why:
                return SetParametersResult(successful=False, reason=why)
        for param in params:
            value = float(param.value)
            if param.name == "goal_radius":
                self.session.goal_radius = value if value > 0.0 else None
            elif param.name == "real_time_factor":
                self._timer.cancel()
                self.destroy_timer(self._timer)
                self._timer = self.create_timer(self._period(value), self._on_timer,
                                                clock=self._wall)
            self.get_logger().info(f"{param.name} set to {value}")
        return SetParametersResult(successful=True)

    def _on_timer(self) -> None:
        tick = self.session.tick()
        late = ", ".join(tick.robots)
        if tick.action == "timeout":
            self.get_logger().warning(
                f"no cmd_vel from {late} within {self.session.config.answer_timeout} s; "
                "holding still this period",
                throttle_duration_sec=WARN_EVERY_S,
            )
            self.session.step()
        elif tick.action == "resend":
            self._topics.resend(tick.robots)
            if tick.waited > WARN_EVERY_S:
                self.get_logger().warning(
                    f"waiting {tick.waited:.0f} s for cmd_vel from {late}"
                    " (is its planner running, on sim time?)",
                    throttle_duration_sec=WARN_EVERY_S,
                )
        elif tick.action == "step":
            if tick.robots:
                self.get_logger().warning(
                    f"no cmd_vel from {late} this period; holding still",
                    throttle_duration_sec=WARN_EVERY_S,
                )
            self.session.step()

    def _on_reset(self, request: Trigger.Request, response: Trigger.Response) -> Trigger.Response:
        response.success, response.message = self.session.reset()
        return response

    # ------------------------------------------------------------------ recording

    def save_recording(self) -> None:
        """Write the episode bag now (once; ``record`` unset: nothing)."""
        self.session.save_recording()

    def destroy_node(self) -> None:
        """Write the recording (if any and not yet written), then destroy the node."""
        self.save_recording()
        super().destroy_node()


def main(args: list[str] | None = None) -> None:
    """Run the node until shutdown; a bad setup is one line on stderr and exit status 2."""
    run_node("mentor_sim", SimNode, args)
