"""The planner's frames (mentor_core.runtime.planner_frames) and the goal checks it shares with
the simulator (mentor_core.runtime.goal_intake), with and without a TF lookup."""

from __future__ import annotations

import math

import pytest

from mentor_core.runtime.goal_intake import bounds_fault, bounds_in, same_goal
from mentor_core.runtime.planner_frames import PlannerFrames
from mentor_core.sim.scan_adapter import LidarMount
from mentor_core.sim.transforms import FrameTree, Transform2D

OFFSET = Transform2D(1.0, -0.5, 0.3)
MOUNT = Transform2D(0.05, 0.0, 0.2)


def test_without_tf_the_parameters_and_the_odometry_link_the_frames() -> None:
    frames = PlannerFrames(map_to_odom=OFFSET, lidar_mount=LidarMount(MOUNT))
    assert not frames.uses_tf
    frames.on_odometry("odom", "r/base_link", (2.0, 1.0, 0.5))
    odom, in_map = frames.goal("map", (4.0, 3.0))
    assert odom == OFFSET.inverse().apply_point((4.0, 3.0))  # exactly the simulator's numbers
    assert in_map == pytest.approx((4.0, 3.0))
    assert frames.goal("", (4.0, 3.0))[0] == odom  # no frame: the map's
    ahead, _ = frames.goal("r/base_link", (1.0, 0.0))
    assert ahead == pytest.approx(Transform2D(2.0, 1.0, 0.5).apply_point((1.0, 0.0)))
    with pytest.raises(LookupError):
        frames.goal("world", (0.0, 0.0))
    assert frames.mount("whatever_frame").pose == MOUNT  # the parameter, by any name
    # odometry in map already (odom = map): goals in map need no offset
    same = PlannerFrames(map_to_odom=OFFSET)
    same.on_odometry("map", "base_link", (0.0, 0.0, 0.0))
    assert same.goal("map", (4.0, 3.0)) == ((4.0, 3.0), (4.0, 3.0))


def test_with_tf_every_transform_comes_from_the_lookup() -> None:
    tree = FrameTree()
    tree.link("map", "odom", OFFSET)
    tree.link("odom", "base_footprint", Transform2D(3.0, 3.0, 0.0))
    tree.link("base_footprint", "laser", MOUNT)
    asked: list[tuple[str, str]] = []

    def lookup(target: str, source: str) -> tuple[Transform2D, bool]:
        asked.append((target, source))
        return tree.lookup(target, source), source == "laser"

    frames = PlannerFrames(lookup=lookup)
    frames.on_odometry("odom", "base_footprint", (3.0, 3.0, 0.0))
    mount = frames.mount("laser")
    assert mount.pose == MOUNT and mount.inverted  # as tf2 says, mirrored here
    assert asked[-1] == ("base_footprint", "laser")
    odom, in_map = frames.goal("map", (4.0, 3.0))
    assert odom == pytest.approx(OFFSET.inverse().apply_point((4.0, 3.0)))
    assert in_map == (4.0, 3.0)

    def no_map(target: str, source: str) -> tuple[Transform2D, bool]:
        if "map" in (target, source):
            raise LookupError(f"no map: {target} <- {source}")
        return Transform2D(), False

    lonely = PlannerFrames(lookup=no_map)
    assert lonely.goal("odom", (1.0, 1.0)) == ((1.0, 1.0), None)  # no map: no area check


def test_goal_checks() -> None:
    assert bounds_fault((2.0, 30.0), (0.0, 0.0, 12.0, 12.0)).endswith("refused")
    assert bounds_fault((2.0, 3.0), (0.0, 0.0, 12.0, 12.0)) == ""
    assert bounds_fault((2.0, 30.0), None) == ""  # no known area: no check
    assert same_goal((1.0, 1.0), (1.0, 1.0 + 1e-12)) and not same_goal((1.0, 1.0), (1.0, 1.1))
    assert same_goal(None, None) and not same_goal(None, (0.0, 0.0))


def test_an_area_seen_from_a_turned_frame_is_the_box_about_its_corners() -> None:
    arena = (0.0, 0.0, 4.0, 2.0)
    assert bounds_in(arena, Transform2D(0.0, 0.0, 0.0)) == arena
    assert bounds_in(arena, Transform2D(-1.0, 0.5, 0.0)) == (-1.0, 0.5, 3.0, 2.5)
    # a quarter turn: x' = -y, y' = x
    assert bounds_in(arena, Transform2D(0.0, 0.0, math.pi / 2)) == pytest.approx((-2, 0, 0, 4))
    # an eighth: the box about the turned rectangle is larger than it
    x0, y0, x1, y1 = bounds_in(arena, Transform2D(0.0, 0.0, math.pi / 4))
    assert (x1 - x0, y1 - y0) == pytest.approx((6 / math.sqrt(2), 6 / math.sqrt(2)))
