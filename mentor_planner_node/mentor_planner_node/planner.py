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
A goal ends reached (within ``goal_radius``, facing its heading where ``yaw_goal_tolerance`` is
set), aborted (Nav2's progress checker, a time limit, an obstacle the map comes to show at it),
canceled or preempted (:class:`mentor_core.GoalTracker`); each step goes out on ``goal_status``,
and Nav2's ``NavigateToPose`` is served on ``navigate_to_pose`` where ``nav2_msgs`` is
(:mod:`.navigate_action`). Frames come from TF through ``tf2_ros`` or, without it, a buffer of
the node's own on ``/tf`` and ``/tf_static`` (:class:`mentor_core.TfBuffer`).
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

import math
import time
from collections import deque
from collections.abc import Callable
from dataclasses import replace
from typing import Any

from geometry_msgs.msg import PoseStamped, Twist, TwistStamped, Vector3
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
    GoalStep,
    GoalTracker,
    MountedScan,
    PlannerFrames,
    TfBuffer,
    Transform2D,
    bounds_fault,
    limited_velocity,
    readings_fault,
    readings_from_scan,
    same_goal,
)
from mentor_planner_node import conversions, global_plan, navigate_action
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
try:  # a full install, or generated in the workspace (interfaces/README.md)
    from tf2_msgs.msg import TFMessage
except ImportError:  # pragma: no cover - depends on the installation
    TFMessage = None

__all__ = ["NODE_NAME", "QOS_COMMAND", "QOS_GOAL", "QOS_LATCHED", "PlannerNode",
           "PlannerSetupError", "main"]  # fmt: skip

