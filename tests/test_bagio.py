"""Scenario and episode bags: exact round trips, what rosbags' generic reader sees, bad input."""

from __future__ import annotations

import dataclasses
import json
import math
import shutil
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from rosbags.highlevel import AnyReader
from rosbags.interfaces import QosDurability, QosReliability
from rosbags.rosbag2 import StoragePlugin, Writer
from rosbags.typesys import Stores, get_typestore

from mentor_core.errors import FileFormatError
from mentor_core.files.bags import (
    CmdRecord,
    EpisodeLog,
    EventRecord,
    GoalRecord,
    OdomRecord,
    RobotEpisode,
    ScanRecord,
    read_episode_bag,
    read_scenario_bag,
    scan_geometry,
    write_episode_bag,
    write_scenario_bag,
)
from mentor_core.files.bags import writing as bag_writing
from mentor_core.sim.frames import quaternion_to_yaw, yaw_to_quaternion
from mentor_core.sim.robots import RobotProfile, get_profile
from mentor_core.sim.world import Scenario, World

TS = get_typestore(Stores.ROS2_JAZZY)


def angle_diff(a: float, b: float) -> float:
    return abs(math.remainder(a - b, 2.0 * math.pi))


@pytest.fixture
def world() -> World:
    # corners that do not survive a centre/size round trip in floating point
    boxes = [[0.1, 0.2, 0.7, 0.3], [1.0 / 3.0, 2.0, 2.0 / 3.0 + 1.0, 2.9], [5.5, 6.1, 11.9, 7.3]]
    return World(size=12.0, obstacles=np.array(boxes), name="odd-floats")


@pytest.fixture
def scenarios(world: World) -> list[Scenario]:
    starts = [(0.5, 0.5, 0.0), (3.3, 4.4, math.pi), (9.1, 1.7, -math.pi / 2), (2.0, 9.9, 3.1)]
    goals = [(10.0, 10.0), (0.1, 11.9), (4.25, 8.125), (11.0, 0.3)]
    return [Scenario(world, s, g) for s, g in zip(starts, goals, strict=True)]


@pytest.fixture
def ugv() -> RobotProfile:
    return get_profile("ugv")


def episode_robots(profile: RobotProfile) -> list[RobotEpisode]:
    rng = np.random.default_rng(7)
    robots = []
    for r in range(2):
        n = profile.n_sensors
        scans = []
        for i in range(4):
            ranges = rng.uniform(0.0, profile.sensor_range, n)
            ranges[i % n] = math.inf
            scans.append(ScanRecord(i * 1_000_000_000 + r, tuple(float(v) for v in ranges)))
        odometry = tuple(
            OdomRecord(
                i * 1_000_000_000 + 5,
                (float(rng.uniform(0, 12)), float(rng.uniform(0, 12)), float(rng.uniform(-3, 3))),
                (0.1 * i + 0.3, -0.7 + i / 7.0),
            )
            for i in range(4)
        )
        commands = tuple(
            CmdRecord(i * 1_000_000_000 + 9, 1.0 / 3.0 + i, -math.pi / (i + 1)) for i in range(3)
        )
        goals = (GoalRecord(0, (10.0 + r, 1.0 / 7.0)), GoalRecord(2_500_000_000, (3.0, 4.0)))
        events = (
            EventRecord(0, "started", scenario=r),
            EventRecord(3_000_000_000, "collided" if r else "reached", scenario=r),
        )
        robots.append(RobotEpisode(f"robot_{r}", tuple(scans), odometry, commands, goals, events))
    return robots


# ---------------------------------------------------------------------------- round trips


def test_scenario_bag_round_trip(tmp_path: Path, world: World, scenarios: list[Scenario]) -> None:
    path = tmp_path / "unseen"
    meta = {"seed": 42, "note": "unseen test set", "nested": {"x": [1.5, 2.25]}}
    write_scenario_bag(path, world, scenarios, "ugv", meta)
    world2, scen2, profile, meta2 = read_scenario_bag(path)
    assert world2 == world  # exact obstacle values, size and name
    assert world2.obstacles.tolist() == world.obstacles.tolist()
    assert profile == "ugv"
    assert meta2 == meta
    assert len(scen2) == len(scenarios)
    for a, b in zip(scenarios, scen2, strict=True):
        assert b.world == world
        assert b.start[:2] == a.start[:2]
        assert angle_diff(b.start[2], a.start[2]) <= 1e-12
        assert -math.pi < b.start[2] <= math.pi
        assert b.goal == a.goal


