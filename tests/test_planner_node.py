"""The planner node in a real rclpy graph: the trainer's decisions, once per observation; zero
Twists on stale or missing data; one-line errors for a corrupt genome or an unknown profile;
the genome run as its deployment (``deployment``, ``deployment_set``) through the same stages
as the planner in process."""

from __future__ import annotations

import json
import math
import time
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from builtin_interfaces.msg import Time
from geometry_msgs.msg import PoseStamped, Twist, TwistStamped
from memory_support import latch
from nav_msgs.msg import OccupancyGrid as OccupancyGridMsg
from nav_msgs.msg import Odometry
from nav_msgs.msg import Path as PathMsg
from rclpy.parameter import Parameter
from rclpy.qos import qos_profile_sensor_data
from ros_support import REGRESSION, Graph, params, run_executable
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import LaserScan
from std_msgs.msg import String
from visualization_msgs.msg import MarkerArray

from mentor_core.controller.collision_guard import CollisionGuardStage
from mentor_core.controller.rotation_shim import RotationShim
from mentor_core.controller.stage import Stage
from mentor_core.controller.turn_gain import TurnGain
from mentor_core.controller.view_corridor import ViewCorridor
from mentor_core.errors import ConfigError, FileFormatError
from mentor_core.files.genome_file import load_genome_and_metadata, save_genome
from mentor_core.navigation.guide import guide_config
from mentor_core.navigation.scan_map import scan_map_resolution
from mentor_core.runtime.guided_planner import GuidedPlanner
from mentor_core.runtime.planner import GenomePlanner, genome_profile
from mentor_core.runtime.velocity_limits import VelocityLimits, limited_velocity
from mentor_core.runtime.wiring import Wiring, wire_pose
from mentor_core.sim.lidar import LidarSpec, lidar_scan
from mentor_core.sim.planner_settings import with_planner
from mentor_core.sim.pymunk_world import PymunkWorld
from mentor_core.sim.robots import get_profile
from mentor_core.sim.scan_adapter import LidarMount, readings_from_scan
from mentor_core.sim.transforms import Transform2D
from mentor_core.sim.world import World
from mentor_planner_node.conversions import path_msg
from mentor_planner_node.planner import QOS_COMMAND, QOS_EVENTS, QOS_LATCHED, PlannerNode
from mentor_sim_node import conversions as sim_conv

pytestmark = pytest.mark.ros

SWARM = get_profile("swarm")
GENOME = REGRESSION / "swarm_reference_genome.json"
NS = "/robot_0"



class Robot:
    """The test's side of one robot: publishes what the simulator would, hears cmd_vel."""

    def __init__(self, graph: Graph, stamped: bool = False) -> None:
        self.node = graph.probe("fake_sim")
        self.scan = self.node.create_publisher(LaserScan, f"{NS}/scan", qos_profile_sensor_data)
        self.odom = self.node.create_publisher(Odometry, f"{NS}/odom", qos_profile_sensor_data)
        self.goal = self.node.create_publisher(PoseStamped, f"{NS}/goal", QOS_LATCHED)
        self.clock = self.node.create_publisher(Clock, "/clock", 10)
        self.commands: list[Twist] = []
        # one process holds a topic of one type only: a stamped cmd_vel is heard as such
        self.stamped: list[TwistStamped] = []
        kind, heard = (TwistStamped, self.stamped) if stamped else (Twist, self.commands)
        self.node.create_subscription(kind, f"{NS}/cmd_vel", heard.append, QOS_COMMAND)

    def observe(self, t_ns: int, ranges: list[float], pose: tuple[float, float, float]) -> None:
        stamp = sim_conv.time_from_ns(t_ns)
        self.scan.publish(sim_conv.laser_scan_from_ranges(ranges, SWARM, stamp, "b"))
        self.odom.publish(sim_conv.odometry_from_pose(pose, (0.0, 0.0), stamp, "robot_0"))

    def tick(self, t_ns: int) -> None:
        self.clock.publish(Clock(clock=sim_conv.time_from_ns(t_ns)))


def _planner(graph: Graph, **values: Any) -> PlannerNode:
    """The node under test; ``deployment_set``, a list of strings, is a string array. Its
    frames come from the parameters (the test publishes no TF)."""
    values = {"genome": str(GENOME), "profile": "swarm", "use_sim_time": True, "use_tf": False,
              **values}
    return graph.add(PlannerNode(context=graph.context, namespace=NS,
                                 parameter_overrides=params(**values)))


def _reference(*stages: Stage) -> GenomePlanner:
    """The regression genome's planner in process through ``stages``, built without a
    deployment."""
    genome, _ = load_genome_and_metadata(GENOME)
    return GenomePlanner(genome, genome_profile(GENOME, "swarm"), str(GENOME), stages=stages)


def _one_line_refusal(graph: Graph, key: str, **values: Any) -> None:
    """The node refuses ``values`` with one ConfigError line naming the deployment's ``key``."""
    with pytest.raises(ConfigError, match=key.replace(".", r"\.") + ": ") as err:
        _planner(graph, **values)
    assert "\n" not in str(err.value)


