"""The MENTOR simulator node: robots on the pymunk reference world, one decision per period.

Everything it computes is ``mentor_core`` (:mod:`mentor_core.simulator`,
:mod:`mentor_core.scenario_plan`, :mod:`mentor_core.recording`); this module only turns that
into topics, parameters, timers and a service. See ``docs/ros.md`` for the full contract.

Stepping ("lockstep", ``real_time_factor`` 0, the default): at each control period the node
publishes ``/clock`` and every driving robot's ``<ns>/scan`` and ``<ns>/odom``, then waits
for one ``<ns>/cmd_vel`` from each of them and steps at once: sim time runs as fast as the
planners answer. An observation not answered within ``resend_period`` (wall s) is published
again with the same stamp (a planner answers a stamp once); with ``answer_timeout`` > 0 a
robot that has not answered by then holds still for the period. With ``real_time_factor`` r
> 0 a wall timer steps every ``dt / r`` s with the latest command of each robot (none: it
holds still).
"""

from __future__ import annotations

import json
import sys
import time
from collections.abc import Callable
from typing import Any, NamedTuple

import rclpy
from geometry_msgs.msg import PoseStamped, Twist
from nav_msgs.msg import Odometry
from rcl_interfaces.msg import FloatingPointRange, IntegerRange, ParameterDescriptor
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

from mentor_core.bagio import EventKind
from mentor_core.errors import MentorError
from mentor_core.lockstep import CommandBarrier, LatestCommands
from mentor_core.recording import EpisodeRecorder
from mentor_core.robots import RobotProfile, get_profile
from mentor_core.scenario_plan import ScenarioPlan, load_scenario_source
from mentor_core.simulator import Event, ReferenceSimulator
from mentor_sim_node import conversions

NODE_NAME = "mentor_sim"
OBSTACLES_TOPIC = "/mentor/obstacles"
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
_NS_PER_S = 1_000_000_000


class SimSetupError(MentorError):
    """A parameter of the simulator node is invalid (one line)."""


class Outcome(NamedTuple):
    """How one robot's episode ended (:attr:`SimNode.outcomes`)."""

    episode: int
    robot: str
    event: str  # reached, collided or timed_out
    scenario: int
    steps: int  # decisions taken
    time_used: float  # s
    pose: tuple[float, float, float]  # where it stopped (x, y, theta)


def _descriptor(text: str, **extra: Any) -> ParameterDescriptor:
    return ParameterDescriptor(description=text, read_only=True, **extra)


def _at_least(low: float) -> list[FloatingPointRange]:
    return [FloatingPointRange(from_value=low, to_value=1e9, step=0.0)]


class _Robot:
    """Publishers, subscription and the last messages of one robot namespace."""

    def __init__(self, name: str, profile: RobotProfile) -> None:
        self.name = name
        self.profile = profile
        self.scan_pub: Any = None
        self.odom_pub: Any = None
        self.goal_pub: Any = None
        self.events_pub: Any = None
        self.cmd_sub: Any = None
        self.last_scan: LaserScan | None = None
        self.last_odom: Odometry | None = None
        self.twist = (0.0, 0.0)  # (v, omega) of the last applied command, for odometry


