"""The MENTOR simulator node: robots on the pymunk reference world, one decision per period.

Everything it computes is :class:`mentor_core.SimSession` (episodes, stepping, events, sim
time, recording). This module only wires rclpy to it: parameters (:mod:`.params`), publishers
and ``cmd_vel`` subscriptions (the session's port; messages from :mod:`.conversions`), one
wall timer and the ``~/reset`` service. See ``docs/ros.md`` for the full contract.

Stepping ("lockstep", ``real_time_factor`` 0, the default): each driving robot's ``scan`` and
``odom`` go out, and the step follows as soon as each has answered with one ``cmd_vel``
(unanswered: published again every ``resend_period`` wall s; after ``answer_timeout`` > 0 the
robot holds still). With ``real_time_factor`` r > 0 the timer steps every ``dt / r`` wall s
with each robot's latest command (none: it holds still).

The world goes out once, latched, as markers on ``/mentor/obstacles`` and as an occupancy
grid on ``/map`` (:func:`mentor_core.source_map`).
"""

from __future__ import annotations

import sys
from collections.abc import Callable, Sequence
from typing import Any

import rclpy
from geometry_msgs.msg import PoseStamped, Twist
from nav_msgs.msg import OccupancyGrid as OccupancyGridMsg
from nav_msgs.msg import Odometry
from numpy.typing import ArrayLike
from rclpy.clock import Clock, ClockType
from rclpy.exceptions import NameValidationException, ParameterException
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node
from rclpy.qos import (
    DurabilityPolicy,
    HistoryPolicy,
    QoSProfile,
    ReliabilityPolicy,
    qos_profile_sensor_data,
)
from rosgraph_msgs.msg import Clock as ClockMsg
from sensor_msgs.msg import LaserScan
from std_msgs.msg import String
from std_srvs.srv import Trigger
from visualization_msgs.msg import MarkerArray

from mentor_core import (
    EpisodeRecorder,
    EventKind,
    MentorError,
    OccupancyGrid,
    Outcome,
    RobotProfile,
    SimSession,
    load_scenario_source,
    source_map,
)
from mentor_sim_node import conversions
from mentor_sim_node.params import SimSetupError, declare_parameters

__all__ = ["NODE_NAME", "QOS_COMMAND", "QOS_LATCHED", "SimNode", "SimSetupError", "main"]

NODE_NAME = "mentor_sim"
OBSTACLES_TOPIC = "/mentor/obstacles"
MAP_TOPIC = "/map"
COMMAND_DEPTH = 10
EVENT_DEPTH = 10
LATCHED_DEPTH = 1
WARN_EVERY_S = 5.0
#: goals and obstacles: latched (transient local), reliable, the latest one
QOS_LATCHED = QoSProfile(
    history=HistoryPolicy.KEEP_LAST,
    depth=LATCHED_DEPTH,
    reliability=ReliabilityPolicy.RELIABLE,
    durability=DurabilityPolicy.TRANSIENT_LOCAL,
)
QOS_COMMAND = QoSProfile(depth=COMMAND_DEPTH, reliability=ReliabilityPolicy.RELIABLE)
QOS_EVENTS = QoSProfile(depth=EVENT_DEPTH, reliability=ReliabilityPolicy.RELIABLE)
QOS_CLOCK = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE)
HOLD = (0.0, 0.0)
Vec = Sequence[float]


class _Robot:
    """Publishers, subscription and the last observation of one robot namespace."""

    def __init__(
        self, node: Node, name: str, profile: RobotProfile, on_cmd: Callable[[Twist], None]
    ) -> None:
        self.profile = profile
        sensor = qos_profile_sensor_data
        self.scan_pub = node.create_publisher(LaserScan, f"{name}/scan", sensor)
        self.odom_pub = node.create_publisher(Odometry, f"{name}/odom", sensor)
        self.goal_pub = node.create_publisher(PoseStamped, f"{name}/goal", QOS_LATCHED)
        self.events_pub = node.create_publisher(String, f"{name}/events", QOS_EVENTS)
        self.cmd_sub = node.create_subscription(Twist, f"{name}/cmd_vel", on_cmd, QOS_COMMAND)
        self.last: tuple[LaserScan, Odometry] | None = None


