"""The simulator node in a real rclpy graph: topics, QoS, sim time, lockstep and real-time
stepping, the reset service, recording, and bad input (bags, worlds, Twists)."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from builtin_interfaces.msg import Time
from geometry_msgs.msg import PoseStamped, Twist
from nav_msgs.msg import Odometry
from rclpy.parameter import Parameter
from rclpy.qos import DurabilityPolicy, ReliabilityPolicy, qos_profile_sensor_data
from ros_support import Graph, params, run_executable
from rosbags.rosbag2 import StoragePlugin, Writer
from rosbags.typesys import Stores, get_typestore
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import LaserScan
from std_msgs.msg import String
from std_srvs.srv import Trigger
from visualization_msgs.msg import MarkerArray

from mentor_core.errors import ConfigError, FileFormatError
from mentor_core.files.bags import read_episode_bag, write_episode_bag, write_scenario_bag
from mentor_core.runtime.recording import recorded_episodes
from mentor_core.sim.kinematics import unicycle_arc
from mentor_core.sim.pymunk_world import PymunkWorld
from mentor_core.sim.robot_description import urdf_joints
from mentor_core.sim.robots import get_profile
from mentor_core.sim.transforms import Transform2D
from mentor_core.sim.world import Scenario, World, save_world
from mentor_sim_node import conversions as sim_conv
from mentor_sim_node.sim import QOS_COMMAND, QOS_LATCHED, SimNode, SimSetupError

pytestmark = pytest.mark.ros

SWARM = get_profile("swarm")
S = 1_000_000_000
WORLD = World(4.0, np.array([[2.0, 0.0, 2.5, 1.5], [0.0, 3.0, 1.0, 4.0]]), name="test")
SCENARIOS = [
    Scenario(WORLD, (1.5, 0.5, 0.0), (3.5, 3.5)),  # the box 0.46 m ahead of the sensors
    Scenario(WORLD, (3.0, 2.5, math.pi), (0.5, 1.5)),
]



@pytest.fixture
def world_file(tmp_path: Path) -> Path:
    path = tmp_path / "world.yaml"
    save_world(path, WORLD, SCENARIOS)
    return path


class Listener:
    """Everything one robot namespace of the simulator publishes, as received."""

    def __init__(self, graph: Graph, ns: str = "robot_0") -> None:
        self.node = graph.probe(f"listener_{ns}")
        self.scans: list[LaserScan] = []
        self.odoms: list[Odometry] = []
        self.events: list[dict[str, Any]] = []
        self.clock: list[int] = []
        sensor = qos_profile_sensor_data
        self.node.create_subscription(LaserScan, f"/{ns}/scan", self.scans.append, sensor)
        self.node.create_subscription(Odometry, f"/{ns}/odom", self.odoms.append, sensor)
        self.node.create_subscription(
            String, f"/{ns}/events", lambda m: self.events.append(json.loads(m.data)), 10
        )
        self.node.create_subscription(
            Clock, "/clock", lambda m: self.clock.append(m.clock.sec * S + m.clock.nanosec), 10
        )
        self.cmd = self.node.create_publisher(Twist, f"/{ns}/cmd_vel", QOS_COMMAND)

    def kinds(self) -> list[tuple[str, int]]:
        return [(e["event"], e["scenario"]) for e in self.events]

    def odom_at(self, t_ns: int) -> Odometry | None:
        return next((o for o in self.odoms if _ns(o.header.stamp) == t_ns), None)


class Answerer:
    """A stand-in planner: answers every new scan stamp of a namespace with one Twist."""

    def __init__(self, graph: Graph, ns: str, linear_x: float, angular_z: float = 0.0) -> None:
        self.node = graph.probe(f"answerer_{ns}")
        self.pub = self.node.create_publisher(Twist, f"/{ns}/cmd_vel", QOS_COMMAND)
        self.twist = Twist()
        self.twist.linear.x, self.twist.angular.z = linear_x, angular_z
        self.answered: set[int] = set()
        self.node.create_subscription(
            LaserScan, f"/{ns}/scan", self._on_scan, qos_profile_sensor_data
        )

    def _on_scan(self, msg: LaserScan) -> None:
        stamp = _ns(msg.header.stamp)
        if stamp not in self.answered:
            self.answered.add(stamp)
            self.pub.publish(self.twist)


def _ns(stamp: Any) -> int:
    return int(stamp.sec) * S + int(stamp.nanosec)


def _yaw(o: Odometry) -> float:
    q = o.pose.pose.orientation
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


def _sim(graph: Graph, **values: Any) -> SimNode:
    values = {"robots": ["robot_0"], "profiles": ["swarm"], **values}
    return graph.add(SimNode(context=graph.context, parameter_overrides=params(**values)))


def test_topics_frames_qos_and_mount_layout(graph: Graph, world_file: Path) -> None:
    listener = Listener(graph)
    sim = _sim(graph, world=str(world_file), auto_advance=False)
    assert graph.spin_until(lambda: bool(listener.scans and listener.odoms and listener.events))
    scan = listener.scans[0]
    assert _ns(scan.header.stamp) == 0 and scan.header.frame_id == "robot_0/base_link"
    assert len(scan.ranges) == 3 and scan.range_max == pytest.approx(0.6)
    assert scan.angle_increment == pytest.approx(math.pi / 4)
    expected = PymunkWorld(WORLD, SWARM).ranges(SCENARIOS[0].start)
    np.testing.assert_array_equal(np.array(scan.ranges), expected.astype(np.float32))
    assert math.isinf(scan.ranges[0]) and scan.ranges[1] == pytest.approx(0.46, abs=1e-6)
    odom = listener.odoms[0]
    assert odom.header.frame_id == "odom" and odom.child_frame_id == "robot_0/base_link"
    assert (odom.pose.pose.position.x, odom.pose.pose.position.y) == (1.5, 0.5)
    assert listener.kinds() == [("started", 0)]
    assert graph.spin_until(lambda: 0 in listener.clock)
    # latched topics reach a subscriber that comes late
    late = graph.probe("late")
    goals: list[PoseStamped] = []
    markers: list[MarkerArray] = []
    late.create_subscription(PoseStamped, "/robot_0/goal", goals.append, QOS_LATCHED)
    late.create_subscription(MarkerArray, "/mentor/obstacles", markers.append, QOS_LATCHED)
    assert graph.spin_until(lambda: bool(goals and markers))
    assert goals[0].header.frame_id == "map"
    assert (goals[0].pose.position.x, goals[0].pose.position.y) == (3.5, 3.5)
    assert len(markers[0].markers) == 1 + len(WORLD.obstacles)
    # QoS offered: sensor data for scan and odom, transient local for goal and obstacles
    for topic, reliability, durability in (
        ("/robot_0/scan", ReliabilityPolicy.BEST_EFFORT, DurabilityPolicy.VOLATILE),
        ("/robot_0/odom", ReliabilityPolicy.BEST_EFFORT, DurabilityPolicy.VOLATILE),
        ("/robot_0/goal", ReliabilityPolicy.RELIABLE, DurabilityPolicy.TRANSIENT_LOCAL),
        ("/mentor/obstacles", ReliabilityPolicy.RELIABLE, DurabilityPolicy.TRANSIENT_LOCAL),
    ):
        (info,) = late.get_publishers_info_by_topic(topic)
        assert (info.qos_profile.reliability, info.qos_profile.durability) == (
            reliability, durability,
        ), topic
    # the sensor mount layout, in scan order, as read-only parameters
    assert sim.get_parameter("robot_0.sensor_angle").value == pytest.approx(
        [-math.pi / 4, 0.0, math.pi / 4]
    )
    assert sim.get_parameter("robot_0.sensor_y").value == pytest.approx([-0.025, 0.0, 0.025])
    assert sim.get_parameter("robot_0.profile").value == "swarm"


def test_lockstep_waits_for_each_answer_and_rejects_nan(
    graph: Graph, world_file: Path, capfd: pytest.CaptureFixture[str]
) -> None:
    listener = Listener(graph)
    sim = _sim(graph, world=str(world_file), resend_period=0.05)
    assert graph.spin_until(lambda: len(listener.scans) >= 3)  # repeated while unanswered
    assert {_ns(s.header.stamp) for s in listener.scans} == {0}
    assert sim.sim_time_ns == 0  # sim time stands still until the planner answers
    start = np.array([SCENARIOS[0].start])

    def send(linear_x: float, angular_z: float, t_ns: int) -> bool:
        twist = Twist()
        twist.linear.x, twist.angular.z = linear_x, angular_z
        listener.cmd.publish(twist)
        return graph.spin_until(lambda: listener.odom_at(t_ns) is not None, timeout=5.0)

    assert send(0.05, 0.3, 1 * S)
    odom = listener.odom_at(1 * S)
    assert odom is not None
    want = unicycle_arc(start, 0.3, 0.05)[0]
    assert odom.pose.pose.position.x == want[0] and odom.pose.pose.position.y == want[1]
    assert abs(_yaw(odom) - want[2]) < 1e-12
    assert odom.twist.twist.linear.x == 0.05 and odom.twist.twist.angular.z == 0.3
    # a Twist with NaN: a logged rejection, the robot holds still, the node keeps running
    assert send(math.nan, 0.0, 2 * S)
    held = listener.odom_at(2 * S)
    assert held is not None and held.pose.pose.position.x == want[0]
    assert "robot_0/cmd_vel rejected: non-finite velocity command" in capfd.readouterr().err
    assert send(0.01, 0.0, 3 * S)
    assert sim.sim_time_ns == 3 * S
    assert graph.spin_until(lambda: 3 * S in listener.clock)


def test_reset_service_starts_the_next_scenario(graph: Graph, world_file: Path) -> None:
    listener = Listener(graph)
    Answerer(graph, "robot_0", 0.01)
    sim = _sim(graph, world=str(world_file), auto_advance=False, time_limit=2.0)
    assert graph.spin_until(lambda: ("timed_out", 0) in listener.kinds())
    graph.spin_for(0.3)
    assert listener.kinds() == [("started", 0), ("timed_out", 0)]  # waits for ~/reset
    assert sim.episodes_done == 1 and sim.sim_time_ns == 2 * S
    client = graph.probe("caller").create_client(Trigger, "/mentor_sim/reset")
    assert client.wait_for_service(timeout_sec=5.0)

    def reset() -> Trigger.Response:
        future = client.call_async(Trigger.Request())
        assert graph.spin_until(future.done)
        result = future.result()
        assert result is not None
        return result

    assert reset().success
    assert graph.spin_until(lambda: ("started", 1) in listener.kinds())
    # the next episode starts one control period after the last one ended
    assert graph.spin_until(lambda: listener.odom_at(3 * S) is not None)
    first = listener.odom_at(3 * S)
    assert first is not None and first.pose.pose.position.x == SCENARIOS[1].start[0]
    # a reset in the middle of an episode ends it (timed out) and starts the next one
    graph.spin_for(0.05)
    assert reset().success
    assert graph.spin_until(lambda: listener.kinds()[-1:] == [("started", 0)])
    assert listener.kinds() == [
        ("started", 0), ("timed_out", 0), ("started", 1), ("timed_out", 1), ("started", 0)
    ]
    assert sim.episodes_done == 2


def test_real_time_mode_steps_without_waiting(
    graph: Graph, world_file: Path, capfd: pytest.CaptureFixture[str]
) -> None:
    listener = Listener(graph)
    sim = _sim(graph, world=str(world_file), real_time_factor=50.0, time_limit=4.0, episodes=1)
    assert graph.spin_until(lambda: sim.finished and len(listener.events) == 2)
    assert listener.kinds() == [("started", 0), ("timed_out", 0)]
    assert graph.spin_until(lambda: listener.odom_at(4 * S) is not None)
    xs = {o.pose.pose.position.x for o in listener.odoms}
    assert xs == {1.5}  # nobody commanded it: it held still, period after period
    assert sim.sim_time_ns == 4 * S
    assert "no cmd_vel from robot_0 this period; holding still" in capfd.readouterr().err


def test_recording_holds_everything_published_and_received(
    graph: Graph, world_file: Path, tmp_path: Path
) -> None:
    Answerer(graph, "robot_0", 0.04, 0.2)
    bag = tmp_path / "rec"
    sim = _sim(graph, world=str(world_file), episodes=2, time_limit=3.0, record=str(bag))
    assert graph.spin_until(lambda: sim.finished)
    log = read_episode_bag(bag)
    assert log.world == WORLD and log.profile_name == "swarm"
    runs = recorded_episodes(log, bag)
    assert [(r.setup.scenario, r.outcome) for r in runs] == [(0, "timed_out"), (1, "timed_out")]
    for run in runs:
        assert len(run.scans) == len(run.commands) == 3
        assert len(run.odometry) == 4  # start, after each decision (the last one at rest)
        assert all((c.linear_x, c.angular_z) == (0.04, 0.2) for c in run.commands)
        assert [s.stamp_ns for s in run.scans] == [c.stamp_ns for c in run.commands]
    assert runs[1].setup.start == SCENARIOS[1].start


def test_a_start_overlapping_an_obstacle_is_skipped(
    graph: Graph, tmp_path: Path, capfd: pytest.CaptureFixture[str]
) -> None:
    path = tmp_path / "overlap.yaml"
    bad = Scenario(WORLD, (1.98, 0.5, 0.0), (3.5, 3.5))  # centre outside, body in the box
    save_world(path, WORLD, [bad, SCENARIOS[1]])
    listener = Listener(graph)
    sim = _sim(graph, world=str(path), auto_advance=False)
    assert graph.spin_until(lambda: bool(listener.events))
    assert listener.kinds() == [("started", 1)]
    assert len(sim.rejections) == 1 and "scenario 0 skipped for robot_0 (swarm)" in (
        sim.rejections[0]
    )
    assert "overlaps an obstacle" in capfd.readouterr().err


def _raw_bag(path: Path, messages: list[tuple[str, str, Any]]) -> None:
    ts = get_typestore(Stores.ROS2_JAZZY)
    with Writer(path, version=9, storage_plugin=StoragePlugin.MCAP) as writer:
        for topic, msgtype, msg in messages:
            conn = writer.add_connection(topic, msgtype, typestore=ts)
            writer.write(conn, 0, ts.serialize_cdr(msg, msgtype))


def _bad_sources(tmp_path: Path) -> dict[str, tuple[dict[str, Any], str]]:
    """Parameter sets the simulator must refuse, with the fault it must name."""
    cut = tmp_path / "cut"
    write_scenario_bag(cut, WORLD, SCENARIOS, "swarm")
    (mcap,) = cut.glob("*.mcap")
    mcap.write_bytes(mcap.read_bytes()[: mcap.stat().st_size // 2])
    foreign = tmp_path / "episodes"
    write_episode_bag(foreign, [], SWARM)
    ts = get_typestore(Stores.ROS2_JAZZY)
    head = {"format": "mentor-scenario-bag", "version": 1, "profile": "swarm",
            "arena_size": 4.0, "n_scenarios": 0}
    missing = tmp_path / "missing_topic"
    _raw_bag(missing, [
        ("/mentor/metadata", "std_msgs/msg/String",
         ts.types["std_msgs/msg/String"](data=json.dumps(head))),
        ("/mentor/obstacles", "visualization_msgs/msg/MarkerArray",
         ts.types["visualization_msgs/msg/MarkerArray"](markers=[])),
    ])
    inside = tmp_path / "inside.yaml"
    inside.write_text(
        "format: mentor-world\nversion: 1\nsize: 4.0\nobstacles: [[1, 1, 2, 2]]\n"
        "scenarios:\n  - {start: [1.5, 1.5, 0.0], goal: [3, 3]}\n"
    )
    (tmp_path / "map.yaml").write_text(
        "image: map.pgm\nresolution: 0.1\norigin: [0, 0, 0]\nnegate: 0\n"
        "occupied_thresh: 0.65\nfree_thresh: 0.196\n"
    )
    (tmp_path / "map.pgm").write_bytes(b"P5 40 40 255\n" + bytes(100))
    return {
        "truncated map": (
            {"map_yaml": str(tmp_path / "map.yaml")},
            f"{tmp_path / 'map.pgm'}: PGM truncated: 100 of 1600 pixel bytes",
        ),
        "truncated bag": ({"scenario_bag": str(cut)}, f"{cut}: unreadable bag"),
        "foreign bag": ({"scenario_bag": str(foreign)}, "not a mentor-scenario-bag"),
        "bag missing a topic": (
            {"scenario_bag": str(missing)}, "topic /mentor/starts is missing"
        ),
        "start inside an obstacle": (
            {"world": str(inside)}, f"{inside}: scenarios[0]: start (1.5, 1.5) lies inside"
        ),
    }


@pytest.mark.parametrize(
    "case",
    [
        "truncated bag", "foreign bag", "bag missing a topic", "start inside an obstacle",
        "truncated map",
    ],
)
def test_bad_scenario_sources_are_one_line_errors(graph: Graph, tmp_path: Path, case: str) -> None:
    values, fault = _bad_sources(tmp_path)[case]
    with pytest.raises(FileFormatError) as err:
        _sim(graph, **values)
    assert fault in str(err.value) and "\n" not in str(err.value)


def test_bad_parameters_are_one_line_errors(graph: Graph, world_file: Path) -> None:
    with pytest.raises(ConfigError, match="unknown robot 'tank'"):
        _sim(graph, profiles=["tank"])
    with pytest.raises(SimSetupError, match="not a relative ROS name"):
        _sim(graph, robots=["/abs"])
    with pytest.raises(SimSetupError, match="2 given for 3 robots"):
        _sim(graph, robots=["a", "b", "c"], profiles=["ugv", "swarm"])
    with pytest.raises(SimSetupError, match="one profile only"):
        _sim(graph, robots=["a", "b"], profiles=["ugv", "swarm"], record="x")
    with pytest.raises(ConfigError, match="only one of a world file, a scenario bag or a map"):
        _sim(graph, world=str(world_file), scenario_bag="b")
    with pytest.raises(ConfigError, match="only one of"):
        _sim(graph, world=str(world_file), map_yaml="m.yaml")
    with pytest.raises(SimSetupError, match="record_metadata: not a JSON object"):
        _sim(graph, world=str(world_file), record_metadata="[1, 2]")
    # periods that would take a whole core, a map that would exhaust memory (issue 56)
    with pytest.raises(SimSetupError, match=r"control_period: a period of 0\.0001 s is shorter"):
        _sim(graph, world=str(world_file), control_period=0.0001)
    with pytest.raises(SimSetupError, match=r"scan_rate: a period of 0\.001 s"):
        _sim(graph, world=str(world_file), continuous=True, scan_rate=1000.0)
    with pytest.raises(SimSetupError, match=r"map_resolution: a map of the world .* more than"):
        _sim(graph, world=str(world_file), map_resolution=0.001)


@pytest.mark.parametrize("case", ["start inside an obstacle", "truncated bag", "truncated map"])
def test_sim_executable_exits_nonzero_with_one_line(tmp_path: Path, case: str) -> None:
    values, fault = _bad_sources(tmp_path)[case]
    args = ["--ros-args", *[a for k, v in values.items() for a in ("-p", f"{k}:={v}")]]
    rc, err = run_executable("mentor_sim_node", "sim", [*args, "-p", "profiles:=[swarm]"])
    assert rc == 2, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("mentor_sim: ") and fault in lines[0], err


# -------------------------------------------------------------------- issue 16


def test_a_plain_publishers_goal_is_the_one_the_robot_is_judged_against(
    graph: Graph, world_file: Path, capfd: pytest.CaptureFixture[str]
) -> None:
    """Failed before: the simulator heard no goals; it judged "reached" against its scenario's
    goal only, so a robot standing at the user's goal timed out."""
    listener = Listener(graph)
    Answerer(graph, "robot_0", 0.0)  # a planner that holds still
    _sim(graph, world=str(world_file), auto_advance=False, time_limit=20.0)
    user = graph.probe("user").create_publisher(PoseStamped, "/goal_pose", 10)
    assert graph.spin_until(lambda: bool(listener.events) and user.get_subscription_count() > 0)
    user.publish(sim_conv.pose_stamped_from_goal((2.0, 30.0), Time()))  # outside the arena
    assert graph.spin_until(lambda: "lies outside the known area" in capfd.readouterr().err)
    near = sim_conv.pose_stamped_from_goal((1.6, 0.6), Time())  # 0.14 m from the robot
    user.publish(near)
    assert graph.spin_until(lambda: ("reached", 0) in listener.kinds(), timeout=5.0)
    assert listener.kinds() == [("started", 0), ("reached", 0)]


