"""Planar transforms and the frame tree (mentor_core.sim.transforms)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from mentor_core.sim.frames import yaw_to_quaternion
from mentor_core.sim.transforms import IDENTITY, FrameTree, Transform2D, planar_transform


def _close(a: tuple[float, ...], b: tuple[float, ...], tol: float = 1e-12) -> bool:
    return all(abs(math.remainder(x - y, 2 * math.pi) if i == 2 else x - y) <= tol
               for i, (x, y) in enumerate(zip(a, b, strict=True)))


def test_a_transform_maps_child_points_and_poses_into_the_parent() -> None:
    t = Transform2D(1.0, 2.0, math.pi / 2)
    assert _close(t.apply_point((1.0, 0.0)), (1.0, 3.0))
    assert _close(t.apply_pose((1.0, 0.0, math.pi / 2)), (1.0, 3.0, math.pi))
    back = t.inverse()
    assert _close(back.apply_pose(t.apply_pose((0.3, -0.7, 2.9))), (0.3, -0.7, 2.9))
    assert _close(t.compose(back).as_tuple(), (0.0, 0.0, 0.0))
    # composition: the child of the child
    a, b = Transform2D(0.5, -1.0, 0.3), Transform2D(2.0, 0.25, -1.1)
    p = (0.4, 0.9, 0.2)
    assert _close(a.compose(b).apply_pose(p), a.apply_pose(b.apply_pose(p)))


def test_the_identity_changes_no_number_at_all() -> None:
    rng = np.random.default_rng(3)
    for _ in range(100):
        pose = (float(rng.uniform(-50, 50)), float(rng.uniform(-50, 50)),
                float(rng.uniform(-math.pi, math.pi)))
        assert IDENTITY.apply_pose(pose) == pose
        assert IDENTITY.inverse().apply_pose(pose) == pose
    assert Transform2D.of([0, 0, 0]).is_identity
    assert Transform2D(0.0, 0.0, 2 * math.pi).yaw == pytest.approx(0.0, abs=1e-15)
    assert Transform2D(0.0, 0.0, -math.pi).yaw == math.pi  # wrapped to (-pi, pi]


def test_bad_transforms_are_refused() -> None:
    with pytest.raises(ValueError, match="finite"):
        Transform2D(math.nan, 0.0, 0.0)
    with pytest.raises(ValueError, match=r"\[x, y, yaw\]"):
        Transform2D.of([1.0, 2.0])


def test_planar_part_of_a_ros_transform() -> None:
    t, inverted = planar_transform((0.1, -0.2, 0.3), yaw_to_quaternion(0.7))
    assert not inverted and _close(t.as_tuple(), (0.1, -0.2, 0.7))
    # upside down (roll pi): the child's x axis still faces yaw, its y axis is mirrored
    half = 0.5 * 0.7
    roll = (math.cos(half), math.sin(half), 0.0, 0.0)  # rotation pi about the axis at 0.35 rad
    t, inverted = planar_transform((0.0, 0.0, 0.0), roll)
    assert inverted and _close(t.as_tuple(), (0.0, 0.0, 0.7))
    with pytest.raises(ValueError, match="tilted"):
        planar_transform((0, 0, 0), (math.sin(0.2), 0.0, 0.0, math.cos(0.2)))
    with pytest.raises(ValueError, match="unit quaternion"):
        planar_transform((0, 0, 0), (0.0, 0.0, 0.0, 0.0))


def test_the_tree_links_any_two_frames() -> None:
    tree = FrameTree()
    map_to_odom = Transform2D(1.0, -0.5, 0.3)
    odom_to_base = Transform2D(4.0, 2.0, -1.2)
    base_to_lidar = Transform2D(0.1, 0.0, math.pi)
    tree.link("map", "odom", map_to_odom)
    tree.link("odom", "r/base_link", odom_to_base)
    tree.link("r/base_link", "r/lidar", base_to_lidar)
    tree.link("r/base_link", "r/sensor_0", Transform2D(0.15, 0.0, 0.0))
    got = tree.lookup("map", "r/lidar")
    want = map_to_odom.compose(odom_to_base).compose(base_to_lidar)
    assert _close(got.as_tuple(), want.as_tuple())
    # siblings, and the way back
    sib = tree.lookup("r/sensor_0", "r/lidar")
    assert _close(sib.apply_point((0.0, 0.0)), (-0.05, 0.0))
    assert _close(tree.lookup("r/lidar", "map").as_tuple(), want.inverse().as_tuple())
    # the exact inverse for the planner's goal (odom <- map), as the simulator computes it
    assert tree.lookup("odom", "map") == map_to_odom.inverse()
    assert tree.lookup("odom", "odom") == IDENTITY
    with pytest.raises(LookupError, match="no transform from frame 'world'"):
        tree.lookup("map", "world")
    with pytest.raises(ValueError, match="loop"):
        tree.link("r/lidar", "map", IDENTITY)