def test_empty_world_without_scenarios_round_trips(tmp_path: Path) -> None:
    empty = World(size=4.0)
    write_scenario_bag(tmp_path / "b", empty, [], "swarm")
    world2, scen2, profile, meta = read_scenario_bag(tmp_path / "b")
    assert world2 == empty and world2.obstacles.shape == (0, 4)
    assert scen2 == [] and profile == "swarm" and meta == {}


@settings(max_examples=200, deadline=None)
@given(st.floats(min_value=-math.pi, max_value=math.pi))
def test_yaw_survives_the_quaternion(theta: float) -> None:
    back = quaternion_to_yaw(*yaw_to_quaternion(theta))
    assert angle_diff(back, theta) <= 1e-12
    assert -math.pi < back <= math.pi


def test_yaw_of_a_general_quaternion_ignores_nothing_but_roll_pitch() -> None:
    # unnormalised pure-yaw quaternion and the q / -q ambiguity
    assert quaternion_to_yaw(0.0, 0.0, 2.0, 2.0) == pytest.approx(math.pi / 2, abs=1e-15)
    assert quaternion_to_yaw(0.0, 0.0, -1.0, 0.0) == math.pi


def test_episode_bag_round_trip(tmp_path: Path, ugv: RobotProfile) -> None:
    robots = episode_robots(ugv)
    path = tmp_path / "episode"
    write_episode_bag(path, robots, ugv, {"genome": "best.json", "seed": 3})
    log = read_episode_bag(path)
    assert isinstance(log, EpisodeLog)
    assert log.profile_name == "ugv"
    assert log.metadata == {"genome": "best.json", "seed": 3}
    assert [r.namespace for r in log.robots] == ["robot_0", "robot_1"]
    for want, got in zip(robots, log.robots, strict=True):
        # LaserScan ranges are float32 on the wire; +inf stays +inf
        assert len(got.scans) == len(want.scans)
        for ws, gs in zip(want.scans, got.scans, strict=True):
            assert gs.stamp_ns == ws.stamp_ns
            assert gs.ranges == tuple(float(v) for v in np.float32(ws.ranges))
            assert math.inf in gs.ranges
        for wo, go in zip(want.odometry, got.odometry, strict=True):
            assert go.stamp_ns == wo.stamp_ns
            assert go.pose[:2] == wo.pose[:2]
            assert angle_diff(go.pose[2], wo.pose[2]) <= 1e-12
            assert go.twist == wo.twist
        assert got.commands == want.commands
        assert got.goals == want.goals
        assert got.events == want.events
    # what was read writes back losslessly
    write_episode_bag(tmp_path / "again", log.robots, ugv, log.metadata)
    again = read_episode_bag(tmp_path / "again")
    assert [r.scans for r in again.robots] == [r.scans for r in log.robots]
    assert [r.commands for r in again.robots] == [r.commands for r in log.robots]


def test_episode_with_empty_topics_round_trips(tmp_path: Path) -> None:
    swarm = get_profile("swarm")
    robot = RobotEpisode("solo", events=(EventRecord(10, "timed_out"),))
    write_episode_bag(tmp_path / "e", [robot], swarm)
    log = read_episode_bag(tmp_path / "e")
    assert log.robots == (robot,)


# ----------------------------------------------------------- what `ros2 bag info` would see


def test_scenario_bag_is_a_plain_jazzy_bag(
    tmp_path: Path, world: World, scenarios: list[Scenario]
) -> None:
    write_scenario_bag(tmp_path / "s", world, scenarios, "ugv")
    meta = (tmp_path / "s" / "metadata.yaml").read_text()
    assert "storage_identifier: mcap" in meta
    with AnyReader([tmp_path / "s"], default_typestore=TS) as reader:
        topics = {c.topic: (c.msgtype, c.msgcount) for c in reader.connections}
        assert topics == {
            "/mentor/metadata": ("std_msgs/msg/String", 1),
            "/mentor/obstacles": ("visualization_msgs/msg/MarkerArray", 1),
            "/mentor/starts": ("geometry_msgs/msg/PoseArray", 1),
            "/mentor/goals": ("geometry_msgs/msg/PoseArray", 1),
        }
        for c in reader.connections:
            (qos,) = c.ext.offered_qos_profiles
            assert qos.durability == QosDurability.TRANSIENT_LOCAL  # latched scene
        msgs: dict[str, Any] = {
            c.topic: reader.deserialize(raw, c.msgtype) for c, _, raw in reader.messages()
        }
    head = json.loads(msgs["/mentor/metadata"].data)
    assert head["format"] == "mentor-scenario-bag" and head["version"] == 1
    assert head["arena_size"] == 12.0 and head["profile"] == "ugv"
    cubes = [m for m in msgs["/mentor/obstacles"].markers if m.ns == "obstacles"]
    assert [m.type for m in cubes] == [1, 1, 1]  # Marker.CUBE
    assert all(m.header.frame_id == "map" for m in cubes)
    first = cubes[0]  # box [0.1, 0.2, 0.7, 0.3]: centre and size as RViz draws it
    assert (first.pose.position.x, first.pose.position.y) == pytest.approx((0.4, 0.25))
    assert (first.scale.x, first.scale.y) == pytest.approx((0.6, 0.1))
    assert msgs["/mentor/starts"].header.frame_id == "map"
    assert len(msgs["/mentor/starts"].poses) == 4 and len(msgs["/mentor/goals"].poses) == 4