def test_lidar_scan_frames_and_robot_description(graph: Graph, world_file: Path) -> None:
    listener = Listener(graph)
    lidars: list[LaserScan] = []
    urdf: list[String] = []
    listener.node.create_subscription(LaserScan, "/robot_0/lidar/scan", lidars.append,
                                      qos_profile_sensor_data)
    listener.node.create_subscription(String, "/robot_0/robot_description", urdf.append,
                                      QOS_LATCHED)
    offset = Transform2D(1.0, -0.5, 0.3)
    _sim(graph, world=str(world_file), auto_advance=False, lidar_rays=90,
         lidar_mount=[0.02, 0.0, 0.1], map_to_odom=list(offset.as_tuple()), lidar_noise=0.001)
    assert graph.spin_until(lambda: bool(lidars and listener.scans and listener.odoms and urdf))
    scan = lidars[0]
    assert scan.header.frame_id == "robot_0/lidar" and len(scan.ranges) == 90
    assert scan.header.stamp == listener.scans[0].header.stamp == listener.odoms[0].header.stamp
    assert scan.angle_increment == pytest.approx(2 * math.pi / 90)
    assert scan.range_max == pytest.approx(SWARM.sensor_range)
    odom = listener.odoms[0]
    want = offset.inverse().apply_pose(SCENARIOS[0].start)
    assert (odom.pose.pose.position.x, odom.pose.pose.position.y) == pytest.approx(want[:2])
    assert odom.header.frame_id == "odom"
    joints = urdf_joints(urdf[0].data)
    assert joints["robot_0/lidar"] == ("robot_0/base_link", Transform2D(0.02, 0.0, 0.1))
    assert set(joints) == {"robot_0/lidar", *(f"robot_0/sensor_{i}" for i in range(3))}