class SimNode(Node):
    """Simulates MENTOR robots on a pymunk world (module docstring; ``docs/ros.md``).

    Raises :class:`mentor_core.errors.MentorError` (one line) for bad parameters, an unknown
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
        self._recorder: EpisodeRecorder | None = None
        self._read_parameters()
        source = load_scenario_source(
            self._world_file, self._scenario_bag, self._robots[0].profile, self._seed
        )
        self._plan = ScenarioPlan(
            source,
            [(r.name, r.profile) for r in self._robots],
            first=self._first,
            time_limit=self._time_limit,
        )
        for line in self._plan.skipped:
            self.get_logger().error(f"{source.origin}: {line}")
        self._world = source.world
        self._sim = ReferenceSimulator(self._world, self._dt)
        self._by_name = {r.name: r for r in self._robots}
        self._time_ns = 0
        self._episode = -1
        self._episodes_done = 0
        self._finished = False
        self._pending_start = True
        self._pending_observe = False
        self._barrier = CommandBarrier(self._resend_period, self._answer_timeout)
        self._latest = LatestCommands()
        if self._record:
            self._recorder = EpisodeRecorder(self._world, self._dt, [r.name for r in self._robots])
        self._saved = False
        self.rejections: list[str] = list(self._plan.skipped)
        #: every robot episode that has ended, in order
        self.outcomes: list[Outcome] = []

        self._clock_pub = self.create_publisher(ClockMsg, "/clock", QOS_CLOCK)
        self._markers_pub = self.create_publisher(MarkerArray, OBSTACLES_TOPIC, QOS_LATCHED)
        sensor = qos_profile_sensor_data
        for r in self._robots:
            r.scan_pub = self.create_publisher(LaserScan, f"{r.name}/scan", sensor)
            r.odom_pub = self.create_publisher(Odometry, f"{r.name}/odom", sensor)
            r.goal_pub = self.create_publisher(PoseStamped, f"{r.name}/goal", QOS_LATCHED)
            r.events_pub = self.create_publisher(String, f"{r.name}/events", QOS_EVENTS)
            r.cmd_sub = self.create_subscription(
                Twist, f"{r.name}/cmd_vel", self._command_callback(r.name), QOS_COMMAND
            )
        self._reset_srv = self.create_service(Trigger, "~/reset", self._on_reset)
        wall = Clock(clock_type=ClockType.STEADY_TIME)
        if self._rtf > 0.0:
            self._timer = self.create_timer(self._dt / self._rtf, self._on_tick, clock=wall)
        else:
            self._timer = self.create_timer(self._resend_period, self._on_lockstep, clock=wall)
        self._markers_pub.publish(conversions.markers_from_world(self._world))
        self._publish_clock()
        self.get_logger().info(
            f"simulating {', '.join(f'{r.name} ({r.profile.name})' for r in self._robots)} "
            f"on {source.origin}: {len(source.scenarios)} scenarios, "
            + ("as fast as the planners answer" if self._rtf == 0.0 else f"{self._rtf}x real time")
        )

    # ------------------------------------------------------------------ parameters

    def _read_parameters(self) -> None:
        declared = self.declare_parameters(
            "",
            [
                ("robots", ["robot_0"], _descriptor("robot namespaces, one robot each")),
                (
                    "profiles",
                    ["ugv"],
                    _descriptor("robot profile per robot (one entry: the same for all)"),
                ),
                ("world", "", _descriptor("world file (YAML) with scenarios")),
                ("scenario_bag", "", _descriptor("scenario bag (instead of a world file)")),
                ("seed", 0, _descriptor("seed of the training scenarios used without a file")),
                (
                    "first_scenario",
                    0,
                    _descriptor("offset of the first scenario handed out", integer_range=[
                        IntegerRange(from_value=0, to_value=1_000_000, step=1)
                    ]),
                ),
                (
                    "episodes",
                    0,
                    _descriptor("episodes to run, then stop (0: no limit)", integer_range=[
                        IntegerRange(from_value=0, to_value=1_000_000, step=1)
                    ]),
                ),
                (
                    "auto_advance",
                    True,
                    _descriptor("start the next scenario when an episode ends (else: ~/reset)"),
                ),
                (
                    "time_limit",
                    0.0,
                    _descriptor(
                        "episode time limit, s (0: the profile's time budget T_tot)",
                        floating_point_range=_at_least(0.0),
                    ),
                ),
                (
                    "real_time_factor",
                    0.0,
                    _descriptor(
                        "sim seconds per wall second (0: as fast as the planners answer)",
                        floating_point_range=_at_least(0.0),
                    ),
                ),
                (
                    "answer_timeout",
                    0.0,
                    _descriptor(
                        "wall s to wait for a cmd_vel before the robot holds still (0: wait)",
                        floating_point_range=_at_least(0.0),
                    ),
                ),
                (
                    "resend_period",
                    0.1,
                    _descriptor(
                        "wall s after which an unanswered observation is published again",
                        floating_point_range=_at_least(0.001),
                    ),
                ),
                ("record", "", _descriptor("episode bag to write everything into ('' : none)")),
                (
                    "record_metadata",
                    "{}",
                    _descriptor("JSON object added to the recording's metadata (e.g. genomes)"),
                ),
            ],
        )
        values = {p.name: p.value for p in declared}
        names = [str(n) for n in values["robots"]]
        profiles = [str(p) for p in values["profiles"]]
        if not names or len(set(names)) != len(names):
            raise SimSetupError(f"robots: need distinct robot names, got {names}")
        for n in names:
            if not n or n.startswith("/") or not all(
                part and part[0].isalpha() and part.replace("_", "").isalnum()
                for part in n.split("/")
            ):
                raise SimSetupError(f"robots: {n!r} is not a relative ROS name like 'robot_0'")
        if len(profiles) == 1:
            profiles = profiles * len(names)
        if len(profiles) != len(names):
            raise SimSetupError(
                f"profiles: {len(profiles)} given for {len(names)} robots (give 1 or one each)"
            )
        self._robots = [_Robot(n, get_profile(p)) for n, p in zip(names, profiles, strict=True)]
        periods = {r.profile.control_period for r in self._robots}
        if len(periods) != 1:
            raise SimSetupError(f"profiles: robots decide at different periods {sorted(periods)}")
        self._dt = periods.pop()
        self._dt_ns = round(self._dt * _NS_PER_S)
        self._world_file = str(values["world"])
        self._scenario_bag = str(values["scenario_bag"])
        self._seed = int(values["seed"])
        self._first = int(values["first_scenario"])
        self._episodes_limit = int(values["episodes"])
        self._auto_advance = bool(values["auto_advance"])
        limit = float(values["time_limit"])
        self._time_limit = limit if limit > 0.0 else None
        self._rtf = float(values["real_time_factor"])
        self._answer_timeout = float(values["answer_timeout"])
        self._resend_period = float(values["resend_period"])
        self._record = str(values["record"])
        if self._record and len({r.profile.name for r in self._robots}) != 1:
            raise SimSetupError("record: an episode bag holds robots of one profile only")
        try:
            note = json.loads(str(values["record_metadata"]))
        except json.JSONDecodeError as err:
            raise SimSetupError(f"record_metadata: not JSON ({err.msg})") from None
        if not isinstance(note, dict):
            raise SimSetupError("record_metadata: not a JSON object")
        self._record_note: dict[str, Any] = note
        # the mount layout of every robot, for tools that need the sensor geometry
        for r in self._robots:
            key = r.name.replace("/", ".")
            self.declare_parameters(
                "",
                [
                    (f"{key}.profile", r.profile.name, _descriptor("robot profile")),
                    (
                        f"{key}.sensor_x",
                        [m.x for m in r.profile.sensors],
                        _descriptor("sensor mount x in the body frame, m (scan order)"),
                    ),
                    (
                        f"{key}.sensor_y",
                        [m.y for m in r.profile.sensors],
                        _descriptor("sensor mount y in the body frame, m (scan order)"),
                    ),
                    (
                        f"{key}.sensor_angle",
                        [m.angle for m in r.profile.sensors],
                        _descriptor("sensor facing angle in the body frame, rad (scan order)"),
                    ),
                    (f"{key}.sensor_range", r.profile.sensor_range, _descriptor("range, m")),
                ],
            )

    # ------------------------------------------------------------------ state, for callers

    @property
    def finished(self) -> bool:
        """All ``episodes`` have run (never with ``episodes`` 0)."""
        return self._finished

    @property
    def episodes_done(self) -> int:
        """Episodes that have ended."""
        return self._episodes_done

    @property
    def sim_time_ns(self) -> int:
        """Current simulation time, ns."""
        return self._time_ns

    @property
    def recorder(self) -> EpisodeRecorder | None:
        """What has been recorded (None without ``record``)."""
        return self._recorder

    # ------------------------------------------------------------------ episodes

    def _start_episode(self) -> None:
        self._pending_start = False
        self._latest.clear()
        if self._episode >= 0:
            self._time_ns += self._dt_ns  # one period between episodes: no stamp in two
        self._episode += 1
        setups = self._plan.setups(self._episode)
        events, rejected = self._sim.start(setups)
        for rej in rejected:
            line = f"episode {self._episode}: {rej.robot} cannot start scenario {rej.scenario}: "
            self.get_logger().error(line + rej.reason)
            self.rejections.append(line + rej.reason)
        accepted = [s for s in setups if s.name in self._sim.robots]
        if self._recorder is not None:
            self._recorder.begin_episode(self._episode, self._time_ns, accepted)
        self._publish_clock()
        stamp = conversions.time_from_ns(self._time_ns)
        for s in accepted:
            r = self._by_name[s.name]
            r.twist = (0.0, 0.0)
            r.goal_pub.publish(conversions.pose_stamped_from_goal(s.goal, stamp))
            if self._recorder is not None:
                self._recorder.goal(s.name, self._time_ns, s.goal)
        self._publish_events(events)
        self.get_logger().info(
            f"episode {self._episode}: "
            + ", ".join(f"{s.name} scenario {s.scenario}" for s in accepted)
            if accepted
            else f"episode {self._episode}: no robot could start"
        )
        if self._sim.done:
            self._end_episode(final=[s.name for s in accepted])
        elif self._rtf > 0.0:
            self._observe()
        else:
            # lockstep: the first observation goes out at the next tick, one resend period
            # after the goals and started events, so that planners in other processes have
            # them first
            self._pending_observe = True

    def _end_episode(self, final: list[str]) -> None:
        self._publish_final_odometry(final)
        self._episodes_done += 1
        self._barrier.clear()
        if self._episodes_limit and self._episodes_done >= self._episodes_limit:
            self.get_logger().info(f"all {self._episodes_limit} episodes done")
            self.save_recording()
            self._finished = True  # after the bag is written: callers may read it at once
        elif self._auto_advance:
            self._pending_start = True
        else:
            self.get_logger().info("episode over; call ~/reset to start the next scenario")

    def _advance(self, decisions: dict[str, tuple[float, float]]) -> None:
        """Step every driving robot by its decision; publish what follows."""
        driving = self._sim.active
        for name in driving:
            dtheta, ds = decisions.get(name, (0.0, 0.0))
            self._by_name[name].twist = (ds / self._dt, dtheta / self._dt)
        events = self._sim.step({n: decisions.get(n, (0.0, 0.0)) for n in driving})
        self._time_ns += self._dt_ns
        self._publish_clock()
        self._publish_events(events)
        ended = [e.robot for e in events]
        if self._sim.done:
            self._end_episode(final=ended)
        else:
            self._publish_final_odometry(ended)
            self._observe()

    def _observe(self) -> None:
        """Publish scan and odometry of every driving robot at the current time."""
        stamp = conversions.time_from_ns(self._time_ns)
        for name in self._sim.active:
            r = self._by_name[name]
            ranges = self._sim.observe(name)
            frame = f"{name}/base_link"
            scan = conversions.laser_scan_from_ranges(ranges, r.profile, stamp, frame)
            odom = conversions.odometry_from_pose(self._sim.pose(name), r.twist, stamp, name)
            r.scan_pub.publish(scan)
            r.odom_pub.publish(odom)
            r.last_scan, r.last_odom = scan, odom
            if self._recorder is not None:
                self._recorder.scan(name, self._time_ns, scan.ranges)
                self._recorder.odometry(name, self._time_ns, self._sim.pose(name), r.twist)
        self._barrier.ask(self._sim.active, time.monotonic())

    def _publish_final_odometry(self, names: list[str]) -> None:
        """Odometry of robots whose episode just ended: where they stopped, at rest."""
        stamp = conversions.time_from_ns(self._time_ns)
        for name in names:
            r = self._by_name[name]
            r.twist = (0.0, 0.0)
            pose = self._sim.pose(name)
            r.odom_pub.publish(conversions.odometry_from_pose(pose, r.twist, stamp, name))
            if self._recorder is not None:
                self._recorder.odometry(name, self._time_ns, pose, r.twist)

    def _publish_events(self, events: list[Event]) -> None:
        for ev in events:
            self._publish_event(ev.robot, ev.kind, ev.scenario)

    def _publish_event(self, name: str, kind: EventKind, scenario: int) -> None:
        goal = self._sim.state(name).goal if kind == "started" else None
        msg = conversions.event_string(kind, scenario, self._time_ns, goal)
        self._by_name[name].events_pub.publish(msg)
        if self._recorder is not None:
            self._recorder.event(name, self._time_ns, kind, scenario)
        if kind != "started":
            state = self._sim.state(name)
            self.outcomes.append(
                Outcome(
                    self._episode, name, kind, scenario, state.steps, state.time_used, state.pose
                )
            )
            self.get_logger().info(
                f"{name}: {kind} after {state.steps} decisions ({state.time_used:.2f} s), "
                f"scenario {scenario}"
            )

    def _publish_clock(self) -> None:
        self._clock_pub.publish(ClockMsg(clock=conversions.time_from_ns(self._time_ns)))

    # ------------------------------------------------------------------ callbacks

    def _command_callback(self, name: str) -> Callable[[Twist], None]:
        def callback(msg: Twist) -> None:
            self._on_command(name, msg)

        return callback

    def _on_command(self, name: str, msg: Twist) -> None:
        lockstep = self._rtf == 0.0
        if name not in self._sim.active or (lockstep and name not in self._barrier.waiting):
            self.get_logger().debug(f"{name}/cmd_vel: no observation waits for it; dropped")
            return
        try:
            decision = conversions.twist_to_action(msg, self._dt)
        except ValueError as err:
            self.get_logger().warning(
                f"{name}/cmd_vel rejected: {err}; the robot holds still this period",
                throttle_duration_sec=WARN_EVERY_S,
            )
            decision = (0.0, 0.0)
        else:
            if self._recorder is not None:
                self._recorder.command(
                    name, self._time_ns, float(msg.linear.x), float(msg.angular.z)
                )
        if lockstep:
            self._barrier.answer(name, decision)
            if self._barrier.complete:
                self._advance(self._barrier.take())
        else:
            self._latest.answer(name, decision)

    def _on_lockstep(self) -> None:
        if self._finished:
            return
        if self._pending_start:
            self._start_episode()
            return
        if self._pending_observe:
            self._pending_observe = False
            self._observe()
            return
        now = time.monotonic()
        late = self._barrier.waiting
        action = self._barrier.poll(now)
        if action == "timeout":
            self.get_logger().warning(
                f"no cmd_vel from {', '.join(late)} within {self._answer_timeout} s; "
                "holding still this period",
                throttle_duration_sec=WARN_EVERY_S,
            )
            self._advance(self._barrier.take())
        elif action == "resend":
            for name in late:
                r = self._by_name[name]
                if r.last_scan is not None and r.last_odom is not None:
                    r.scan_pub.publish(r.last_scan)
                    r.odom_pub.publish(r.last_odom)
            waited = self._barrier.waited(now)
            if waited > WARN_EVERY_S:
                self.get_logger().warning(
                    f"waiting {waited:.0f} s for cmd_vel from {', '.join(late)}"
                    " (is its planner running, on sim time?)",
                    throttle_duration_sec=WARN_EVERY_S,
                )

    def _on_tick(self) -> None:
        if self._finished:
            return
        if self._pending_start:
            self._start_episode()
            return
        if self._sim.done:
            return
        decisions, missing = self._latest.take(self._sim.active)
        if missing:
            self.get_logger().warning(
                f"no cmd_vel from {', '.join(missing)} this period; holding still",
                throttle_duration_sec=WARN_EVERY_S,
            )
        self._advance(decisions)

    def _on_reset(self, request: Trigger.Request, response: Trigger.Response) -> Trigger.Response:
        if self._finished:
            response.success = False
            response.message = f"all {self._episodes_limit} episodes are done"
            return response
        cut = list(self._sim.active)
        for name in cut:  # a reset ends the robots still driving: out of time
            self._publish_event(name, "timed_out", self._sim.state(name).scenario)
        self._barrier.clear()
        self._latest.clear()
        if cut:
            self._publish_final_odometry(cut)
            self._sim.start([])  # nothing drives until the next episode starts
            self._episodes_done += 1
            if self._episodes_limit and self._episodes_done >= self._episodes_limit:
                self.save_recording()
                self._finished = True
                response.success = True
                response.message = f"episode {self._episode} ended; all episodes are done"
                return response
        # started by the next timer tick, so that commands still in flight find nothing
        # waiting for them and are dropped
        self._pending_start = True
        response.success = True
        response.message = f"starting episode {self._episode + 1}"
        return response

    # ------------------------------------------------------------------ recording

    def save_recording(self) -> None:
        """Write the episode bag now (once; ``record`` unset: nothing)."""
        if self._recorder is None or self._saved:
            return
        self._saved = True
        try:
            self._recorder.save(
                self._record,
                self._robots[0].profile,
                {**self._record_note, "node": NODE_NAME, "real_time_factor": self._rtf},
                overwrite=True,
            )
        except (OSError, ValueError) as err:
            self.get_logger().error(f"{self._record}: recording not written: {err}")
        else:
            n = self._recorder.n_episodes
            self.get_logger().info(f"recorded {n} episodes: {self._record}")

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