def test_episode_bag_is_a_plain_jazzy_bag(tmp_path: Path, ugv: RobotProfile) -> None:
    write_episode_bag(tmp_path / "e", episode_robots(ugv), ugv)
    with AnyReader([tmp_path / "e"], default_typestore=TS) as reader:
        topics = {c.topic: (c.msgtype, c.msgcount) for c in reader.connections}
        assert topics["/robot_1/scan"] == ("sensor_msgs/msg/LaserScan", 4)
        assert topics["/robot_1/odom"] == ("nav_msgs/msg/Odometry", 4)
        assert topics["/robot_1/cmd_vel"] == ("geometry_msgs/msg/Twist", 3)
        assert topics["/robot_1/goal"] == ("geometry_msgs/msg/PoseStamped", 2)
        assert topics["/robot_1/events"] == ("std_msgs/msg/String", 2)
        assert len(topics) == 1 + 2 * 5
        scan_conn = next(c for c in reader.connections if c.topic == "/robot_0/scan")
        assert scan_conn.ext.offered_qos_profiles[0].reliability == QosReliability.BEST_EFFORT
        stamps = [t for _, t, _ in reader.messages()]
        assert stamps == sorted(stamps)  # written in time order, as a recorder would
        scan = next(
            reader.deserialize(raw, c.msgtype)
            for c, _, raw in reader.messages()
            if c.topic == "/robot_0/scan"
        )
        odom = next(
            reader.deserialize(raw, c.msgtype)
            for c, _, raw in reader.messages()
            if c.topic == "/robot_0/odom"
        )
    geo = scan_geometry(ugv)
    assert scan.header.frame_id == "robot_0/base_link"
    assert np.isposinf(scan.ranges[0])  # REP-117
    assert scan.range_max == pytest.approx(ugv.sensor_range)
    assert scan.angle_min == pytest.approx(geo.angle_min)
    assert odom.header.frame_id == "odom" and odom.child_frame_id == "robot_0/base_link"


def test_scan_geometry_describes_regular_and_irregular_mounts(ugv: RobotProfile) -> None:
    paired = dataclasses.replace(  # a pair facing the same way: irregular
        ugv, sensors=tuple(dataclasses.replace(m, angle=0.0) for m in ugv.sensors[:2])
    )
    geo = scan_geometry(paired)
    assert geo.angle_increment == 0.0
    assert geo.angle_min == geo.angle_max == 0.0
    assert geo.range_min == 0.0 and geo.range_max == ugv.sensor_range
    for profile, step in ((get_profile("swarm"), 45.0), (ugv, 45.0)):  # evenly spaced
        sg = scan_geometry(profile)
        assert sg.angle_increment == pytest.approx(math.radians(step))
        assert sg.angle_min == profile.sensors[0].angle
        last = sg.angle_min + (profile.n_sensors - 1) * sg.angle_increment
        assert last == pytest.approx(sg.angle_max)


# ---------------------------------------------------------------------------- bad input


def write_raw_bag(path: Path, messages: list[tuple[str, str, Any]]) -> None:
    """A bag written with rosbags directly (foreign or hand-made content)."""
    writer = Writer(path, version=9, storage_plugin=StoragePlugin.MCAP)
    with writer:
        conns: dict[str, Any] = {}
        for topic, msgtype, msg in messages:
            if topic not in conns:
                conns[topic] = writer.add_connection(topic, msgtype, typestore=TS)
            writer.write(conns[topic], 0, TS.serialize_cdr(msg, msgtype))


def string_msg(obj: Any) -> Any:
    return TS.types["std_msgs/msg/String"](data=json.dumps(obj))