def test_answers_each_observation_once_with_the_trainers_decision(graph: Graph) -> None:
    planner = _planner(graph)
    robot = Robot(graph)
    reference = GenomePlanner.load(GENOME, "swarm")
    robot.goal.publish(sim_conv.pose_stamped_from_goal((3.0, 2.5), Time()))
    observations = [
        ([0.31, math.inf, 0.45], (1.0, 1.0, 0.3)),
        ([math.inf, math.inf, math.inf], (1.02, 1.05, 0.9)),
        ([0.05, 0.2, 0.599], (2.0, 0.5, -2.0)),
    ]
    for k, (ranges, pose) in enumerate(observations):
        # repeat each observation until answered: the subscriptions may still be matching
        assert graph.spin_until(
            lambda k=k, ranges=ranges, pose=pose: robot.observe(k * 10**9, ranges, pose)
            or len(robot.commands) > k,
        )
        graph.spin_for(0.1)  # repeats of the same stamp must not be answered again
        assert len(robot.commands) == k + 1
        got = robot.commands[k]
        ranges_wire = [float(np.float32(r)) for r in ranges]
        vx, wz = reference.command(ranges_wire, pose, (3.0, 2.5))
        assert (got.linear.x, got.angular.z) == (vx, wz)
        assert (got.linear.y, got.linear.z, got.angular.x, got.angular.y) == (0, 0, 0, 0)
    assert planner.decisions == 3 and planner.zero_commands == 0


def test_missing_or_stale_data_gives_a_zero_twist_and_a_warning(
    graph: Graph, capfd: pytest.CaptureFixture[str]
) -> None:
    # two decisions in the genome's period of 1 s: stale after 3 periods, 1.5 wall s
    planner = _planner(graph, deployment_set=["decisions_per_period=2"])
    assert planner.control_period == 0.5
    robot = Robot(graph)
    t = 0
    began = time.monotonic()

    def advance() -> bool:
        nonlocal t
        t += 250_000_000
        robot.tick(t)
        return bool(robot.commands)

    robot.goal.publish(sim_conv.pose_stamped_from_goal((3.0, 2.5), Time()))
    assert graph.spin_until(advance)  # a goal, sim time passes, no data at all
    assert all(c.linear.x == 0.0 and c.angular.z == 0.0 for c in robot.commands)
    assert planner.zero_commands >= 1 and planner.decisions == 0
    assert time.monotonic() - began > 1.5  # not before stale_timeout (3 control periods)
    # data arrives: real decisions; then it stops coming: zero Twists again
    assert graph.spin_until(lambda: robot.observe(t, [0.3] * 3, (1.0, 1.0, 0.0))
                            or planner.decisions == 1)
    assert graph.spin_until(lambda: any(c.linear.x > 0.0 for c in robot.commands))
    answer = next(k for k, c in enumerate(robot.commands) if c.linear.x > 0.0)
    assert graph.spin_until(lambda: advance() and len(robot.commands) >= answer + 4)
    assert all(c == Twist() for c in robot.commands[answer + 1 :])
    # the warning names the fault and is throttled: one line for many zero Twists
    err = capfd.readouterr().err
    assert err.count("watchdog: no scan, odometry received: sending a zero Twist") == 1
    assert err.count("sending a zero Twist") < planner.zero_commands


def test_the_watchdog_stops_the_robot_when_sim_time_stops(
    graph: Graph, capfd: pytest.CaptureFixture[str]
) -> None:
    """Failed before: with use_sim_time and the simulator gone, the watchdog ran on the stopped
    sim clock: no zero Twist and no warning for as long as one waited."""
    planner = _planner(graph, deployment_set=["decisions_per_period=2"])  # 0.5 s periods
    robot = Robot(graph)
    robot.tick(5 * 10**9)
    robot.goal.publish(sim_conv.pose_stamped_from_goal((3.0, 2.5), Time()))
    assert graph.spin_until(lambda: robot.observe(5 * 10**9, [0.3] * 3, (1.0, 1.0, 0.0))
                            or planner.decisions == 1)
    began = time.monotonic()  # the simulator dies: no clock, no data any more
    assert graph.spin_until(lambda: planner.zero_commands > 0, timeout=5.0)
    # the scans stopped: stale after a few of their intervals, within stale_timeout (1.5 s)
    assert time.monotonic() - began < 1.5 + 0.5
    assert graph.spin_until(lambda: robot.commands[-1] == Twist(), timeout=2.0)
    assert "watchdog: no scan for" in capfd.readouterr().err


def test_nan_scan_is_rejected_and_the_node_keeps_running(
    graph: Graph, capfd: pytest.CaptureFixture[str]
) -> None:
    planner = _planner(graph)
    robot = Robot(graph)
    robot.goal.publish(sim_conv.pose_stamped_from_goal((3.0, 2.5), Time()))
    # the simulator's per-sensor scan with a NaN (a lidar's NaN is "no measurement", REP-117)
    bad = sim_conv.laser_scan_from_ranges([0.1, 0.3, 0.2], SWARM, sim_conv.time_from_ns(0), "b")
    bad.ranges[1] = math.nan

    seen = ""

    def send_bad() -> bool:
        nonlocal seen
        robot.scan.publish(bad)
        robot.odom.publish(sim_conv.odometry_from_pose((1.0, 1.0, 0.0), (0, 0), Time(), "r"))
        seen += capfd.readouterr().err
        return "scan refused: scan holds a NaN range: stopping" in seen and bool(robot.commands)

    assert graph.spin_until(send_bad)
    assert planner.decisions == 0 and all(c == Twist() for c in robot.commands)
    assert graph.spin_until(lambda: robot.observe(10**9, [0.3] * 3, (1.0, 1.0, 0.0))
                            or planner.decisions == 1)


def _lidar_robot_scan(t_ns: int, ranges: Any) -> LaserScan:
    """A 360-ray lidar scan at the body centre (Gazebo's TurtleBot3 publishes such)."""
    scan = LaserScan()
    scan.header.stamp = sim_conv.time_from_ns(t_ns)
    scan.header.frame_id = "robot_0/lidar"
    scan.angle_min, scan.angle_increment = -math.pi, 2 * math.pi / 360
    scan.range_min, scan.range_max = 0.12, 3.5
    scan.ranges = [float(r) for r in ranges]
    return scan


