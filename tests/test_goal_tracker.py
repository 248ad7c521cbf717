"""A goal's end as Nav2's goal and progress checkers judge it, a footprint as Nav2 gives it, a
goal the map shows cannot be reached, and the bounds on a node's periods and maps."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from mentor_core.navigation.grid import (
    MAX_CELLS,
    OCCUPIED,
    OccupancyGrid,
    disc_touches,
    grid_fault,
    world_grid,
)
from mentor_core.navigation.guide import guide_config
from mentor_core.navigation.scan_map import ScanMap
from mentor_core.runtime.footprint import footprint_box, with_footprint
from mentor_core.runtime.goal_tracker import (
    TIME_FLOOR,
    TIME_SLACK,
    GoalRules,
    GoalTracker,
    goal_rules,
)
from mentor_core.runtime.guided_planner import GuidedPlanner, ScanGuidedPlanner
from mentor_core.runtime.planner import GenomePlanner
from mentor_core.runtime.ros_arguments import MIN_PERIOD, period_fault
from mentor_core.runtime.velocity_limits import VelocityLimits
from mentor_core.sim.robots import get_profile
from mentor_core.sim.world import World

UGV = get_profile("ugv")
REGRESSION = Path(__file__).resolve().parents[1] / "bags" / "regression"


def test_a_goal_is_reached_within_its_radius() -> None:
    tracker = GoalTracker(GoalRules(radius=0.5), (4.0, 0.0), None, (0.0, 0.0, 0.0), 0.0)
    assert tracker.step((3.0, 0.0, 0.0), 1.0).kind == "drive"
    step = tracker.step((3.6, 0.0, 0.0), 2.0)
    assert step.kind == "reached" and step.distance == pytest.approx(0.4)


def test_a_heading_is_turned_to_in_place_without_passing_it() -> None:
    rules = GoalRules(radius=0.5, yaw_tolerance=0.1, turn_rate=1.0, period=0.5)
    tracker = GoalTracker(rules, (1.0, 0.0), math.pi / 2, (0.0, 0.0, 0.0), 0.0)
    assert tracker.step((0.9, 0.0, 0.0), 1.0).turn == pytest.approx(1.0)  # capped: 1 rad/s
    near = tracker.step((0.9, 0.0, math.pi / 2 - 0.3), 2.0)  # 0.3 rad left: 0.6 rad/s
    assert near.kind == "turn" and near.turn == pytest.approx(0.6)
    right = tracker.step((0.9, 0.0, math.pi), 3.0)  # past it: turn back
    assert right.kind == "turn" and right.turn < 0.0
    assert tracker.step((0.9, 0.0, math.pi / 2 + 0.05), 4.0).kind == "reached"
    # without a tolerance headings are ignored
    plain = GoalTracker(GoalRules(radius=0.5), (1.0, 0.0), math.pi / 2, (0.0, 0.0, 0.0), 0.0)
    assert plain.step((0.9, 0.0, 0.0), 1.0).kind == "reached"


def test_no_progress_aborts_as_nav2s_progress_checker() -> None:
    rules = GoalRules(radius=0.5, movement_radius=0.5, movement_time=10.0)
    tracker = GoalTracker(rules, (10.0, 0.0), None, (0.0, 0.0, 0.0), 0.0)
    assert tracker.step((0.4, 0.0, 0.0), 9.0).kind == "drive"
    assert tracker.step((0.6, 0.0, 0.0), 10.5).kind == "drive"  # moved 0.6 m: progress
    assert tracker.step((0.7, 0.0, 0.0), 20.0).kind == "drive"  # 9.5 s since
    step = tracker.step((0.8, 0.3, 0.0), 20.6)  # 0.36 m in 10.1 s
    assert step.kind == "aborted" and step.reason.startswith("no progress: moved less than 0.5 m")


def test_a_goal_out_of_time_aborts_and_the_default_limit_follows_its_distance() -> None:
    rules = GoalRules(radius=0.5, speed=0.5)
    tracker = GoalTracker(rules, (3.0, 4.0), None, (0.0, 0.0, 0.0), 100.0)
    assert tracker.limit == TIME_FLOOR + TIME_SLACK * 5.0 / 0.5
    assert tracker.step((1.0, 1.0, 0.0), 100.0 + tracker.limit).kind == "drive"
    step = tracker.step((1.0, 1.0, 0.0), 100.1 + tracker.limit)
    assert step.kind == "aborted" and step.reason.startswith("out of time")
    assert GoalRules(radius=0.5, time_limit=7.0).limit_for(100.0) == 7.0
    endless = GoalTracker(GoalRules(radius=0.5, time_limit=math.inf), (9.0, 0.0), None,
                          (0.0, 0.0, 0.0), 0.0)  # fmt: skip
    assert endless.step((1.0, 0.0, 0.0), 1e9).kind == "drive"


def test_goal_rules_take_the_robots_limits_and_defaults() -> None:
    limits = VelocityLimits(max_vel_x=0.22, max_vel_theta=0.5)
    rules = goal_rules(UGV, 0.4, limits, 0.5)
    assert (rules.speed, rules.turn_rate, rules.movement_radius, rules.period) == (
        0.22, 0.5, 0.2, 0.5)  # fmt: skip
    fast = goal_rules(UGV, 1.0, VelocityLimits(max_vel_x=5.0), 1.0, movement_time=0.0)
    assert fast.speed == UGV.rated_speed and fast.movement_radius == 0.0  # no check


@pytest.mark.parametrize("bad", [
    {"radius": 0.0}, {"radius": 1.0, "yaw_tolerance": math.pi}, {"radius": 1.0, "speed": -1},
    {"radius": 1.0, "time_limit": math.nan}, {"radius": 1.0, "movement_radius": math.inf},
])  # fmt: skip
def test_bad_goal_rules_are_refused(bad: dict[str, float]) -> None:
    with pytest.raises(ValueError):
        GoalRules(**bad)


def test_a_nav2_footprint_becomes_the_box_that_holds_it() -> None:
    # TurtleBot3 Waffle's footprint in its Nav2 parameters
    box = footprint_box("[[-0.205, -0.155], [-0.205, 0.155], [0.077, 0.155], [0.077, -0.155]]")
    assert box == pytest.approx((0.41, 0.31))
    assert footprint_box("", 0.105) == pytest.approx((0.21, 0.21))  # Burger: robot_radius
    assert footprint_box("", 0.0) is None
    profile = with_footprint(UGV, box)
    assert (profile.length, profile.width) == box and profile.sensors == UGV.sensors
    for bad in ("[[0, 0], [1, 1]]", "[[0, 0], [1], [1, 1]]", "not a list", "[[0, 0], [0, 0], "
                "[0, 0]]", "[[nan, 1], [1, 1], [1, 0]]"):  # fmt: skip
        with pytest.raises(ValueError, match="footprint"):
            footprint_box(bad)
    with pytest.raises(ValueError, match="robot_radius"):
        footprint_box("", -1.0)


def test_a_disc_touches_a_cell_within_its_radius_or_the_cell_under_it() -> None:
    occupied = np.zeros((10, 10), dtype=bool)
    occupied[5, 5] = True  # centre (5.5, 5.5)
    assert disc_touches(occupied, (5.2, 5.9), 0.0)  # in it
    assert disc_touches(occupied, (3.6, 5.5), 1.9) and not disc_touches(occupied, (3.4, 5.5), 1.9)
    assert not disc_touches(occupied, (-5.0, -5.0), 2.0)  # off the grid: nothing known


def test_a_goal_in_an_obstacle_of_the_map_or_the_scans_is_refused() -> None:
    planner = GenomePlanner.load(REGRESSION / "ugv_reference_genome.json", "ugv")
    config = guide_config(planner.profile)
    world = World(12.0, np.array([[4.0, 4.0, 6.0, 6.0]]))
    guided = GuidedPlanner(planner, config)
    assert guided.goal_fault((5.0, 5.0)) == ""  # no map yet
    guided.set_map(world_grid(world, 0.05))
    assert "lies in an obstacle of the map" in guided.goal_fault((5.0, 5.0))
    assert "lies in an obstacle" in guided.goal_fault((3.9, 5.0))  # the body would touch it
    assert guided.goal_fault((2.0, 2.0)) == ""
    scan = ScanGuidedPlanner(planner, config, 12.0)
    assert scan.goal_fault((5.0, 5.0)) == ""  # not seen yet
    # a ray from (4, 5) east ending at (5, 5): that cell read as an obstacle
    scan.scan.map.update([[4.0, 5.0, 0.0]], [1.0], 3.0)
    assert "the scans have seen" in scan.goal_fault((5.0, 5.0))
    assert scan.goal_fault((8.0, 8.0)) == ""


def test_a_goal_no_plan_reaches_is_not_refused_the_robot_steers_to_it() -> None:
    """A plan's inflated disc closes gaps the robot may pass (a TurtleBot3 Waffle's footprint
    in a forest: E091), so no path is no reason to give a goal up: the progress checker and the
    time limit judge it."""
    planner = GenomePlanner.load(REGRESSION / "ugv_reference_genome.json", "ugv")
    data = np.zeros((240, 240), dtype=np.int8)
    data[100:141, 100] = data[100:141, 140] = data[100, 100:141] = data[140, 100:141] = OCCUPIED
    guided = GuidedPlanner(planner, guide_config(planner.profile))
    guided.set_map(OccupancyGrid(0.05, (0.0, 0.0, 0.0), data))  # a closed room at 5-7 m
    guided.decide(np.full(8, np.inf), (1.0, 1.0, 0.0), (6.0, 6.0))
    assert guided.guide.path is None and guided.goal_fault((6.0, 6.0)) == ""


def test_maps_and_periods_that_would_exhaust_the_machine_are_refused() -> None:
    assert grid_fault(100.0, 100.0, 0.05) == ""
    fault = grid_fault(20.0, 20.0, 0.001, "the scan map")
    assert fault.startswith("the scan map of 20 x 20 m in 0.001 m cells") and "\n" not in fault
    assert str(MAX_CELLS)[:1] in fault
    with pytest.raises(ValueError, match="more than"):
        ScanMap(20.0, 0.001)
    with pytest.raises(ValueError, match="more than"):
        world_grid(World(12.0, np.zeros((0, 4))), 0.001)
    assert period_fault("control_period", MIN_PERIOD) == ""
    assert "shorter than the floor of 0.01 s" in period_fault("control_period", 0.0001)
    assert "not a period" in period_fault("x", 0.0)


def test_the_planners_tf_buffer_composes_the_latest_links_as_tf2_does() -> None:
    from mentor_core.runtime.tf_buffer import TfBuffer
    from mentor_core.sim.transforms import Transform2D

    tf = TfBuffer()
    tf.set("map", "odom", Transform2D(1.0, 0.0, math.pi / 2))
    tf.set("odom", "base_link", Transform2D(2.0, 0.0, 0.0))
    tf.set("base_link", "laser", Transform2D(0.1, 0.0, 0.0), inverted=True)
    pose, inverted = tf.lookup("map", "base_link")
    assert (pose.x, pose.y, pose.yaw) == pytest.approx((1.0, 2.0, math.pi / 2))
    assert not inverted
    mount, flipped = tf.lookup("base_link", "laser")
    assert mount.x == pytest.approx(0.1) and flipped
    assert tf.lookup("map", "laser")[1] and not tf.lookup("laser", "laser")[1]
    tf.set("odom", "base_link", Transform2D(3.0, 0.0, 0.0))  # the latest replaces
    assert tf.lookup("odom", "base_link")[0].x == 3.0
    with pytest.raises(LookupError):
        tf.lookup("map", "elsewhere")
