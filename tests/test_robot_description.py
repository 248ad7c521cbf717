"""A robot's frames and URDF from its profile (mentor_core.sim.robot_description), and the TF
tree the recordings carry (read back with rosbags' own reader, not ours)."""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest
from tf_support import tf_tree

from mentor_core.runtime.recording import EpisodeRecorder, record_planners
from mentor_core.sim.robot_description import (
    frame_id,
    robot_links,
    robot_urdf,
    urdf_joints,
)
from mentor_core.sim.robots import get_profile
from mentor_core.sim.transforms import Transform2D
from mentor_core.sim.world import Scenario, World

UGV = get_profile("ugv")
LIDAR = Transform2D(0.05, 0.0, 0.1)


def test_frames_come_from_the_profile() -> None:
    links = robot_links(UGV, "ugv_0", LIDAR)
    assert [link.child for link in links] == [f"ugv_0/sensor_{i}" for i in range(8)] + [
        "ugv_0/lidar"
    ]
    assert all(link.parent == "ugv_0/base_link" for link in links)
    for link, mount in zip(links, UGV.sensors, strict=False):
        x, y, yaw = link.transform.as_tuple()
        assert (x, y) == (mount.x, mount.y)
        assert abs(math.remainder(yaw - mount.angle, 2 * math.pi)) < 1e-12
    assert links[-1].transform == LIDAR
    assert frame_id("", "base_link") == "base_link" and frame_id("/a/b/", "lidar") == "a/b/lidar"
    assert len(robot_links(UGV)) == 8  # no lidar, no namespace


def test_the_urdf_never_disagrees_with_the_frames() -> None:
    text = robot_urdf(UGV, "ugv_0", LIDAR)
    root = ET.fromstring(text)
    assert root.tag == "robot" and root.get("name") == "ugv"
    names = {link.get("name") for link in root.iter("link")}
    assert names == {"ugv_0/base_link"} | {link.child for link in robot_links(UGV, "ugv_0", LIDAR)}
    box = root.find("link/visual/geometry/box")
    assert box is not None and box.get("size", "").split()[:2] == ["0.3", "0.25"]
    joints = urdf_joints(text)
    for link in robot_links(UGV, "ugv_0", LIDAR):
        parent, origin = joints[link.child]
        assert parent == link.parent
        assert origin == link.transform  # the same numbers, written with repr
    with pytest.raises(ValueError, match="not XML"):
        urdf_joints("<robot")


def test_a_recording_holds_thetf_tree(tmp_path: Path) -> None:
    world = World(12.0, name="open")
    scenario = Scenario(world, (2.0, 3.0, 0.5), (9.0, 9.0))
    recorder, traces = record_planners(
        world, UGV, {"ugv_0": lambda r, p, g: (0.1, 1.0)}, [scenario]
    )
    recorder.save(tmp_path / "bag", UGV)
    tree, stamps = tf_tree(tmp_path / "bag")
    assert len(stamps["ugv_0/base_link"]) == traces["ugv_0"][0].steps + 1  # every odometry
    start = tree.lookup("map", "ugv_0/base_link")
    assert start.as_tuple() == pytest.approx(scenario.start)
    sensor = tree.lookup("map", "ugv_0/sensor_0")
    mount = UGV.sensors[0]
    want = Transform2D(*scenario.start).compose(Transform2D(mount.x, mount.y, mount.angle))
    assert sensor.as_tuple() == pytest.approx(want.as_tuple())


def test_odom_apart_from_map_and_a_lidar_frame(tmp_path: Path) -> None:
    world = World(12.0)
    offset = Transform2D(1.5, -0.5, 0.3)
    recorder = EpisodeRecorder(world, 1.0, ["r"], map_to_odom=offset, lidar=LIDAR)
    pose_odom = (2.0, 1.0, -0.4)
    recorder.odometry("r", 0, pose_odom, (0.0, 0.0))
    recorder.save(tmp_path / "bag", UGV)
    tree, _ = tf_tree(tmp_path / "bag")
    assert tree.lookup("map", "odom") == offset
    got = tree.lookup("map", "r/lidar")
    want = offset.compose(Transform2D(*pose_odom)).compose(LIDAR)
    assert got.as_tuple() == pytest.approx(want.as_tuple(), abs=1e-12)
    assert math.isclose(recorder.metadata()["map_to_odom"][2], 0.3)