@pytest.mark.parametrize("bad", ["nan", "zero"])
def test_a_lidar_scan_of_invalid_ranges_stops_the_robot_with_a_line(
    graph: Graph, capfd: pytest.CaptureFixture[str], bad: str
) -> None:
    """Failed before: a scan all NaN or all 0.0 read as free space, and the robot drove on
    (issue 56, point 2)."""
    _planner(graph)
    robot = Robot(graph)
    robot.goal.publish(sim_conv.pose_stamped_from_goal((3.0, 2.5), Time()))
    stamp = 0

    def send(ranges: Any) -> None:
        nonlocal stamp
        stamp += 10**8  # a new stamp each time: each is answered
        scan = _lidar_robot_scan(stamp, ranges)
        robot.scan.publish(scan)
        robot.odom.publish(sim_conv.odometry_from_pose((1.0, 1.0, 0.0), (0, 0),
                                                       scan.header.stamp, "r"))  # fmt: skip

    assert graph.spin_until(lambda: send(np.full(360, np.inf)) or bool(robot.commands))
    assert robot.commands[-1].linear.x > 0.0  # free all round: it drives
    value = math.nan if bad == "nan" else 0.0
    seen = ""

    def send_bad() -> bool:
        nonlocal seen
        send(np.full(360, value))
        seen += capfd.readouterr().err
        return "ranges are valid (NaN, or outside [range_min, range_max]" in seen and (
            robot.commands[-1] == Twist())

    assert graph.spin_until(send_bad)
    stopped = len(robot.commands)
    for _ in range(5):  # more of them: still nothing but zero Twists
        send(np.full(360, value))
        graph.spin_for(0.05)
    assert all(c == Twist() for c in robot.commands[stopped:])


def test_when_the_odometry_stops_the_next_command_is_a_zero_twist(
    graph: Graph, capfd: pytest.CaptureFixture[str]
) -> None:
    """Failed before: the last command was sent again until the watchdog's stale_timeout, 1.6 m
    blind at 1 m/s (issue 56, point 2). Scans at 5 Hz, odometry at 30 Hz, then none."""
    planner = _planner(graph, decide_on_timer=True, use_sim_time=False)
    robot = Robot(graph)
    robot.goal.publish(sim_conv.pose_stamped_from_goal((3.0, 2.5), Time()))
    began = time.monotonic_ns()
    sent = 0

    def publish(odometry: bool) -> None:
        nonlocal sent
        t = time.monotonic_ns() - began
        if odometry:
            robot.odom.publish(sim_conv.odometry_from_pose(
                (1.0, 1.0, 0.0), (0, 0), sim_conv.time_from_ns(t), "r"))  # fmt: skip
        if sent % 6 == 0:
            robot.scan.publish(sim_conv.laser_scan_from_ranges(
                [math.inf] * 3, SWARM, sim_conv.time_from_ns(t), "b"))  # fmt: skip
        sent += 1
        graph.spin_for(1 / 30)

    deadline = time.monotonic() + 10.0
    while not (robot.commands and robot.commands[-1].linear.x > 0.0):
        assert time.monotonic() < deadline
        publish(odometry=True)
    moving = len(robot.commands)
    stopped_at = time.monotonic()
    while robot.commands[-1] != Twist():
        assert time.monotonic() - stopped_at < 1.0  # well within stale_timeout (3 s)
        publish(odometry=False)
    assert len(robot.commands) > moving and planner.zero_commands >= 1
    assert "no odometry for" in capfd.readouterr().err


def test_the_robots_limits_scale_the_arc_and_cmd_vel_may_be_stamped(graph: Graph) -> None:
    """A robot slower than the trained one drives the same arc, more slowly; Jazzy's
    diff_drive_controller takes TwistStamped (issue 56, point 3)."""
    limits = VelocityLimits(max_vel_x=0.05, max_vel_theta=0.4)
    _planner(graph, max_vel_x=0.05, max_vel_theta=0.4, cmd_vel_stamped=True)
    robot = Robot(graph, stamped=True)
    stamped = robot.stamped
    robot.goal.publish(sim_conv.pose_stamped_from_goal((3.0, 2.5), Time()))
    ranges, pose = [0.31, math.inf, 0.45], (1.0, 1.0, 0.3)
    assert graph.spin_until(lambda: robot.observe(0, ranges, pose) or bool(stamped))
    wire = [float(np.float32(r)) for r in ranges]
    want = limited_velocity(GenomePlanner.load(GENOME, "swarm").command(wire, pose, (3.0, 2.5)),
                            limits)  # fmt: skip
    got = stamped[0]
    assert (got.twist.linear.x, got.twist.angular.z) == pytest.approx(want, abs=1e-12)
    assert abs(got.twist.linear.x) <= 0.05 + 1e-12 and abs(got.twist.angular.z) <= 0.4 + 1e-12
    assert got.header.frame_id == "robot_0/base_link"  # the odometry's child frame


def test_without_a_genome_every_answer_is_zero(graph: Graph) -> None:
    planner = _planner(graph, genome="")
    robot = Robot(graph)
    robot.goal.publish(sim_conv.pose_stamped_from_goal((3.0, 2.5), Time()))
    assert graph.spin_until(lambda: robot.observe(0, [0.3] * 3, (1.0, 1.0, 0.0))
                            or bool(robot.commands))
    assert robot.commands[0] == Twist() and planner.decisions == 0


