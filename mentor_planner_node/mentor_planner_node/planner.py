"""The MENTOR planner node: an evolved genome as a path planner for one robot.

It subscribes ``scan``, ``odom``, goals (``goal``, latched or not, and ``/goal_pose``, where
RViz's and Foxglove's goal tools and any plain publisher reach it) and ``events`` in its
namespace, and the arena (``/mentor/obstacles``), and publishes
``cmd_vel``. A scan may be the simulator's per-sensor scan or any 2-D lidar's
(:func:`mentor_core.readings_from_scan`, the lidar's mount from TF where ``tf2_ros`` is
installed, else the ``lidar_mount`` parameter); goals may come in any frame it can link to its
odometry frame (:class:`mentor_core.PlannerFrames`), and one outside the arena is refused.

It answers every new scan, with the pose at the scan's stamp from the odometry before and
after it (:class:`mentor_core.DecisionGate`), with one ``cmd_vel`` (lockstep), or decides every
control period with the latest one (``decide_on_timer``, for a simulator or robot that runs
continuously), sending its latest ``cmd_vel`` again at ``repeat_rate`` in between, as bases that
stop on a quiet ``cmd_vel`` need, but a zero Twist at once when the scans or the odometry have
stopped coming (each judged by its own pace). A scan it cannot read (invalid ranges where a
sensor would read nothing, or too few valid ranges: unknown, never free) or an odometry that
is not finite stops the robot at once, with a line saying why. The decision is
:class:`mentor_core.GenomePlanner`, the trainer's own input and output functions; when to
decide, when the goal is reached and when data is stale is :class:`mentor_core.DecisionGate`;
a planner with a memory is reset at the first observation of each new goal or episode.
A watchdog on the steady clock sends a zero Twist with a throttled warning when no observation
could be answered for ``stale_timeout`` wall s, also when sim time stops. A corrupt genome or
an unknown profile is one line on stderr and exit status 2.
The genome runs as its ``deployment`` (``none``: as trained, ``shipped``: as the shipped
planners, or a file; ``deployment_set`` changes keys of it), through the same decision chain as
``mentor-bench --deployment`` (:mod:`mentor_core.controller`): a collision guard may answer
with a step back (``linear.x < 0``). With ``global_plan`` the network steers along a path
given on ``plan`` or planned on the map, with a deployment's ``scan_map`` along a plan on a
map of its own scans, which it publishes on ``scan_map`` (:mod:`.global_plan`).
"""

from __future__ import annotations

from typing import Any

from geometry_msgs.msg import PoseStamped, Twist, TwistStamped
from nav_msgs.msg import Odometry
from rcl_interfaces.msg import SetParametersResult
from rclpy.clock import Clock, ClockType
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import (
    DurabilityPolicy,
    HistoryPolicy,
    QoSProfile,
    ReliabilityPolicy,
    qos_profile_sensor_data,
)
from rclpy.time import Time
from sensor_msgs.msg import LaserScan
from std_msgs.msg import String
from visualization_msgs.msg import MarkerArray

from mentor_core import (
    Bounds,
    DecisionGate,
    GenomePlanner,
    PlannerFrames,
    Transform2D,
    bounds_fault,
    limited_velocity,
    readings_fault,
    readings_from_scan,
)
from mentor_planner_node import conversions, global_plan
from mentor_planner_node.params import (
    PlannerSetupError,
    check_goal_radius,
    declare_parameters,
)
from mentor_ros_common.node_main import run_node

try:  # a full ROS 2 install has tf2_ros; the pip-only one has no wheel
    from tf2_ros import Buffer, TransformException, TransformListener
except ImportError:  # pragma: no cover - depends on the installation
    Buffer = TransformListener = None
    TransformException = LookupError

__all__ = ["NODE_NAME", "QOS_COMMAND", "QOS_GOAL", "QOS_LATCHED", "PlannerNode",
           "PlannerSetupError", "main"]  # fmt: skip

