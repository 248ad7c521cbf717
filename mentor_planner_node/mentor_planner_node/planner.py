"""The MENTOR planner node: an evolved genome as a path planner for one robot.

It subscribes ``scan``, ``odom``, ``goal`` (and ``events``) in its namespace and answers every
new observation (a scan and an odometry with the same stamp) with one ``cmd_vel``: once per
control period. The decision is :class:`mentor_core.GenomePlanner`, the trainer's own input
and output functions; when to decide and when data is stale is
:class:`mentor_core.DecisionGate`. A watchdog on the node's clock (sim time under
``use_sim_time``) sends a zero Twist with a throttled warning when no observation could be
answered for ``stale_timeout`` s. A corrupt genome or an unknown profile is one line on stderr
and exit status 2. With ``global_plan`` the network steers along a path given on ``plan`` or
planned on the map (:mod:`.global_plan`).
"""

from __future__ import annotations

import sys
from typing import Any

import rclpy
from geometry_msgs.msg import PoseStamped, Twist
from nav_msgs.msg import Odometry
from rcl_interfaces.msg import FloatingPointRange, ParameterDescriptor
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
from sensor_msgs.msg import LaserScan
from std_msgs.msg import String

from mentor_core import DecisionGate, GenomePlanner, MentorError, get_profile
from mentor_planner_node import conversions, global_plan

NODE_NAME = "mentor_planner"
COMMAND_DEPTH = 10
EVENT_DEPTH = 10
LATCHED_DEPTH = 1
WARN_EVERY_S = 5.0
#: periods without an answer before the watchdog fires, when ``stale_timeout`` is 0
STALE_PERIODS = 3.0
QOS_LATCHED = QoSProfile(
    history=HistoryPolicy.KEEP_LAST,
    depth=LATCHED_DEPTH,
    reliability=ReliabilityPolicy.RELIABLE,
    durability=DurabilityPolicy.TRANSIENT_LOCAL,
)
QOS_COMMAND = QoSProfile(depth=COMMAND_DEPTH, reliability=ReliabilityPolicy.RELIABLE)
QOS_EVENTS = QoSProfile(depth=EVENT_DEPTH, reliability=ReliabilityPolicy.RELIABLE)


class PlannerSetupError(MentorError):
    """A parameter of the planner node is invalid (one line)."""


def _descriptor(text: str, low: float | None = None) -> ParameterDescriptor:
    extra: dict[str, Any] = {}
    if low is not None:
        bounds = FloatingPointRange(from_value=low, to_value=1e9, step=0.0)
        extra["floating_point_range"] = [bounds]
    return ParameterDescriptor(description=text, read_only=True, **extra)