def test_bad_genome_or_profile_raises_one_line(graph: Graph, tmp_path: Path) -> None:
    bad = tmp_path / "corrupt.json"
    bad.write_text(GENOME.read_text()[:200])
    with pytest.raises(FileFormatError, match=r"corrupt\.json: ") as err:
        _planner(graph, genome=str(bad))
    assert "\n" not in str(err.value)
    with pytest.raises(ConfigError, match="unknown robot 'tank'"):
        _planner(graph, profile="tank")
    with pytest.raises(ConfigError, match="trained for robot 'swarm', not 'ugv'"):
        _planner(graph, profile="ugv")  # a Swarm-Robot genome on a UGV
    with pytest.raises(FileFormatError, match=r"missing\.json"):
        _planner(graph, genome=str(tmp_path / "missing.json"))


@pytest.mark.parametrize(
    ("args", "fault"),
    [
        (["-p", "genome:={corrupt}", "-p", "profile:=swarm"], "corrupt.json: "),
        (["-p", f"genome:={GENOME}", "-p", "profile:=tank"], "unknown robot 'tank'"),
        (["-p", f"genome:={GENOME}", "-p", "profile:=swarm",
          "-p", "deployment_set:=[stages.turn_gain.gain=1.5]"], "stages.turn_gain.gain: "),
        (["-p", f"genome:={GENOME}", "-p", "profile:=swarm", "-p", "deployment:={corrupt}"],
         "corrupt.json: "),
    ],
)
def test_planner_executable_exits_nonzero_on_bad_input(
    args: list[str], fault: str, tmp_path: Path
) -> None:
    corrupt = tmp_path / "corrupt.json"
    corrupt.write_text("{\"format\": \"mentor-genome\", \"version\": 1, \"nodes\": [")
    rc, err = run_executable(
        "mentor_planner_node", "planner",
        ["--ros-args", *[a.format(corrupt=corrupt) for a in args]],
    )
    assert rc == 2, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("mentor_planner: ") and fault in lines[0], err


# -------------------------------------------------------------------- issue 16


def _answered(graph: Graph, robot: Robot, planner: PlannerNode, k: int, ranges: Any,
              pose: tuple[float, float, float]) -> Twist:
    """Observe at stamp ``k`` s until the planner answers; its answer."""
    assert graph.spin_until(lambda: robot.observe(k * 10**9, ranges, pose)
                            or len(robot.commands) > k)
    return robot.commands[k]


def test_a_planner_with_memory_reads_its_last_answer_and_starts_each_goal_blank(
    graph: Graph, tmp_path: Path
) -> None:
    genome = tmp_path / "latch.json"
    save_genome(latch(with_planner(SWARM, memory_units=1)), genome, metadata={"memory_units": 1})
    planner = _planner(graph, genome=str(genome))
    robot = Robot(graph)
    reference = GenomePlanner.load(genome, "swarm")
    robot.goal.publish(sim_conv.pose_stamped_from_goal((3.0, 2.5), Time()))
    pose = (1.0, 1.0, 0.0)
    seen = [[0.31, 0.5, 0.45], [0.12, 0.4, 0.2], [0.55, 0.1, 0.3]]
    wire = [[float(np.float32(r)) for r in ranges] for ranges in seen]
    previous = [0.0] + [ranges[0] for ranges in wire]  # the memory each answer reads
    for k, ranges in enumerate(seen):
        got = _answered(graph, robot, planner, k, ranges, pose)
        graph.spin_for(0.1)  # repeats (as lockstep resends) are not answered, nor remembered
        assert len(robot.commands) == k + 1
        # the turn reads the first reading of the answer before (a full right turn at first)
        assert got.angular.z == math.pi * (2.0 * previous[k] - 1.0)
        assert (got.linear.x, got.angular.z) == reference.command(wire[k], pose, (3.0, 2.5))
    # a new goal: the same observation answered again, from a blank memory
    robot.goal.publish(sim_conv.pose_stamped_from_goal((2.0, 3.0), Time()))
    assert graph.spin_until(lambda: len(robot.commands) > len(seen))
    assert robot.commands[-1].angular.z == -math.pi


def test_a_goal_from_a_plain_publisher_on_goal_pose_is_taken(graph: Graph) -> None:
    """Failed before: a volatile publisher matched no subscription (incompatible QoS), and
    nothing listened on /goal_pose."""
    planner = _planner(graph)
    robot = Robot(graph)
    rviz = graph.probe("rviz").create_publisher(PoseStamped, "/goal_pose", 10)
    assert graph.spin_until(lambda: rviz.get_subscription_count() >= 1)
    rviz.publish(sim_conv.pose_stamped_from_goal((3.0, 2.5), Time()))
    got = _answered(graph, robot, planner, 0, [0.3] * 3, (1.0, 1.0, 0.0))
    want = GenomePlanner.load(GENOME, "swarm").command([np.float32(0.3)] * 3, (1.0, 1.0, 0.0),
                                                       (3.0, 2.5))
    assert (got.linear.x, got.angular.z) == want
    # and from a plain publisher on the robot's own goal topic
    plain = graph.probe("user").create_publisher(PoseStamped, "/robot_0/goal", 10)
    assert graph.spin_until(lambda: plain.get_subscription_count() >= 1)
    plain.publish(sim_conv.pose_stamped_from_goal((2.0, 3.0), Time()))
    assert graph.spin_until(lambda: planner.gate.goal == (2.0, 3.0))


