"""Message conversions of both node packages, tested without a running ROS graph."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import ros_support  # noqa: F401  (puts the node packages on sys.path)
from geometry_msgs.msg import Twist, Vector3
from rclpy.serialization import deserialize_message, serialize_message
from sensor_msgs.msg import LaserScan
from std_msgs.msg import String

from mentor_core.sim.observation import network_inputs
from mentor_core.sim.robots import RobotProfile, get_profile
from mentor_core.sim.world import World
from mentor_planner_node import conversions as planner
from mentor_sim_node import conversions as sim


@pytest.fixture
def ugv() -> RobotProfile:
    return get_profile("ugv")


@pytest.fixture
def swarm() -> RobotProfile:
    return get_profile("swarm")


def test_time_stamps_convert_both_ways() -> None:
    t = sim.time_from_ns(12_345_678_901)
    assert (t.sec, t.nanosec) == (12, 345_678_901)
    assert sim.ns_from_time(t) == 12_345_678_901
    with pytest.raises(ValueError):
        sim.time_from_ns(-1)


def test_scan_carries_inf_and_the_profile_geometry(ugv: RobotProfile) -> None:
    ranges = np.array([0.5, np.inf, 3.99, 4.0, 4.5, 0.0, 1.25, 2.0])
    msg = sim.laser_scan_from_ranges(ranges, ugv, sim.time_from_ns(2_000_000_000), "r/base_link")
    assert msg.header.frame_id == "r/base_link" and msg.header.stamp.sec == 2
    assert msg.range_min == 0.0 and msg.range_max == pytest.approx(4.0)
    assert msg.angle_increment == pytest.approx(math.pi / 4)  # UGV sensors face every 45 deg
    assert msg.angle_min == pytest.approx(ugv.sensors[0].angle)
    assert msg.angle_max == pytest.approx(ugv.sensors[-1].angle)
    got = np.array(msg.ranges)
    assert np.isposinf(got[1]) and np.isposinf(got[4])  # beyond range -> +inf (REP-117)
    assert got[3] == pytest.approx(4.0) and got[0] == pytest.approx(0.5)


def test_scan_of_evenly_spaced_mounts_has_an_increment(swarm: RobotProfile) -> None:
    msg = sim.laser_scan_from_ranges([0.1, 0.2, np.inf], swarm, sim.time_from_ns(0), "b")
    assert msg.angle_increment == pytest.approx(math.pi / 4)
    assert msg.angle_min == pytest.approx(-math.pi / 4)
    assert msg.angle_max == pytest.approx(math.pi / 4)


def test_scan_rejects_bad_readings(ugv: RobotProfile) -> None:
    t = sim.time_from_ns(0)
    with pytest.raises(ValueError, match="8 sensors"):
        sim.laser_scan_from_ranges([1.0, 2.0], ugv, t, "b")
    with pytest.raises(ValueError, match="NaN"):
        sim.laser_scan_from_ranges([math.nan] + [1.0] * 7, ugv, t, "b")
    with pytest.raises(ValueError, match="negative"):
        sim.laser_scan_from_ranges([-1.0] + [1.0] * 7, ugv, t, "b")


def test_scan_survives_the_wire_and_feeds_the_shared_input_function(ugv: RobotProfile) -> None:
    ranges = np.array([0.5, np.inf, 3.5, 1.0, 2.0, 0.25, 1.5, 3.0])
    msg = sim.laser_scan_from_ranges(ranges, ugv, sim.time_from_ns(0), "b")
    wire = deserialize_message(serialize_message(msg), LaserScan)
    got = planner.ranges_from_scan(wire, ugv)
    assert got.dtype == np.float64 and got.shape == (8,)
    assert np.isposinf(got[1])  # kept: the shared input function clips it
    np.testing.assert_array_equal(got, ranges.astype(np.float32).astype(np.float64))
    inputs = network_inputs(got[None], np.array([[1.0, 1.0, 0.0]]), np.array([[5.0, 5.0]]), ugv)
    assert inputs[0, 1] == ugv.sensor_range


def test_planner_rejects_a_bad_scan(ugv: RobotProfile, swarm: RobotProfile) -> None:
    msg = sim.laser_scan_from_ranges([0.1, 0.2, 0.3], swarm, sim.time_from_ns(0), "b")
    with pytest.raises(ValueError, match="8 sensors"):
        planner.ranges_from_scan(msg, ugv)
    msg.ranges[1] = math.nan
    with pytest.raises(ValueError, match="NaN"):
        planner.ranges_from_scan(msg, swarm)


@pytest.mark.parametrize("theta", [0.0, 1.0, -2.5, math.pi, -math.pi / 2, 3.1])
def test_odometry_round_trip(theta: float) -> None:
    pose = (3.25, 7.125, theta)
    msg = sim.odometry_from_pose(pose, (0.5, -0.25), sim.time_from_ns(1_500_000_000), "robot_0")
    assert msg.header.frame_id == "odom" and msg.child_frame_id == "robot_0/base_link"
    assert msg.twist.twist.linear.x == 0.5 and msg.twist.twist.angular.z == -0.25
    x, y, th = planner.pose_from_odometry(msg)
    assert (x, y) == pose[:2]
    assert abs(math.remainder(th - theta, 2 * math.pi)) <= 1e-12
    assert -math.pi < th <= math.pi


def test_odometry_rejects_garbage() -> None:
    msg = sim.odometry_from_pose((1.0, 1.0, 0.0), (0.0, 0.0), sim.time_from_ns(0), "r")
    msg.pose.pose.orientation.w = 0.0
    with pytest.raises(ValueError, match="zero quaternion"):
        planner.pose_from_odometry(msg)
    msg.pose.pose.position.x = math.inf
    with pytest.raises(ValueError, match="not finite"):
        planner.pose_from_odometry(msg)


def test_goal_round_trip_in_any_frame() -> None:
    msg = sim.pose_stamped_from_goal((10.5, 1.0 / 3.0), sim.time_from_ns(0))
    assert msg.header.frame_id == "map"
    assert planner.goal_request(msg) == ("map", (10.5, 1.0 / 3.0), 0.0)  # facing +x
    msg.header.frame_id = "odom"  # refused before issue 16; now the planner transforms it
    assert planner.goal_request(msg) == ("odom", (10.5, 1.0 / 3.0), 0.0)
    msg.pose.orientation.z, msg.pose.orientation.w = math.sin(0.5), math.cos(0.5)
    assert planner.goal_request(msg)[2] == pytest.approx(1.0)  # a heading of 1 rad
    msg.pose.orientation.z = msg.pose.orientation.w = 0.0  # all zeros: no heading
    assert planner.goal_request(msg)[2] is None
    msg.pose.orientation.w = math.nan
    with pytest.raises(ValueError, match="orientation is not finite"):
        planner.goal_request(msg)
    msg.pose.orientation.w = 1.0
    msg.pose.position.x = math.nan
    with pytest.raises(ValueError, match="not finite"):
        planner.goal_request(msg)


def test_action_twist_round_trip() -> None:
    dt = 0.5
    twist = planner.twist_from_action(-1.2, 0.75, dt)
    assert twist.angular.z == pytest.approx(-2.4) and twist.linear.x == pytest.approx(1.5)
    dtheta, ds = sim.twist_to_action(twist, dt)
    assert dtheta == pytest.approx(-1.2, abs=1e-15) and ds == pytest.approx(0.75, abs=1e-15)


@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf])
def test_non_finite_commands_are_refused(bad: float) -> None:
    with pytest.raises(ValueError):
        sim.twist_to_action(Twist(linear=Vector3(x=bad)), 1.0)
    with pytest.raises(ValueError):
        sim.twist_to_action(Twist(angular=Vector3(z=bad)), 1.0)
    with pytest.raises(ValueError):
        planner.twist_from_action(bad, 0.5, 1.0)
    with pytest.raises(ValueError):
        planner.twist_from_action(0.1, bad, 1.0)


@pytest.mark.parametrize("dt", [0.0, -1.0, math.nan])
def test_bad_control_period_is_refused(dt: float) -> None:
    with pytest.raises(ValueError):
        sim.twist_to_action(Twist(), dt)
    with pytest.raises(ValueError):
        planner.twist_from_action(0.1, 0.5, dt)


def test_markers_describe_the_world_exactly() -> None:
    world = World(size=12.0, obstacles=np.array([[0.1, 0.2, 0.7, 0.3], [5.0, 5.0, 6.0, 8.0]]))
    arr = sim.markers_from_world(world)
    arena = [m for m in arr.markers if m.ns == "arena"]
    cubes = [m for m in arr.markers if m.ns == "obstacles"]
    assert len(arena) == 1 and len(arena[0].points) == 5
    assert max(p.x for p in arena[0].points) == 12.0
    assert [m.id for m in cubes] == [0, 1]
    assert all(m.type == m.CUBE and m.header.frame_id == "map" for m in cubes)
    c = cubes[1]
    assert (c.pose.position.x, c.pose.position.y) == (5.5, 6.5)
    assert (c.scale.x, c.scale.y) == (1.0, 3.0)
    corners = [[p.x, p.y] for p in cubes[0].points]
    assert corners == [[0.1, 0.2], [0.7, 0.3]]  # exact, unlike centre +- size / 2


def test_events_carry_kind_scenario_stamp_and_the_started_goal() -> None:
    msg = sim.event_string("started", 3, 7_000_000_000, (1.5, 2.25))
    body = json.loads(msg.data)
    assert body == {
        "format": "mentor-episode-event", "version": 1, "event": "started", "scenario": 3,
        "stamp_ns": 7_000_000_000, "goal": [1.5, 2.25],
    }
    assert planner.event_from_string(msg) == ("started", (1.5, 2.25))
    assert planner.event_from_string(sim.event_string("collided", 3, 9)) == ("collided", None)
    with pytest.raises(ValueError, match="unknown event"):
        sim.event_string("exploded", 0, 0)
    for bad in ("not json", '{"format": "other", "event": "started"}',
                '{"format": "mentor-episode-event", "event": "lost"}',
                '{"format": "mentor-episode-event", "event": "started", "goal": [1, NaN]}'):
        with pytest.raises(ValueError):
            planner.event_from_string(String(data=bad))


def test_stamps_in_ns() -> None:
    assert planner.ns_from_stamp(sim.time_from_ns(3_000_000_007)) == 3_000_000_007