def test_continuous_mode_drives_a_teleop_command_until_it_times_out(
    graph: Graph, world_file: Path
) -> None:
    listener = Listener(graph)
    sim = _sim(graph, world=str(world_file), auto_advance=False, continuous=True,
               real_time_factor=4.0, physics_step=0.05, scan_rate=10.0, odom_rate=20.0,
               command_timeout=0.3, time_limit=30.0)
    assert graph.spin_until(lambda: bool(listener.odoms))
    teleop = Twist()
    teleop.linear.x = 0.05  # 5 cm/s ahead, once
    assert graph.spin_until(lambda: listener.cmd.get_subscription_count() > 0)
    listener.cmd.publish(teleop)
    assert graph.spin_until(lambda: sim.sim_time_ns > 2 * S)
    odoms = sorted(listener.odoms, key=lambda o: _ns(o.header.stamp))
    stamps = np.array([_ns(o.header.stamp) for o in odoms])
    assert set(np.diff(stamps)) == {S // 20}  # odometry every 0.05 s of sim time
    scans = {_ns(s.header.stamp) for s in listener.scans}
    assert all(t % (S // 10) == 0 for t in scans) and len(scans) >= 15  # scans at 10 Hz
    xs = np.array([o.pose.pose.position.x for o in odoms])
    moved = np.flatnonzero(np.diff(xs) > 0)
    assert 0.0 < xs[-1] - xs[0] <= 0.05 * 0.35 + 1e-9  # held for the 0.3 s timeout, no more
    assert len(moved) in (6, 7) and (np.diff(moved) == 1).all()  # one run of steps, then still


def test_parameters_that_change_at_run_time(graph: Graph, world_file: Path) -> None:
    sim = _sim(graph, world=str(world_file), real_time_factor=50.0, auto_advance=False)
    assert sim.set_parameters([Parameter("real_time_factor", value=20.0)])[0].successful
    assert not sim.set_parameters([Parameter("real_time_factor", value=0.0)])[0].successful
    assert sim.set_parameters([Parameter("goal_radius", value=0.5)])[0].successful
    assert sim.session.goal_radius == 0.5
    assert not sim.set_parameters([Parameter("world", value="x.yaml")])[0].successful
    descriptors = sim.describe_parameters(["real_time_factor", "goal_radius", "seed"])
    assert [d.read_only for d in descriptors] == [False, False, True]


def test_the_simulator_decides_at_the_planners_period(graph: Graph, world_file: Path) -> None:
    """A planner whose genome decides every 0.5 s (metadata ``control_period``) sends Twists
    that stand for 0.5 s: the simulator steps at that period when told to."""
    assert _sim(graph, world=str(world_file), auto_advance=False).session.dt == 1.0
    sim = _sim(graph, world=str(world_file), auto_advance=False, control_period=0.5)
    assert sim.session.dt == 0.5


def test_an_unparsable_parameter_value_is_one_line_and_exit_2() -> None:
    """Failed before: a traceback and exit status 1."""
    rc, err = run_executable(
        "mentor_sim_node", "sim", ["--ros-args", "-p", 'record_metadata:={"who": "review"}']
    )
    assert rc == 2, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("mentor_sim: bad ROS arguments: "), err
    assert "record_metadata" in lines[0]