def test_a_goal_outside_the_arena_is_refused(
    graph: Graph, capfd: pytest.CaptureFixture[str]
) -> None:
    """Failed before: a goal at (2, 30) outside a 12 m arena was accepted silently."""
    planner = _planner(graph)
    robot = Robot(graph)
    arena = graph.probe("sim_markers").create_publisher(MarkerArray, "/mentor/obstacles",
                                                        QOS_LATCHED)
    arena.publish(sim_conv.markers_from_world(World(12.0)))
    assert graph.spin_until(lambda: planner.arena is not None)
    robot.goal.publish(sim_conv.pose_stamped_from_goal((2.0, 30.0), Time()))
    assert graph.spin_until(lambda: "outside the known area" in capfd.readouterr().err)
    graph.spin_for(0.2)
    robot.observe(0, [0.3] * 3, (1.0, 1.0, 0.0))
    graph.spin_for(0.3)
    assert planner.gate.goal is None and not robot.commands
    robot.goal.publish(sim_conv.pose_stamped_from_goal((3.0, 2.5), Time()))
    _answered(graph, robot, planner, 0, [0.3] * 3, (1.0, 1.0, 0.0))


def test_any_lidar_scan_is_read_from_its_mount(graph: Graph) -> None:
    """Failed before: a scan of another ray count than the profile's sensors was refused."""
    mount = Transform2D(0.02, -0.01, 0.3)
    _planner(graph, lidar_mount=list(mount.as_tuple()))
    robot = Robot(graph)
    world = World(4.0, np.array([[1.5, 0.8, 1.7, 1.6]]))
    pose = (1.0, 1.0, 0.2)
    physics = PymunkWorld(world, SWARM)
    physics.add_robot("r", pose)
    spec = LidarSpec(360, range_max=3.0, mount=mount)
    scan = sim_conv.lidar_scan(lidar_scan(physics, "r", spec), spec, Time(), "robot_0/lidar")
    robot.goal.publish(sim_conv.pose_stamped_from_goal((3.0, 2.5), Time()))

    def observe() -> bool:
        robot.scan.publish(scan)
        robot.odom.publish(sim_conv.odometry_from_pose(pose, (0.0, 0.0), Time(), "robot_0"))
        return bool(robot.commands)

    assert graph.spin_until(observe)
    data = Wiring(lidar=spec).scan_data(lidar_scan(physics, "r", spec))  # float32 fields
    readings = readings_from_scan(data, LidarMount(mount), SWARM).readings
    assert np.isfinite(readings[1])  # the box ahead is seen
    want = GenomePlanner.load(GENOME, "swarm").command(readings, wire_pose(pose), (3.0, 2.5))
    assert (robot.commands[0].linear.x, robot.commands[0].angular.z) == want


def test_goals_in_any_linked_frame_are_turned_into_the_odometry_frame(graph: Graph) -> None:
    """Failed before: odometry was taken to be in map, a goal in another frame refused."""
    offset = Transform2D(0.5, -0.25, 0.4)
    planner = _planner(graph, map_to_odom=list(offset.as_tuple()))
    robot = Robot(graph)
    reference = GenomePlanner.load(GENOME, "swarm")
    pose = (1.0, 1.0, 0.0)  # in odom
    goal_map = (3.0, 2.5)
    robot.goal.publish(sim_conv.pose_stamped_from_goal(goal_map, Time()))
    got = _answered(graph, robot, planner, 0, [0.3] * 3, pose)
    goal_odom = offset.inverse().apply_point(goal_map)
    assert (got.linear.x, got.angular.z) == reference.command([np.float32(0.3)] * 3, pose,
                                                              goal_odom)
    # a goal 0.4 m ahead of the robot, in its body frame
    ahead = sim_conv.pose_stamped_from_goal((0.4, 0.0), Time())
    ahead.header.frame_id = "robot_0/base_link"
    robot.goal.publish(ahead)
    assert graph.spin_until(lambda: planner.gate.goal is not None
                            and planner.gate.goal[0] == pytest.approx(1.4))
    unknown = sim_conv.pose_stamped_from_goal((1.0, 1.0), Time())
    unknown.header.frame_id = "world"
    robot.goal.publish(unknown)
    graph.spin_for(0.2)
    assert planner.gate.goal == pytest.approx((1.4, 1.0))  # refused: kept the last one


def test_the_goal_radius_changes_at_run_time_and_a_reached_goal_stops_the_robot(
    graph: Graph,
) -> None:
    planner = _planner(graph)
    robot = Robot(graph)
    assert planner.goal_radius == SWARM.goal_radius
    result = planner.set_parameters([Parameter("goal_radius", value=1.0)])
    assert result[0].successful and planner.goal_radius == 1.0
    assert not planner.set_parameters([Parameter("goal_radius", value=-1.0)])[0].successful
    assert not planner.set_parameters([Parameter("profile", value="ugv")])[0].successful
    robot.goal.publish(sim_conv.pose_stamped_from_goal((1.5, 1.5), Time()))
    assert graph.spin_until(lambda: planner.gate.goal is not None)
    got = _answered(graph, robot, planner, 0, [0.3] * 3, (1.0, 1.0, 0.0))  # 0.71 m away
    assert got == Twist() and planner.goals_reached == 1 and planner.gate.goal is None
    # then the node is quiet (it would fight a teleoperator): no repeats, no watchdog zeros,
    # though the data keeps coming and then stops (issue 56, point 3)
    sent = len(robot.commands)
    for k in range(1, 4):
        robot.observe(k * 10**9, [0.3] * 3, (1.0, 1.0, 0.0))
        graph.spin_for(0.2)
    graph.spin_for(1.0)
    assert len(robot.commands) == sent