def assert_fault(path: Path, reader: Any, *words: str) -> None:
    with pytest.raises(FileFormatError) as info:
        reader(path)
    text = str(info.value)
    assert "\n" not in text
    assert text.startswith(f"{path}: ")
    for w in words:
        assert w in text


@pytest.mark.parametrize("reader", [read_scenario_bag, read_episode_bag])
def test_missing_path(tmp_path: Path, reader: Any) -> None:
    assert_fault(tmp_path / "nope", reader, "no such bag")


def test_not_a_bag_folder(tmp_path: Path) -> None:
    (tmp_path / "file.mcap").write_bytes(b"junk")
    assert_fault(tmp_path / "file.mcap", read_scenario_bag, "not a rosbag2 bag")
    (tmp_path / "dir").mkdir()
    assert_fault(tmp_path / "dir", read_scenario_bag, "metadata.yaml")


@pytest.mark.parametrize("keep", [0.5, 0.9, 0.99])
def test_truncated_bag(
    tmp_path: Path, world: World, scenarios: list[Scenario], keep: float
) -> None:
    path = tmp_path / "cut"
    write_scenario_bag(path, world, scenarios, "ugv")
    (mcap,) = path.glob("*.mcap")
    data = mcap.read_bytes()
    mcap.write_bytes(data[: int(len(data) * keep)])
    assert_fault(path, read_scenario_bag, "unreadable bag")


def test_corrupt_metadata_yaml(tmp_path: Path, world: World) -> None:
    write_scenario_bag(tmp_path / "b", world, [], "ugv")
    (tmp_path / "b" / "metadata.yaml").write_text("rosbag2_bagfile_information: [\n")
    assert_fault(tmp_path / "b", read_scenario_bag, "unreadable bag")


def test_foreign_bag(tmp_path: Path) -> None:
    path = tmp_path / "chatter"
    write_raw_bag(path, [("/chatter", "std_msgs/msg/String", string_msg("hello"))])
    assert_fault(path, read_scenario_bag, "not a mentor-scenario-bag", "/mentor/metadata")
    assert_fault(path, read_episode_bag, "not a mentor-episode-bag")


def test_wrong_format_and_version(tmp_path: Path, world: World, ugv: RobotProfile) -> None:
    write_scenario_bag(tmp_path / "s", world, [], "ugv")
    assert_fault(tmp_path / "s", read_episode_bag, "not a mentor-episode-bag")
    write_episode_bag(tmp_path / "e", episode_robots(ugv), ugv)
    assert_fault(tmp_path / "e", read_scenario_bag, "not a mentor-scenario-bag")
    head = {"format": "mentor-scenario-bag", "version": 2, "profile": "ugv", "arena_size": 4.0}
    write_raw_bag(tmp_path / "v2", [("/mentor/metadata", "std_msgs/msg/String", string_msg(head))])
    assert_fault(tmp_path / "v2", read_scenario_bag, "version 2 is not supported")


def test_missing_topic(tmp_path: Path) -> None:
    head = {
        "format": "mentor-scenario-bag",
        "version": 1,
        "profile": "ugv",
        "arena_size": 4.0,
        "n_scenarios": 0,
    }
    markers = TS.types["visualization_msgs/msg/MarkerArray"](markers=[])
    write_raw_bag(
        tmp_path / "m",
        [
            ("/mentor/metadata", "std_msgs/msg/String", string_msg(head)),
            ("/mentor/obstacles", "visualization_msgs/msg/MarkerArray", markers),
        ],
    )
    assert_fault(tmp_path / "m", read_scenario_bag, "topic /mentor/starts is missing")


def test_episode_bag_missing_robot_topic(tmp_path: Path) -> None:
    head = {"format": "mentor-episode-bag", "version": 1, "profile": "ugv", "namespaces": ["r"]}
    write_raw_bag(tmp_path / "m", [("/mentor/metadata", "std_msgs/msg/String", string_msg(head))])
    assert_fault(tmp_path / "m", read_episode_bag, "topic /r/scan is missing")


# ---------------------------------------------------------------------------- writing


def no_leftovers(folder: Path, *allowed: str) -> None:
    assert sorted(p.name for p in folder.iterdir()) == sorted(allowed)


def test_refuses_to_overwrite_unless_asked(
    tmp_path: Path, world: World, scenarios: list[Scenario]
) -> None:
    path = tmp_path / "b"
    write_scenario_bag(path, world, scenarios, "ugv")
    with pytest.raises(FileExistsError, match="overwrite=True"):
        write_scenario_bag(path, world, scenarios[:1], "swarm")
    assert read_scenario_bag(path)[2] == "ugv"
    write_scenario_bag(path, world, scenarios[:1], "swarm", overwrite=True)
    _, scen, profile, _ = read_scenario_bag(path)
    assert profile == "swarm" and len(scen) == 1
    assert len(list(path.glob("*.mcap"))) == 1
    no_leftovers(tmp_path, "b")