NODE_NAME = "mentor_planner"
_NS_PER_S = 1e9
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
#: /tf as tf2_ros's listener subscribes it
QOS_TF = QoSProfile(depth=100, reliability=ReliabilityPolicy.RELIABLE)
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
                                              guide, p.decide_on_timer)  # fmt: skip
        self.decisions = 0
        #: s from each answered scan's arrival to its Twist's publication, and from the start
        #: of the answer (the timer's tick, or the scan) to it (wall clock; the latest 100,000
        #: each), for ``benchmarks/tools/scripted_robot_goals.py --timing``
        self.latencies: deque[float] = deque(maxlen=100_000)
        self.answer_seconds: deque[float] = deque(maxlen=100_000)
        self._scan_arrived = 0.0
        self.zero_commands = 0
        #: cmd_vel sent again between decisions (``repeat_rate``)
        self.repeats = 0
        self._last_cmd: Twist | None = None  # what a repeat sends; None: nothing
        self.goals_reached = 0
        self.goals_aborted = 0
        #: the goal being driven to, judged (None before its first observation)
        self.tracker: GoalTracker | None = None
        self._goal_yaw: float | None = None  # the held goal's heading (odometry frame)
        self._episode_goal: tuple[float, float] | None = None  # the simulator's episode goal
        #: called with (outcome, text) when a goal ends (the NavigateToPose server)
        self.on_goal_end: Callable[[str, str], None] | None = None
        #: called with (pose, distance) after each decision (the server's feedback)
        self.on_decision: Callable[[Any, float], None] | None = None
        self._status_pub = self.create_publisher(String, "goal_status", QOS_LATCHED)
        #: steady ns of each timer's last run, and whether it judged nothing then
        self._timer_runs: dict[str, tuple[int, bool]] = {}
        #: a goal waiting for TF: frame, xy, yaw, episode, why, since (steady ns)
        self._pending: tuple[str, Any, float | None, bool, str, int] | None = None
        self._episode_in_map: tuple[float, float] | None = None  # the last episode's goal

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
        #: Nav2's NavigateToPose on ``navigate_to_pose``, where nav2_msgs is installed
        self.navigate = navigate_action.attach(self)
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

    def destroy_node(self) -> None:
        """Take the action server down with the node."""
        if getattr(self, "navigate", None) is not None:
            self.navigate.destroy()
        super().destroy_node()

    # ------------------------------------------------------------------ frames

    def _tf(self) -> Any:
        """The TF lookup (``use_tf``): ``tf2_ros``'s buffer where it is installed, else a
        buffer of its own on ``/tf`` and ``/tf_static`` where ``tf2_msgs`` is
        (:class:`mentor_core.TfBuffer`, the same lookups at the latest time); None without
        either (frames from the parameters)."""
        if not self.params.use_tf:
            return None
        if Buffer is not None:
            self._tf_buffer = Buffer()
            self._tf_listener = TransformListener(self._tf_buffer, self)

            def lookup(target: str, source: str) -> tuple[Transform2D, bool]:
                try:
                    found = self._tf_buffer.lookup_transform(target, source, Time())  # latest
                except TransformException as err:
                    raise LookupError(str(err)) from None
                return conversions.planar(found)

            return lookup
        if TFMessage is None:
            return None
        self._own_tf = TfBuffer()
        self._tf_subs = [self.create_subscription(TFMessage, "/tf", self._on_tf, QOS_TF),
                         self.create_subscription(TFMessage, "/tf_static", self._on_tf,
                                                  QOS_LATCHED)]  # fmt: skip
        return self._own_tf.lookup

    def _on_tf(self, msg: Any) -> None:
        for link in msg.transforms:
            try:
                pose, inverted = conversions.planar(link)
                self._own_tf.set(link.header.frame_id, link.child_frame_id, pose, inverted)
            except ValueError as err:
                self._warn(f"transform {link.header.frame_id} -> {link.child_frame_id} "
                           f"refused: {err}")
        self._retry_goal()

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
        self._scan_arrived = time.perf_counter()
        if self.frames.uses_tf and not self.frames.has_odometry:
            return  # no pose to pair it with, and the body frame its mount hangs from unknown
        kind = self.params.scan_kind
        if kind == "auto":
            kind = "sensors" if conversions.is_profile_scan(msg, self.profile) else "lidar"
        now = self._steady_ns()
        scan = None
        try:
            if kind == "sensors":
                ranges = conversions.ranges_from_scan(msg, self.profile)
            else:
                ranges, scan = self._lidar_readings(msg)
        except (ValueError, LookupError) as err:
            self.gate.refuse_scan(now)  # nothing is decided on an older scan
            self._stop(f"scan refused: {err}")
            return
        self.gate.on_scan(conversions.ns_from_stamp(msg.header.stamp), ranges, now, scan)
        if self._decide_timer is None:
            self._answer()

    def _lidar_readings(self, msg: LaserScan) -> tuple[Any, MountedScan]:
        """The profile's readings off a lidar's scan (its mount from TF or the parameter),
        and the scan on its mount (for a scan map of all its rays)."""
        mount = self.frames.mount(msg.header.frame_id)
        data = conversions.scan_data(msg)
        read = readings_from_scan(data, mount, self.profile, self.params.ray_width)
        if read.uncovered:
            self._warn(f"sensors {list(read.uncovered)} lie outside the scan's field of view: "
                       "they read nothing in range")
        fault = readings_fault(read)
        if fault:
            raise ValueError(fault)
        return read.readings, MountedScan(data, mount)

    def _on_odom(self, msg: Odometry) -> None:
        try:
            pose = conversions.pose_from_odometry(msg)
        except ValueError as err:
            self._stop(f"odometry refused: {err}")
            return
        self.frames.on_odometry(msg.header.frame_id, msg.child_frame_id, pose)
        self._retry_goal()
        self.gate.on_odometry(conversions.ns_from_stamp(msg.header.stamp), pose,
                              self._steady_ns())  # fmt: skip
        if self._decide_timer is None:
            self._answer()

    def _goal_in_odom(self, frame: str, xy: Any) -> tuple[tuple[float, float] | None, str]:
        """A goal turned into the odometry frame, or None and why it is refused. LookupError:
        its frame is not linked to the odometry frame (yet)."""
        try:
            odom, in_map = self.frames.goal(frame, xy)
        except ValueError as err:
            return None, f"goal refused: {err}"
        why = bounds_fault(in_map, self.arena) if in_map is not None else ""
        return (None, why) if why else (odom, "")

    def request_goal(self, frame: str, xy: Any, yaw: float | None = None,
                     episode: bool = False, renew: bool = False) -> str:  # fmt: skip
        """Drive to the goal ``xy`` (m) given in ``frame`` (empty: the map's), with the
        heading ``yaw`` (rad; None: any) where ``yaw_goal_tolerance`` is set; '' when it is
        accepted (or is the goal already held), else why it is refused (one line, logged and
        published on ``goal_status``). A goal held before ends ``preempted``. A goal whose
        frame TF does not link yet (at start-up) waits for it, ``stale_timeout`` at most;
        ``episode``: the simulator's episode goal, which the simulator judges; ``renew``: a
        new goal even where it is the goal held (an action's new goal)."""
        # the simulator sends its episode's goal on the goal topic too
        episode = episode or (frame in ("", self.frames.map_frame) and
                              same_goal(self._episode_in_map, xy))
        try:
            goal, why = self._goal_in_odom(frame, xy)
            heading = None if yaw is None or goal is None else self.frames.heading(frame, yaw)
            if goal is not None and self.global_plan is not None:
                why = self.global_plan.goal_fault(goal)
        except LookupError as err:
            self._wait_for_tf(frame, xy, yaw, episode, err)
            return ""
        self._pending = None
        if why and not why.startswith("goal refused"):
            why = f"goal refused: {why}"
        if goal is None or why:
            self.get_logger().warning(why)
            self._status(why)
            return why
        held = self.gate.goal
        if renew and held is not None:
            self._finish("preempted", "a new goal came", stop=False)
            self.gate.end_goal()
            held = None
        if self.gate.on_goal(goal):  # the same goal twice: one goal
            if held is not None:
                self._finish("preempted", "a new goal came", stop=False)
            self._goal_yaw = heading
            self._episode_goal = goal if episode else None
            self.get_logger().info(
                f"new goal ({xy[0]:.3f}, {xy[1]:.3f}) in {frame or self.frames.map_frame!r}"
            )
            self._status(f"accepted ({goal[0]:.3f}, {goal[1]:.3f})")
            self._answer()
        return ""

    def _wait_for_tf(self, frame: str, xy: Any, yaw: float | None, episode: bool,
                     err: LookupError) -> None:  # fmt: skip
        """Hold a goal whose frame TF does not link yet (:meth:`_retry_goal` takes it)."""
        if self._pending is None:
            self.get_logger().info(f"goal waits for its frame on TF: {err}")
        since = self._steady_ns() if self._pending is None else self._pending[-1]
        self._pending = (frame, tuple(xy), yaw, episode, str(err), since)

    @property
    def goal_waits(self) -> bool:
        """A goal waits for its frame on TF (:meth:`request_goal`)."""
        return self._pending is not None

    def _retry_goal(self) -> None:
        """Take a goal that waits for TF now, or refuse it once it has waited too long."""
        if self._pending is None:
            return
        frame, xy, yaw, episode, err, since = self._pending
        if self._steady_ns() - since <= self.params.stale_timeout * _NS_PER_S:
            self.request_goal(frame, xy, yaw, episode)
            return
        self._pending = None
        why = f"goal refused: {err} (waited {self.params.stale_timeout:g} s for TF)"
        self.get_logger().warning(why)
        self._status(why)
        if self.on_goal_end is not None:
            self.on_goal_end("refused", why)

    def cancel_goal(self) -> bool:
        """End the goal held (``canceled``: one zero Twist, then quiet); False without one."""
        if self.gate.goal is None:
            return False
        self._finish("canceled", "goal canceled")
        return True

    def _on_goal(self, msg: PoseStamped) -> None:
        try:
            frame, xy, yaw = conversions.goal_request(msg)
        except ValueError as err:
            self.get_logger().warning(f"goal refused: {err}")
            self._status(f"goal refused: {err}")
            return
        self.request_goal(frame, xy, yaw)

    def _on_event(self, msg: String) -> None:
        try:
            kind, goal = conversions.event_from_string(msg)
        except ValueError as err:
            self._warn(f"event rejected: {err}")
            return
        in_map, goal = goal, None
        if kind == "started":
            self._episode_in_map = in_map
        if in_map is not None:  # the simulator's goals are in map
            try:
                goal, why = self._goal_in_odom(self.frames.map_frame, in_map)
            except LookupError as err:  # map -> odom not on TF yet: the goal waits for it
                why = ""
                self._wait_for_tf(self.frames.map_frame, in_map, None, True, err)
            if why:
                self.get_logger().warning(why)
        if kind == "started":  # the simulator's episode: it judges the goal's end itself
            self._episode_goal, self._goal_yaw = goal, None
        self.gate.on_event(kind, self._steady_ns(), goal)
        if self.gate.goal is None:
            self.tracker = None
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
        began = time.perf_counter()
        if self.global_plan is not None and not self.global_plan.ready:
            return  # nothing to follow yet: the observation waits for a map or a path
        obs = self.gate.take(self._steady_ns())
        if obs is None or obs.goal is None:
            return
        step = self._goal_step(obs.goal, obs.pose)
        if step.kind in ("reached", "aborted"):
            self._finish(step.kind, "goal reached" if step.kind == "reached" else step.reason)
            return
        if step.kind == "turn":  # at the goal: turning in place to its heading
            self._send(self._limited(Twist(angular=Vector3(z=step.turn))))
            return
        if self.planner is None:
            self._send_zero("no genome loaded")
            return
        if obs.new_goal:  # a planner with a memory starts each goal blank, as in training
            if self.global_plan is None:
                self.planner.reset()
            else:
                self.global_plan.reset(obs.new_episode)
        try:
            if self.global_plan is None:
                dtheta, ds = self.planner.decide(obs.ranges, obs.pose, obs.goal)
            else:
                dtheta, ds = self.global_plan.decide(obs.ranges, obs.pose, obs.goal, obs.scan)
            twist = self._limited(conversions.twist_from_action(dtheta, ds, self.control_period))
            # a goal of a request the map now shows unreachable (an episode's is the
            # simulator's to end)
            fault = "" if self.global_plan is None or self._episode_goal is not None else (
                self.global_plan.goal_fault(obs.goal))
        except (ValueError, LookupError) as err:  # LookupError: map -> odom for a global plan
            self._send_zero(f"no decision ({err})")
            return
        if fault:
            self._finish("aborted", fault)
            return
        self._send(twist)
        sent = time.perf_counter()
        self.latencies.append(sent - self._scan_arrived)
        self.answer_seconds.append(sent - began)
        self.decisions += 1
        if self.on_decision is not None:
            self.on_decision(obs.pose, step.distance)

    def _goal_step(self, goal: tuple[float, float], pose: Any) -> GoalStep:
        """Where the goal stands with the robot at ``pose`` (:class:`mentor_core.GoalTracker`,
        started at the goal's first observation; an episode's goal is only ever reached)."""
        now = self.get_clock().now().nanoseconds / _NS_PER_S
        if self.tracker is None or self.tracker.goal != goal:
            rules = self.params.goal_rules(self.goal_radius)
            if self._episode_goal is not None:
                rules = replace(rules, movement_radius=0.0, time_limit=math.inf)
            self.tracker = GoalTracker(rules, goal, self._goal_yaw, pose, now)
        return self.tracker.step(pose, now)

    def _limited(self, twist: Twist) -> Twist:
        """``twist`` within the robot's limits (after the network), from the last command."""
        if self.params.limits.any:
            last = self._last_cmd or Twist()
            v, w = limited_velocity((twist.linear.x, twist.angular.z), self.params.limits,
                                    (last.linear.x, last.angular.z), self.control_period)
            twist.linear.x, twist.angular.z = v, w
        return twist

    def _finish(self, outcome: str, text: str, stop: bool = True) -> None:
        """End the goal held: ``outcome`` is reached, aborted, canceled or preempted (by a
        new goal, which drives on: no ``stop``); one zero Twist, then quiet (nothing is
        repeated: a teleoperator may drive); logged and published on ``goal_status``."""
        if outcome == "reached":
            self.goals_reached += 1
            self.get_logger().info("goal reached: stopping")
        elif outcome == "aborted":
            self.goals_aborted += 1
            self.get_logger().warning(f"goal aborted: {text}: stopping")
        else:
            self.get_logger().info(text)
        if stop:
            self.gate.end_goal()
            self._send(Twist())
            self._last_cmd = None
        self.tracker = None
        self._status(outcome if outcome in ("reached", "canceled") else f"{outcome}: {text}")
        if self.on_goal_end is not None:
            self.on_goal_end(outcome, text)

    def _status(self, text: str) -> None:
        self._status_pub.publish(String(data=text))

    def _on_watchdog(self) -> None:
        now = self._steady_ns()
        if self._held_up("watchdog", self.control_period, now):
            return
        reason = self.gate.watchdog(now)
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

    def _held_up(self, timer: str, period: float, now: int) -> bool:
        """Whether ``timer`` (of ``period`` s) runs late because the node was busy (a long
        plan): the messages that came meanwhile wait behind it, so no stream can be judged
        stale this round."""
        last, skipped = self._timer_runs.get(timer, (None, False))
        # once: a node held up round after round (a machine too slow) is judged as it is
        late = last is not None and now - last > 2.0 * period * _NS_PER_S and not skipped
        self._timer_runs[timer] = (now, late)
        return late

    def _repeat(self) -> None:
        now = self._steady_ns()
        if self._held_up("repeat", 1.0 / self.params.repeat_rate, now):
            return
        if self._last_cmd is None:
            return
        stale = self.gate.stale(now)
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
        """A zero Twist at once, with a line of its own (throttled apart from other lines);
        without a goal only the line: nothing is driven, and a teleoperator may be."""
        if self.gate.goal is None:
            self.get_logger().warning(reason, throttle_duration_sec=WARN_EVERY_S)
            return
        self._zero()
        self.get_logger().warning(f"{reason}: stopping", throttle_duration_sec=WARN_EVERY_S)


def main(args: list[str] | None = None) -> None:
    """Run the node until shutdown; a bad setup is one line on stderr and exit status 2."""
    run_node("mentor_planner", PlannerNode, args)