def test_a_timer_node_stops_repeating_once_its_goal_is_reached(graph: Graph) -> None:
    planner = _planner(graph, decide_on_timer=True, use_sim_time=False, goal_radius=1.0)
    robot = Robot(graph)
    robot.goal.publish(sim_conv.pose_stamped_from_goal((1.5, 1.5), Time()))
    assert graph.spin_until(lambda: planner.gate.goal is not None)
    assert graph.spin_until(lambda: robot.observe(0, [0.3] * 3, (1.0, 1.0, 0.0))
                            or planner.goals_reached == 1)  # fmt: skip
    assert graph.spin_until(lambda: bool(robot.commands))
    graph.spin_for(0.3)  # the one zero Twist arrives
    sent = len(robot.commands)
    graph.spin_for(1.0)  # ten repeats' worth at 10 Hz
    assert len(robot.commands) == sent and robot.commands[-1] == Twist()


def test_behind_a_rotation_shim_the_node_turns_onto_a_goal_behind_it_first(
    graph: Graph,
) -> None:
    planner = _planner(graph, deployment_set=["stages.rotation_shim.threshold_deg=45"])
    assert planner.planner is not None
    assert planner.planner.stages == (RotationShim(threshold_deg=45.0),)
    robot = Robot(graph)
    reference = _reference(RotationShim(threshold_deg=45.0))
    robot.goal.publish(sim_conv.pose_stamped_from_goal((1.0, 1.0), Time()))
    pose = (2.0, 1.0, 0.0)  # the goal straight behind
    assert graph.spin_until(lambda: robot.observe(10**9, [0.5, 0.5, 0.5], pose)
                            or len(robot.commands) > 0)  # fmt: skip
    got = robot.commands[0]
    assert (got.linear.x, got.angular.z) == reference.command([0.5, 0.5, 0.5], pose, (1.0, 1.0))
    # a turn on the spot onto the goal (this genome may turn a half turn a decision)
    limit = planner.planner.profile.heading_change_max
    assert got.linear.x == pytest.approx(SWARM.step_min / SWARM.control_period)
    assert abs(got.angular.z) == pytest.approx(min(math.pi, limit) / SWARM.control_period)


def test_behind_a_collision_guard_the_node_backs_out_of_a_wedge(
    graph: Graph, tmp_path: Path
) -> None:
    # the reference genome's body 5 mm before a wall it faces (x = 5 m; readings of a wall
    # there): its own decision sweeps a corner into the wall, the guard backs it up instead
    deployment = tmp_path / "guarded.yaml"
    deployment.write_text("stages:\n  collision_guard: {memory: 3}\n")
    planner = _planner(graph, deployment=str(deployment))
    assert planner.planner is not None
    assert planner.planner.stages == (CollisionGuardStage(memory=3),)
    robot = Robot(graph)
    reference = _reference(CollisionGuardStage(memory=3))
    robot.goal.publish(sim_conv.pose_stamped_from_goal((3.0, 9.0), Time()))
    pose = (5.0 - 0.5 * SWARM.length - 0.005, 3.0, 0.0)
    ranges = [0.005 * math.sqrt(2.0), 0.005, 0.005 * math.sqrt(2.0)]
    got = _answered(graph, robot, planner, 0, ranges, pose)
    wire = [float(np.float32(r)) for r in ranges]
    assert (got.linear.x, got.angular.z) == reference.command(wire, pose, (3.0, 9.0))
    assert got.linear.x < 0.0 and got.angular.z == 0.0
    unguarded = GenomePlanner.load(GENOME, "swarm").command(wire, pose, (3.0, 9.0))
    assert unguarded[0] > 0.0


def test_along_a_given_path_the_node_decides_in_map_through_map_to_odom(graph: Graph) -> None:
    """Failed before: the node steered along a path in ``map`` from the odometry's pose, as if
    ``odom`` were ``map``; a localiser's ``map -> odom`` then put the robot elsewhere on it."""
    planner = _planner(graph, global_plan=True, map_topic="/no_map_here", use_tf=False,
                       map_to_odom=[1.0, 0.5, 0.3])  # fmt: skip
    robot = Robot(graph)
    give = robot.node.create_publisher(PathMsg, f"{NS}/plan", 1)
    points = np.array([(1.0, 1.0), (3.0, 1.0), (3.0, 3.0)])  # in map
    assert graph.spin_until(lambda: give.get_subscription_count() > 0)
    give.publish(path_msg(points, Time()))
    assert graph.spin_until(lambda: planner.global_plan is not None and planner.global_plan.ready)
    robot.goal.publish(sim_conv.pose_stamped_from_goal((3.0, 3.0), Time()))  # in map
    pose = (0.4, 0.1, -0.2)  # in odom
    got = _answered(graph, robot, planner, 0, [0.5, 0.5, 0.5], pose)
    to_map = Transform2D(1.0, 0.5, 0.3)
    reference = GuidedPlanner(GenomePlanner.load(GENOME, "swarm"), guide_config(SWARM))
    reference.set_path(points)
    dtheta, ds = reference.decide([0.5, 0.5, 0.5], to_map.apply_pose(pose), (3.0, 3.0))
    period = planner.control_period
    assert (got.linear.x, got.angular.z) == pytest.approx((ds / period, dtheta / period))
    # the carrot was taken from where the robot stands in map
    assert planner.global_plan.planner.guide.carrot == pytest.approx(  # type: ignore[union-attr]
        reference.guide.carrot)


def test_a_scan_map_of_size_0_covers_the_arena_in_the_odometry_frame(graph: Graph) -> None:
    planner = _planner(graph, deployment_set=["scan_map={}"], use_tf=False,
                       map_to_odom=[1.0, 0.5, math.pi / 2])  # fmt: skip
    assert planner.global_plan is not None and not planner.global_plan.ready
    arena = graph.probe("sim_markers").create_publisher(MarkerArray, "/mentor/obstacles",
                                                        QOS_LATCHED)  # fmt: skip
    arena.publish(sim_conv.markers_from_world(World(4.0)))
    assert graph.spin_until(lambda: planner.global_plan.ready)  # type: ignore[union-attr]
    scan = planner.global_plan.planner.scan.map  # type: ignore[union-attr]
    # odom sits at (1, 0.5) in map, turned a quarter: map's [0, 4]^2 is [-0.5, 3.5] x [-3, 1]
    assert scan.origin == pytest.approx((-0.5, -3.0))
    assert scan.hits.shape[0] * scan.resolution == pytest.approx(4.0)