NODE_NAME = "mentor_planner"
COMMAND_DEPTH = 10
EVENT_DEPTH = 10
LATCHED_DEPTH = 1
GOAL_DEPTH = 10
WARN_EVERY_S = 5.0
OBSTACLES_TOPIC = "/mentor/obstacles"
QOS_LATCHED = QoSProfile(
    history=HistoryPolicy.KEEP_LAST,
    depth=LATCHED_DEPTH,
    reliability=ReliabilityPolicy.RELIABLE,
    durability=DurabilityPolicy.TRANSIENT_LOCAL,
)
#: goals from ordinary publishers (RViz, Foxglove, a plain rclpy publisher)
QOS_GOAL = QoSProfile(depth=GOAL_DEPTH, reliability=ReliabilityPolicy.RELIABLE)
QOS_COMMAND = QoSProfile(depth=COMMAND_DEPTH, reliability=ReliabilityPolicy.RELIABLE)
QOS_EVENTS = QoSProfile(depth=EVENT_DEPTH, reliability=ReliabilityPolicy.RELIABLE)


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
        p = declare_parameters(self)
        self.params = p
        self.profile = p.profile
        self.control_period = p.control_period
        self.goal_radius = p.goal_radius
        # the genome and its deployment as the parameters' check loaded them
        self.planner = (
            None if p.loaded is None or p.deployed is None
            else GenomePlanner(p.loaded, p.deployed.profile, p.genome, stages=p.deployed.stages)
        )  # fmt: skip
        self.gate = DecisionGate(p.stale_timeout, p.sync_tolerance)
        self.frames = PlannerFrames(p.map_frame, p.map_to_odom, p.lidar_mount, self._tf())
        self.arena: Bounds | None = None
        #: the global plan (parameter global_plan), None without
        guide = None if p.deployed is None else p.deployed.guide
        self.global_plan = global_plan.attach(self, self.planner, self.frames, self._answer,
                                              guide)  # fmt: skip
        self.decisions = 0
        self.zero_commands = 0
        #: cmd_vel sent again between decisions (``repeat_rate``)
        self.repeats = 0
        self._last_cmd: Twist | None = None  # what a repeat sends; None: nothing
        self.goals_reached = 0

        self._cmd_pub = self.create_publisher(TwistStamped if p.cmd_vel_stamped else Twist,
                                              "cmd_vel", QOS_COMMAND)  # fmt: skip
        # events and goals first: the executor serves ready subscriptions in creation order,
        # so an episode's end and the next start are handled before its observations
        self._events_sub = self.create_subscription(String, "events", self._on_event, QOS_EVENTS)
        self._goal_subs = self._subscribe_goals("goal", latched=True)
        if p.goal_pose_topic:
            self._goal_subs += self._subscribe_goals(p.goal_pose_topic, latched=False)
        self._arena_sub = self.create_subscription(
            MarkerArray, OBSTACLES_TOPIC, self._on_arena, QOS_LATCHED
        )
        sensor = qos_profile_sensor_data
        self._scan_sub = self.create_subscription(LaserScan, "scan", self._on_scan, sensor)
        self._odom_sub = self.create_subscription(Odometry, "odom", self._on_odom, sensor)
        # the watchdog runs on the steady clock: it must fire when sim time stops
        self._steady = Clock(clock_type=ClockType.STEADY_TIME)
        self._watchdog = self.create_timer(self.control_period, self._on_watchdog,
                                           clock=self._steady)
        self._decide_timer = (
            self.create_timer(self.control_period, self._answer) if p.decide_on_timer else None
        )
        # a base stops a robot whose cmd_vel goes quiet for its timeout (diff_drive_controller's
        # cmd_vel_timeout, the simulator's command_timeout: 0.5 s), shorter than a period
        repeating = p.decide_on_timer and p.repeat_rate > 0.0
        self._repeat_timer = (
            self.create_timer(1.0 / p.repeat_rate, self._repeat) if repeating else None
        )
        self.add_on_set_parameters_callback(self._on_parameters)
        if self.planner is None:
            self.get_logger().warning(
                "no genome given (parameter 'genome'): every answer is a zero Twist"
            )
        else:
            g = self.planner.genome
            self.get_logger().info(
                f"planning for {self.profile.name!r} with {p.genome} "
                f"({len(g.nodes)} nodes, {len(g.enabled_connections)} enabled connections); "
                + ("frames from TF" if self.frames.uses_tf else "frames from parameters")
            )

    # ------------------------------------------------------------------ frames

    def _tf(self) -> Any:
        """The TF lookup where tf2_ros is installed (and ``use_tf``), else None."""
        if Buffer is None or not self.params.use_tf:
            return None
        self._tf_buffer = Buffer()
        self._tf_listener = TransformListener(self._tf_buffer, self)

        def lookup(target: str, source: str) -> tuple[Transform2D, bool]:
            try:
                found = self._tf_buffer.lookup_transform(target, source, Time())  # latest
            except TransformException as err:
                raise LookupError(str(err)) from None
            return conversions.planar(found)

        return lookup

    def _steady_ns(self) -> int:
        return int(self._steady.now().nanoseconds)

    # ------------------------------------------------------------------ inputs

    def _subscribe_goals(self, topic: str, latched: bool) -> list[Any]:
        """A volatile subscription (it matches every publisher) and, with ``latched``, a
        latched one for the last goal a latched publisher sent before (not on the goal tools'
        topic: it would only warn of incompatible QoS at every volatile publisher)."""
        subs = [self.create_subscription(PoseStamped, topic, self._on_goal, QOS_GOAL)]
        if latched:
            subs.append(self.create_subscription(PoseStamped, topic, self._on_goal, QOS_LATCHED))
        return subs

    def _warn(self, text: str) -> None:
        self.get_logger().warning(text, throttle_duration_sec=WARN_EVERY_S)

    def _on_scan(self, msg: LaserScan) -> None:
        kind = self.params.scan_kind
        if kind == "auto":
            kind = "sensors" if conversions.is_profile_scan(msg, self.profile) else "lidar"
        now = self._steady_ns()
        try:
            if kind == "sensors":
                ranges = conversions.ranges_from_scan(msg, self.profile)
            else:
                ranges = self._lidar_readings(msg)
        except (ValueError, LookupError) as err:
            self.gate.refuse_scan(now)  # nothing is decided on an older scan
            self._stop(f"scan refused: {err}")
            return
        self.gate.on_scan(conversions.ns_from_stamp(msg.header.stamp), ranges, now)
        if self._decide_timer is None:
            self._answer()

    def _lidar_readings(self, msg: LaserScan) -> Any:
        """The profile's readings off a lidar's scan (its mount from TF or the parameter)."""
        mount = self.frames.mount(msg.header.frame_id)
        read = readings_from_scan(
            conversions.scan_data(msg), mount, self.profile, self.params.ray_width
        )
        if read.uncovered:
            self._warn(f"sensors {list(read.uncovered)} lie outside the scan's field of view: "
                       "they read nothing in range")
        fault = readings_fault(read)
        if fault:
            raise ValueError(fault)
        return read.readings

    def _on_odom(self, msg: Odometry) -> None:
        try:
            pose = conversions.pose_from_odometry(msg)
        except ValueError as err:
            self._stop(f"odometry refused: {err}")
            return
        self.frames.on_odometry(msg.header.frame_id, msg.child_frame_id, pose)
        self.gate.on_odometry(conversions.ns_from_stamp(msg.header.stamp), pose,
                              self._steady_ns())  # fmt: skip
        if self._decide_timer is None:
            self._answer()

    def _goal_in_odom(self, frame: str, xy: Any) -> tuple[float, float] | None:
        """A goal turned into the odometry frame, or None (refused: a warning says why)."""
        try:
            odom, in_map = self.frames.goal(frame, xy)
        except (LookupError, ValueError) as err:
            self.get_logger().warning(f"goal refused: {err}")
            return None
        why = bounds_fault(in_map, self.arena) if in_map is not None else ""
        if why:
            self.get_logger().warning(why)
            return None
        return odom

    def _on_goal(self, msg: PoseStamped) -> None:
        try:
            frame, xy = conversions.goal_request(msg)
        except ValueError as err:
            self.get_logger().warning(f"goal refused: {err}")
            return
        goal = self._goal_in_odom(frame, xy)
        if goal is not None and self.gate.on_goal(goal):  # the same goal twice: one goal
            self.get_logger().info(
                f"new goal ({xy[0]:.3f}, {xy[1]:.3f}) in {frame or self.frames.map_frame!r}"
            )
            self._answer()

    def _on_event(self, msg: String) -> None:
        try:
            kind, goal = conversions.event_from_string(msg)
        except ValueError as err:
            self._warn(f"event rejected: {err}")
            return
        if goal is not None:  # the simulator's goals are in map
            goal = self._goal_in_odom(self.frames.map_frame, goal)
        self.gate.on_event(kind, self._steady_ns(), goal)
        self._last_cmd = None  # an episode began or ended: the last command is not its own
        self._answer()

    def _on_arena(self, msg: MarkerArray) -> None:
        self.arena = conversions.arena_bounds(msg)
        if self.global_plan is not None:
            self.global_plan.on_arena(self.arena)

    def _on_parameters(self, params: list[Parameter]) -> SetParametersResult:
        """``goal_radius`` at run time (the rest is read-only: rclpy refuses it first)."""
        for param in params:
            radius, why = check_goal_radius(param.value, self.profile)
            if why:
                return SetParametersResult(successful=False, reason=why)
            self.goal_radius = radius
            self.get_logger().info(f"goal_radius set to {radius} m")
        return SetParametersResult(successful=True)

    # ------------------------------------------------------------------ answers

    def _answer(self) -> None:
        if self.global_plan is not None and not self.global_plan.ready:
            return  # nothing to follow yet: the observation waits for a map or a path
        obs = self.gate.take(self._steady_ns())
        if obs is None or obs.goal is None:
            return
        if self.gate.arrived(obs.pose, self.goal_radius):
            self.goals_reached += 1
            self.get_logger().info("goal reached: stopping")
            self._send(Twist())
            self._last_cmd = None  # then quiet: nothing is repeated, a teleoperator may drive
            return
        if self.planner is None:
            self._send_zero("no genome loaded")
            return
        decider = self.planner if self.global_plan is None else self.global_plan
        if obs.new_goal:  # a planner with a memory starts each goal blank, as in training
            if self.global_plan is None:
                self.planner.reset()
            else:
                self.global_plan.reset(obs.new_episode)
        try:
            decide = decider.decide
            dtheta, ds = decide(obs.ranges, obs.pose, obs.goal)
            twist = conversions.twist_from_action(dtheta, ds, self.control_period)
            if self.params.limits.any:  # the robot's limits, after the network
                last = self._last_cmd or Twist()
                v, w = limited_velocity((twist.linear.x, twist.angular.z), self.params.limits,
                                        (last.linear.x, last.angular.z), self.control_period)
                twist.linear.x, twist.angular.z = v, w
        except (ValueError, LookupError) as err:  # LookupError: map -> odom for a global plan
            self._send_zero(f"no decision ({err})")
            return
        self._send(twist)
        self.decisions += 1

    def _on_watchdog(self) -> None:
        reason = self.gate.watchdog(self._steady_ns())
        if reason is not None and self.global_plan is not None and not self.global_plan.ready:
            reason = self.global_plan.waiting_for()
        if reason is not None:
            self._zero()
            # its own call site: rclpy throttles each call site apart, so a flood of other
            # warnings never hides why the robot stopped
            self.get_logger().warning(f"watchdog: {reason}: sending a zero Twist",
                                      throttle_duration_sec=WARN_EVERY_S)  # fmt: skip

    def _send(self, twist: Twist) -> None:
        self._publish(twist)
        self._last_cmd = twist

    def _publish(self, twist: Twist) -> None:
        """``twist`` on cmd_vel, stamped now in the robot's body frame with
        ``cmd_vel_stamped``."""
        if not self.params.cmd_vel_stamped:
            self._cmd_pub.publish(twist)
            return
        msg = TwistStamped(twist=twist)
        msg.header.stamp = self.get_clock().now().to_msg()
        msg.header.frame_id = self.frames.base_frame
        self._cmd_pub.publish(msg)

    def _repeat(self) -> None:
        if self._last_cmd is None:
            return
        stale = self.gate.stale(self._steady_ns())
        if stale is not None and self._last_cmd != Twist():
            self._stop(stale)  # never the last command again on data that stopped coming
            return
        self._publish(self._last_cmd)
        self.repeats += 1

    def _zero(self) -> None:
        self._send(Twist())
        self.zero_commands += 1

    def _send_zero(self, reason: str) -> None:
        self._zero()
        self._warn(f"{reason}: sending a zero Twist")

    def _stop(self, reason: str) -> None:
        """A zero Twist at once, with a line of its own (throttled apart from other lines)."""
        self._zero()
        self.get_logger().warning(f"{reason}: stopping", throttle_duration_sec=WARN_EVERY_S)


def main(args: list[str] | None = None) -> None:
    """Run the node until shutdown; a bad setup is one line on stderr and exit status 2."""
    run_node("mentor_planner", PlannerNode, args)