class PlannerNode(Node):
    """Runs an evolved genome as a path planner (module docstring; ``docs/ros.md``).

    Raises :class:`mentor_core.MentorError` (one line) for a corrupt or missing genome
    file, an unknown profile, a genome that does not fit the profile, or bad parameters.
    """

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(NODE_NAME, **kwargs)
        try:
            self._setup()
        except BaseException:
            Node.destroy_node(self)
            raise

    def _setup(self) -> None:
        declared = self.declare_parameters(
            "",
            [
                ("genome", "", _descriptor("genome JSON file ('' : answer zero Twists)")),
                ("profile", "ugv", _descriptor("robot profile (robots.yaml)")),
                (
                    "control_period",
                    0.0,
                    _descriptor("s per decision (0: the profile's)", low=0.0),
                ),
                (
                    "stale_timeout",
                    0.0,
                    _descriptor(
                        "s without an answered observation before a zero Twist "
                        f"(0: {STALE_PERIODS:g} control periods)",
                        low=0.0,
                    ),
                ),
                (
                    "sync_tolerance",
                    0.05,
                    _descriptor("s, largest stamp gap of a scan and the odometry used", low=0.0),
                ),
            ],
        )
        values = {p.name: p.value for p in declared}
        self.profile = get_profile(str(values["profile"]))
        period = float(values["control_period"])
        self.control_period = period if period > 0.0 else self.profile.control_period
        stale = float(values["stale_timeout"])
        stale = stale if stale > 0.0 else STALE_PERIODS * self.control_period
        if stale <= self.control_period:
            raise PlannerSetupError(
                f"stale_timeout: {stale} s must exceed the control period {self.control_period} s"
            )
        genome = str(values["genome"])
        self.planner = GenomePlanner.load(genome, self.profile.name) if genome else None
        self.gate = DecisionGate(stale, float(values["sync_tolerance"]))
        #: the global plan (parameter global_plan), None without
        self.global_plan = global_plan.attach(self, self.planner, self._answer)
        self.decisions = 0
        self.zero_commands = 0

        self._cmd_pub = self.create_publisher(Twist, "cmd_vel", QOS_COMMAND)
        # events and goals first: the executor serves ready subscriptions in creation order,
        # so an episode's end and the next start are handled before its observations
        self._events_sub = self.create_subscription(String, "events", self._on_event, QOS_EVENTS)
        self._goal_sub = self.create_subscription(PoseStamped, "goal", self._on_goal, QOS_LATCHED)
        sensor = qos_profile_sensor_data
        self._scan_sub = self.create_subscription(LaserScan, "scan", self._on_scan, sensor)
        self._odom_sub = self.create_subscription(Odometry, "odom", self._on_odom, sensor)
        self._watchdog = self.create_timer(self.control_period, self._on_watchdog)
        if self.planner is None:
            self.get_logger().warning(
                "no genome given (parameter 'genome'): every answer is a zero Twist"
            )
        else:
            g = self.planner.genome
            self.get_logger().info(
                f"planning for {self.profile.name!r} with {genome} "
                f"({len(g.nodes)} nodes, {len(g.enabled_connections)} enabled connections)"
            )

    def _now_ns(self) -> int:
        return int(self.get_clock().now().nanoseconds)

    def _on_scan(self, msg: LaserScan) -> None:
        try:
            ranges = conversions.ranges_from_scan(msg, self.profile)
        except ValueError as err:
            self.get_logger().warning(
                f"scan rejected: {err}", throttle_duration_sec=WARN_EVERY_S
            )
            return
        self.gate.on_scan(conversions.ns_from_stamp(msg.header.stamp), ranges)
        self._answer()

    def _on_odom(self, msg: Odometry) -> None:
        try:
            pose = conversions.pose_from_odometry(msg)
        except ValueError as err:
            self.get_logger().warning(
                f"odometry rejected: {err}", throttle_duration_sec=WARN_EVERY_S
            )
            return
        self.gate.on_odometry(conversions.ns_from_stamp(msg.header.stamp), pose)
        self._answer()

    def _on_goal(self, msg: PoseStamped) -> None:
        try:
            goal = conversions.goal_from_pose_stamped(msg)
        except ValueError as err:
            self.get_logger().warning(f"goal rejected: {err}")
            return
        self.gate.on_goal(goal)
        self._answer()

    def _on_event(self, msg: String) -> None:
        try:
            kind, goal = conversions.event_from_string(msg)
        except ValueError as err:
            self.get_logger().warning(
                f"event rejected: {err}", throttle_duration_sec=WARN_EVERY_S
            )
            return
        self.gate.on_event(kind, self._now_ns(), goal)
        self._answer()

    def _answer(self) -> None:
        if self.global_plan is not None and not self.global_plan.ready:
            return  # nothing to follow yet: the observation waits for a map or a path
        obs = self.gate.take(self._now_ns())
        if obs is None or obs.goal is None:
            return
        if self.planner is None:
            self._send_zero("no genome loaded")
            return
        try:
            decide = self.planner.decide if self.global_plan is None else self.global_plan.decide
            dtheta, ds = decide(obs.ranges, obs.pose, obs.goal)
            twist = conversions.twist_from_action(dtheta, ds, self.control_period)
        except ValueError as err:
            self._send_zero(f"no decision ({err})")
            return
        self._cmd_pub.publish(twist)
        self.decisions += 1

    def _on_watchdog(self) -> None:
        reason = self.gate.watchdog(self._now_ns())
        if reason is not None and self.global_plan is not None and not self.global_plan.ready:
            reason = "no map or path to follow yet (global_plan)"
        if reason is not None:
            self._send_zero(reason)

    def _send_zero(self, reason: str) -> None:
        self._cmd_pub.publish(Twist())
        self.zero_commands += 1
        self.get_logger().warning(
            f"{reason}: sending a zero Twist", throttle_duration_sec=WARN_EVERY_S
        )


def main(args: list[str] | None = None) -> None:
    """Run the node until shutdown; a bad setup is one line on stderr and exit status 2."""
    rclpy.init(args=args)
    try:
        node = PlannerNode()
    except (MentorError, ValueError, ParameterException, NameValidationException) as err:
        print(f"mentor_planner: {' '.join(str(err).split())}", file=sys.stderr)
        rclpy.try_shutdown()
        sys.exit(2)
    try:
        rclpy.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        node.destroy_node()
        rclpy.try_shutdown()