@pytest.mark.parametrize("cell", [None, 0.1])
def test_the_scan_maps_cell_is_the_profiles_unless_given(
    graph: Graph, cell: float | None
) -> None:
    setting = "scan_map={}" if cell is None else f"scan_map.resolution={cell}"
    planner = _planner(graph, deployment_set=[setting], scan_map_size=4.0)
    guide = planner.global_plan.planner.scan  # type: ignore[union-attr]
    want = cell or scan_map_resolution(get_profile("swarm"))
    assert guide.map.resolution == want and guide.guide.config.resolution == want
    assert guide.map.hits.shape == (round(4.0 / want),) * 2


@pytest.mark.parametrize(("cost", "want"), [(None, 1.0), (0.0, 0.0), (2.0, 2.0)])
def test_the_scan_map_plans_clearance_cost_is_the_robots_unless_given(
    graph: Graph, cost: float | None, want: float
) -> None:
    setting = "scan_map={}" if cost is None else f"scan_map.clearance_cost={cost}"
    planner = _planner(graph, deployment_set=[setting], scan_map_size=4.0)
    guide = planner.global_plan.planner.scan  # type: ignore[union-attr]
    assert guide.guide.config.clearance_cost == want  # the Swarm-Robot's: 1
    assert guide.guide.planner is not None
    assert guide.guide.planner.clearance_cost == want


@pytest.mark.parametrize(
    ("setting", "key"),
    [("scan_map.resolution=0", "scan_map.resolution"),
     ("scan_map.clearance_cost=-1", "scan_map.clearance_cost"),
     ("scan_map.lookahead=-0.5", "scan_map.lookahead"),
     ("scan_map.cell=0.1", "scan_map.cell")],
)  # fmt: skip
def test_a_bad_scan_map_setting_is_refused_in_one_line(
    graph: Graph, setting: str, key: str
) -> None:
    _one_line_refusal(graph, key, deployment_set=[setting], scan_map_size=4.0)


@pytest.mark.parametrize("keep", [False, True])
def test_a_kept_scan_map_lasts_across_goals_until_an_episode_starts(
    graph: Graph, keep: bool
) -> None:
    planner = _planner(graph, deployment_set=["scan_map={}"], scan_map_size=4.0,
                       scan_map_keep=keep)  # fmt: skip
    robot = Robot(graph)
    events = graph.probe("sim_events").create_publisher(String, f"{NS}/events", QOS_EVENTS)
    maps: list[OccupancyGridMsg] = []
    graph.probe("rviz").create_subscription(OccupancyGridMsg, f"{NS}/scan_map", maps.append,
                                            QOS_LATCHED)  # fmt: skip
    assert planner.global_plan is not None and planner.global_plan.ready  # sized: no arena
    robot.goal.publish(sim_conv.pose_stamped_from_goal((3.0, 2.5), Time()))
    _answered(graph, robot, planner, 0, [0.3, 0.2, 0.3], (1.0, 1.0, 0.0))  # a wall ahead
    scan = planner.global_plan.planner.scan  # type: ignore[union-attr]
    assert (scan.map.data == 100).sum() == 3
    assert graph.spin_until(lambda: bool(maps))  # published with the first plan, in odom
    assert maps[-1].header.frame_id == "odom" and list(maps[-1].data).count(100) == 3

    robot.goal.publish(sim_conv.pose_stamped_from_goal((2.0, 3.0), Time()))  # the next goal
    # (decisions, not commands: on a slow machine the watchdog may have sent a zero Twist)
    assert graph.spin_until(lambda: planner.decisions > 1)
    kept = planner.global_plan.planner.scan  # type: ignore[union-attr]
    # the same scan answered for the new goal: read once more into the kept map, or once
    # into a new one
    assert (kept is scan) == keep and kept.map.hits.sum() == (6 if keep else 3)
    events.publish(sim_conv.event_string("started", 0, 2 * 10**9, (2.0, 3.0)))  # an episode
    assert graph.spin_until(lambda: robot.observe(2 * 10**9, [math.inf] * 3, (1.0, 1.0, 0.0))
                            or planner.decisions > 2)  # fmt: skip
    fresh = planner.global_plan.planner.scan  # type: ignore[union-attr]
    assert fresh is not scan and not (fresh.map.data == 100).any()


def test_a_genome_that_decides_twice_a_second_sets_the_nodes_period(
    graph: Graph, tmp_path: Path
) -> None:
    """Its metadata's ``control_period`` is the node's default: a Twist then stands for
    0.5 s of driving, as the genome was trained."""
    doc = json.loads(GENOME.read_text())
    doc["metadata"] |= {"heading_change_max": math.pi / 4, "step_max": 0.04,
                        "control_period": 0.5}  # fmt: skip
    fast = tmp_path / "fast.json"
    fast.write_text(json.dumps(doc))
    planner = _planner(graph, genome=str(fast))
    assert planner.control_period == 0.5
    robot = Robot(graph)
    reference = GenomePlanner.load(fast, "swarm")
    robot.goal.publish(sim_conv.pose_stamped_from_goal((1.0, 1.0), Time()))
    pose = (1.4, 1.1, 2.0)
    assert graph.spin_until(lambda: robot.observe(10**9, [0.5, 0.5, 0.5], pose)
                            or len(robot.commands) > 0)  # fmt: skip
    got = robot.commands[0]
    dtheta, ds = reference.decide([0.5, 0.5, 0.5], pose, (1.0, 1.0))
    assert (got.linear.x, got.angular.z) == pytest.approx((ds / 0.5, dtheta / 0.5))