class _Topics:
    """The node's publishers as the session's port (:class:`mentor_core.SessionPort`)."""

    def __init__(
        self,
        node: Node,
        robots: Sequence[tuple[str, RobotProfile]],
        on_command: Callable[[str], Callable[[Twist], None]],
    ) -> None:
        self._log = node.get_logger()
        self.clock_pub = node.create_publisher(ClockMsg, "/clock", QOS_CLOCK)
        self.markers_pub = node.create_publisher(MarkerArray, OBSTACLES_TOPIC, QOS_LATCHED)
        self.robots = {n: _Robot(node, n, p, on_command(n)) for n, p in robots}

    def clock(self, time_ns: int) -> None:
        self.clock_pub.publish(ClockMsg(clock=conversions.time_from_ns(time_ns)))

    def goal(self, robot: str, goal: Vec, time_ns: int) -> None:
        msg = conversions.pose_stamped_from_goal(goal, conversions.time_from_ns(time_ns))
        self.robots[robot].goal_pub.publish(msg)

    def event(
        self, robot: str, kind: EventKind, scenario: int, time_ns: int, goal: Vec | None
    ) -> None:
        msg = conversions.event_string(kind, scenario, time_ns, goal)
        self.robots[robot].events_pub.publish(msg)

    def observation(
        self, robot: str, ranges: ArrayLike, pose: Vec, twist: Vec, time_ns: int
    ) -> None:
        r = self.robots[robot]
        stamp = conversions.time_from_ns(time_ns)
        frame = f"{robot}/base_link"
        scan = conversions.laser_scan_from_ranges(ranges, r.profile, stamp, frame)
        odom = conversions.odometry_from_pose(pose, twist, stamp, robot)
        r.scan_pub.publish(scan)
        r.odom_pub.publish(odom)
        r.last = (scan, odom)

    def odometry(self, robot: str, pose: Vec, twist: Vec, time_ns: int) -> None:
        stamp = conversions.time_from_ns(time_ns)
        msg = conversions.odometry_from_pose(pose, twist, stamp, robot)
        self.robots[robot].odom_pub.publish(msg)

    def resend(self, robots: Sequence[str]) -> None:
        """Publish the last observation of ``robots`` again (same stamp)."""
        for name in robots:
            last = self.robots[name].last
            if last is not None:
                self.robots[name].scan_pub.publish(last[0])
                self.robots[name].odom_pub.publish(last[1])

    def info(self, text: str) -> None:
        self._log.info(text)

    def error(self, text: str) -> None:
        self._log.error(text)


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
        self._topics = _Topics(self, cfg.robots, self._command_callback)
        #: the episodes being run: everything the node computes
        self.session = session = SimSession(source, cfg, self._topics)
        self._reset_srv = self.create_service(Trigger, "~/reset", self._on_reset)
        wall = Clock(clock_type=ClockType.STEADY_TIME)
        rtf = cfg.real_time_factor
        period = session.dt / rtf if rtf > 0.0 else cfg.resend_period
        self._timer = self.create_timer(period, self._on_timer, clock=wall)
        self._topics.markers_pub.publish(conversions.markers_from_world(session.world))
        self._publish_map(source_map(source, p.map_resolution))
        self._topics.clock(session.time_ns)
        self.get_logger().info(
            f"simulating {', '.join(f'{n} ({pr.name})' for n, pr in cfg.robots)} "
            f"on {source.origin}: {len(source.scenarios)} scenarios, "
            + ("as fast as the planners answer" if rtf == 0.0 else f"{rtf}x real time")
        )

    def _publish_map(self, grid: OccupancyGrid) -> None:
        """The world as ``nav_msgs/OccupancyGrid`` on ``/map`` (latched), for planners' global
        plans and RViz."""
        self._map_pub = self.create_publisher(OccupancyGridMsg, MAP_TOPIC, QOS_LATCHED)
        self._map_pub.publish(conversions.occupancy_grid_from_grid(grid))

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
    rclpy.init(args=args)
    try:
        node = SimNode()
    except (MentorError, ValueError, ParameterException, NameValidationException) as err:
        print(f"mentor_sim: {' '.join(str(err).split())}", file=sys.stderr)
        rclpy.try_shutdown()
        sys.exit(2)
    try:
        rclpy.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        node.destroy_node()
        rclpy.try_shutdown()