def test_overwrite_never_replaces_what_is_not_a_bag(tmp_path: Path, world: World) -> None:
    precious = tmp_path / "notes"
    precious.mkdir()
    (precious / "thesis.tex").write_text("keep me")
    with pytest.raises(FileExistsError, match="not a rosbag2 bag"):
        write_scenario_bag(precious, world, [], "ugv", overwrite=True)
    assert (precious / "thesis.tex").read_text() == "keep me"


def test_failed_write_leaves_nothing_and_keeps_the_old_bag(
    tmp_path: Path,
    world: World,
    scenarios: list[Scenario],
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    path = tmp_path / "b"
    write_scenario_bag(path, world, scenarios, "ugv")
    before = {p.name: p.read_bytes() for p in path.iterdir()}
    calls = []
    original = Writer.write

    def failing_write(self: Writer, connection: Any, timestamp: int, data: Any) -> None:
        calls.append(timestamp)
        if len(calls) == 2:
            raise OSError("disk full")
        original(self, connection, timestamp, data)

    monkeypatch.setattr(bag_writing.Writer, "write", failing_write)
    with pytest.raises(OSError, match="disk full"):
        write_scenario_bag(path, world, [], "swarm", overwrite=True)
    calls.clear()
    with pytest.raises(OSError, match="disk full"):
        write_scenario_bag(tmp_path / "new", world, [], "swarm")
    monkeypatch.undo()
    assert {p.name: p.read_bytes() for p in path.iterdir()} == before
    no_leftovers(tmp_path, "b")


def test_bad_records_are_refused_before_writing(tmp_path: Path, ugv: RobotProfile) -> None:
    short = RobotEpisode("r", scans=(ScanRecord(0, (1.0, 2.0)),))
    with pytest.raises(ValueError, match="8 sensors"):
        write_episode_bag(tmp_path / "a", [short], ugv)
    nan = RobotEpisode("r", scans=(ScanRecord(0, (math.nan,) * 8),))
    with pytest.raises(ValueError, match="NaN"):
        write_episode_bag(tmp_path / "a", [nan], ugv)
    backwards = RobotEpisode("r", commands=(CmdRecord(5, 0.1, 0.0), CmdRecord(4, 0.1, 0.0)))
    with pytest.raises(ValueError, match="non-decreasing"):
        write_episode_bag(tmp_path / "a", [backwards], ugv)
    with pytest.raises(ValueError, match="namespace"):
        write_episode_bag(tmp_path / "a", [RobotEpisode("/abs")], ugv)
    with pytest.raises(ValueError, match="unique"):
        write_episode_bag(tmp_path / "a", [RobotEpisode("r"), RobotEpisode("r")], ugv)
    with pytest.raises(ValueError, match="JSON"):
        write_episode_bag(tmp_path / "a", [RobotEpisode("r")], ugv, {"x": math.nan})
    no_leftovers(tmp_path)


def test_truncated_copy_of_a_good_bag_does_not_affect_the_original(
    tmp_path: Path, world: World, scenarios: list[Scenario]
) -> None:
    write_scenario_bag(tmp_path / "good", world, scenarios, "ugv")
    shutil.copytree(tmp_path / "good", tmp_path / "cut")
    (mcap,) = (tmp_path / "cut").glob("*.mcap")
    mcap.write_bytes(mcap.read_bytes()[:100])
    assert_fault(tmp_path / "cut", read_scenario_bag)
    assert read_scenario_bag(tmp_path / "good")[0] == world


def test_episode_bag_carries_its_world(tmp_path: Path, ugv: RobotProfile, world: World) -> None:
    path = tmp_path / "with_world"
    write_episode_bag(path, episode_robots(ugv), ugv, {"k": 1}, world=world)
    log = read_episode_bag(path)
    assert log.world is not None and log.world == world
    np.testing.assert_array_equal(log.world.obstacles, world.obstacles)  # exact corners
    with AnyReader([path], default_typestore=TS) as reader:
        assert "/mentor/obstacles" in {c.topic for c in reader.connections}
    # without a world there is no obstacle topic and no world read back
    write_episode_bag(tmp_path / "plain", episode_robots(ugv), ugv)
    assert read_episode_bag(tmp_path / "plain").world is None