def test_a_rotation_shim_beyond_a_half_turn_is_refused(graph: Graph) -> None:
    _one_line_refusal(graph, "stages.rotation_shim.threshold_deg",
                      deployment_set=["stages.rotation_shim.threshold_deg=270"])  # fmt: skip


def test_with_a_turn_gain_the_node_answers_as_the_planner_with_that_gain(graph: Graph) -> None:
    # the string array as rclpy types it explicitly (``_planner`` lets rclpy infer it)
    typed = Parameter("deployment_set", Parameter.Type.STRING_ARRAY,
                      ["stages.turn_gain.gain=0.75"])  # fmt: skip
    planner = graph.add(PlannerNode(
        context=graph.context, namespace=NS,
        parameter_overrides=[*params(genome=str(GENOME), profile="swarm", use_sim_time=True,
                                     use_tf=False), typed],
    ))  # fmt: skip
    assert planner.planner is not None
    assert planner.planner.stages == (TurnGain(gain=0.75),)
    robot = Robot(graph)
    reference = _reference(TurnGain(gain=0.75))
    robot.goal.publish(sim_conv.pose_stamped_from_goal((1.0, 1.0), Time()))
    pose = (1.4, 1.1, 2.0)
    assert graph.spin_until(lambda: robot.observe(10**9, [0.5, 0.5, 0.5], pose)
                            or len(robot.commands) > 0)  # fmt: skip
    got = robot.commands[0]
    assert (got.linear.x, got.angular.z) == reference.command([0.5, 0.5, 0.5], pose, (1.0, 1.0))


@pytest.mark.parametrize("gain", ["0", "1.5", "fast"])
def test_a_turn_gain_outside_zero_to_one_is_refused(graph: Graph, gain: str) -> None:
    _one_line_refusal(graph, "stages.turn_gain.gain",
                      deployment_set=[f"stages.turn_gain.gain={gain}"])  # fmt: skip


def test_with_a_view_margin_the_node_answers_as_the_planner_with_that_corridor(
    graph: Graph,
) -> None:
    """The readings beside the way to the goal read as nothing seen, as in the episodes;
    the command differs from the plain planner's."""
    planner = _planner(graph, deployment_set=["stages.view_corridor.margin=0.1"])
    assert planner.planner is not None
    assert planner.planner.stages == (ViewCorridor(margin=0.1),)
    robot = Robot(graph)
    reference = _reference(ViewCorridor(margin=0.1))
    robot.goal.publish(sim_conv.pose_stamped_from_goal((1.0, 1.0), Time()))
    pose, readings = (1.4, 1.1, 2.0), [0.5, 0.5, 0.5]
    assert graph.spin_until(lambda: robot.observe(10**9, readings, pose)
                            or len(robot.commands) > 0)  # fmt: skip
    got = robot.commands[0]
    expected = reference.command(readings, pose, (1.0, 1.0))
    assert (got.linear.x, got.angular.z) == expected
    assert expected != _reference().command(readings, pose, (1.0, 1.0))


def test_without_a_deployment_the_node_keeps_the_stages_the_genome_was_trained_with(
    graph: Graph, tmp_path: Path
) -> None:
    """The regression genome was trained without a corridor: it runs without one. A genome
    trained with one (metadata ``view_margin``) keeps it, unless the deployment sets its own."""
    planner = _planner(graph)
    assert planner.planner is not None and planner.planner.stages == ()
    doc = json.loads(GENOME.read_text())
    doc["metadata"]["view_margin"] = 0.2
    viewed = tmp_path / "viewed.json"
    viewed.write_text(json.dumps(doc))
    trained = _planner(graph, genome=str(viewed), goal_pose_topic="")
    assert trained.planner is not None
    assert trained.planner.stages == (ViewCorridor(margin=0.2),)
    replaced = _planner(graph, genome=str(viewed), goal_pose_topic="",
                        deployment_set=["stages.view_corridor.margin=0.1"])  # fmt: skip
    assert replaced.planner is not None
    assert replaced.planner.stages == (ViewCorridor(margin=0.1),)


@pytest.mark.parametrize("margin", ["-0.1", "0"])
def test_a_negative_or_zero_view_margin_is_refused(graph: Graph, margin: str) -> None:
    _one_line_refusal(graph, "stages.view_corridor.margin",
                      deployment_set=[f"stages.view_corridor.margin={margin}"])  # fmt: skip


def test_the_shipped_deployment_runs_the_shipped_stages_at_half_the_period(
    graph: Graph,
) -> None:
    """``deployment: shipped`` runs the Swarm-Robot's shipped stages (view corridor, gain on
    the turn, rotation shim, collision guard) at two decisions a trained period, on a scan map
    whose plan keeps clear of what was read."""
    planner = _planner(graph, deployment="shipped", scan_map_size=4.0)
    assert planner.planner is not None
    assert planner.planner.stages == (
        ViewCorridor(margin=0.1), TurnGain(gain=0.75), RotationShim(threshold_deg=45.0),
        CollisionGuardStage(memory=3))  # fmt: skip
    assert planner.control_period == planner.planner.profile.control_period == 0.5
    guide = planner.global_plan.planner.scan  # type: ignore[union-attr]
    assert guide.guide.config.clearance_cost == 1.0
