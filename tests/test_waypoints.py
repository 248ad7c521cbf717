"""Training planners to follow a plan (``guide: waypoint``; not in the paper): the goals the
networks see (navigation/waypoints.py) and the training problem under them."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from mentor_core.errors import ConfigError
from mentor_core.navigation import goal_distance, waypoints
from mentor_core.navigation.goal_distance import GoalDistance
from mentor_core.navigation.guide import GuideConfig
from mentor_core.navigation.shortest_path import VisibilityGraph
from mentor_core.navigation.waypoints import WaypointGoals
from mentor_core.sim.world import Scenario, World
from mentor_core.training.config import TrainerConfig
from mentor_core.training.problem import NavigationProblem
from mentor_core.training.trainer import make_problem

# a wall at x in [5, 5.4] from the floor up to y = 8 (the way round goes over its top)
WALL = World(12.0, np.array([[5.0, 0.0, 5.4, 8.0]]))
CONFIG = GuideConfig(lookahead=2.0, replan_distance=2.0, radius=0.2, margin=0.2,
                     resolution=0.05)  # fmt: skip


def test_in_sight_of_the_goal_the_network_sees_the_goal() -> None:
    scenarios = [Scenario(WALL, (8.0, 1.0, 0.0), (8.0, 4.0)),
                 Scenario(WALL, (2.0, 10.0, 0.0), (9.0, 10.5))]  # fmt: skip
    aims = WaypointGoals(scenarios, CONFIG, 1.0)
    poses = np.array([[8.0, 1.0, 0.3], [2.0, 10.0, 0.0], [11.0, 7.0, 2.0]])
    robots = np.array([0, 1, 2])  # robot 2 is on scenario 0 again (genome-major)
    # bit for bit the scenario's goal: the paper's inputs wherever the way is straight
    assert np.array_equal(aims(poses, robots), [[8.0, 4.0], [9.0, 10.5], [8.0, 4.0]])


def test_behind_a_wall_the_network_sees_the_corner_at_the_way_still_to_go() -> None:
    goal, goal_radius = (8.0, 4.0), 1.0
    aims = WaypointGoals([Scenario(WALL, (2.0, 4.0, 0.0), goal)], CONFIG, goal_radius)
    here = np.array([2.0, 4.0])
    aim = aims(np.array([[*here, 0.0]]), np.array([0]))[0]
    # the planner's disc (0.4 m) goes round the wall's grown top corner (4.6, 8.4)
    way = GoalDistance(VisibilityGraph(WALL, CONFIG.inflation), goal, goal_radius)
    corner = np.array([5.0 - CONFIG.inflation, 8.0 + CONFIG.inflation])
    assert np.allclose(way.waypoints([here])[0], corner)
    direction = (aim - here) / np.linalg.norm(aim - here)
    assert np.allclose(direction, (corner - here) / np.linalg.norm(corner - here))
    assert math.dist(aim, here) == pytest.approx(way([here])[0] + goal_radius)


def test_near_an_obstacle_the_bodys_way_then_the_goal() -> None:
    goal = (8.0, 4.0)
    aims = WaypointGoals([Scenario(WALL, (2.0, 4.0, 0.0), goal)], CONFIG, 1.0)
    # 0.3 m from the wall: inside the planner's disc, outside the body's
    near = np.array([4.7, 4.0])
    body = GoalDistance(VisibilityGraph(WALL, CONFIG.radius), goal, 1.0)
    corner = body.waypoints([near])[0]
    assert np.allclose(corner, [5.0 - CONFIG.radius, 8.0 + CONFIG.radius])
    aim = aims(np.array([[*near, 0.0], [5.2, 4.0, 0.0]]), np.array([0, 0]))
    assert np.allclose((aim[0] - near) / np.linalg.norm(aim[0] - near),
                       (corner - near) / np.linalg.norm(corner - near))  # fmt: skip
    # inside the wall: no way at all, the goal
    assert np.array_equal(aim[1], goal)


def test_guided_training_sees_the_way_and_scores_the_goal() -> None:
    config = dataclasses.replace(TrainerConfig(robot="ugv"), guide="waypoint")
    profile = make_problem(config).profile
    empty = World(12.0, np.zeros((0, 4)))
    open_scenarios = [Scenario(empty, (2.0, 6.0, 0.0), (8.0, 6.0)),
                      Scenario(empty, (6.0, 2.0, 1.0), (6.0, 10.0))]  # fmt: skip
    from mentor_core.evolution.loop import Evolution

    genomes = Evolution(config.evolution, profile.n_inputs, 2, seed=0, objectives=2).ask()[:6]
    # in the open the guided networks see their goals: the same numbers as unguided
    plain = NavigationProblem(profile, open_scenarios).evaluate(genomes)
    guided = NavigationProblem(profile, open_scenarios, guide="waypoint").evaluate(genomes)
    assert np.array_equal(plain.objectives, guided.objectives)
    # behind a wall they are shown the way round, and F still measures the real goal
    walled = [Scenario(WALL, (2.0, 4.0, 0.0), (8.0, 4.0))]
    straight = NavigationProblem(profile, walled).simulate(genomes)
    shown = NavigationProblem(profile, walled, guide="waypoint").simulate(genomes)
    assert not np.array_equal(straight.trajectories, shown.trajectories)
    assert np.array_equal(shown.final_distance, np.hypot(
        *(shown.final_position - np.array([8.0, 4.0])).T))  # fmt: skip
    with pytest.raises(ValueError, match="guide"):
        NavigationProblem(profile, walled, guide="map")  # type: ignore[arg-type]
    with pytest.raises(ConfigError, match="guide"):
        TrainerConfig.from_dict({"robot": "ugv", "guide": "map"})


def test_a_share_of_the_scenarios_is_guided() -> None:
    behind = Scenario(WALL, (2.0, 4.0, 0.0), (8.0, 4.0))
    aims = WaypointGoals([behind, behind], CONFIG, 1.0, guided=[False, True])
    shown = aims(np.array([[2.0, 4.0, 0.0]] * 4), np.array([0, 1, 2, 3]))
    assert np.array_equal(shown[[0, 2]], [[8.0, 4.0]] * 2)  # scenario 0: its goal
    assert not np.allclose(shown[[1, 3]], [8.0, 4.0])  # scenario 1: the way round
    with pytest.raises(ValueError, match="flags"):
        WaypointGoals([behind], CONFIG, 1.0, guided=[True, False])
    config = dataclasses.replace(TrainerConfig(robot="ugv"), guide="waypoint", guide_share=0.5)
    problem = make_problem(config)
    assert problem._input_goals is not None
    assert problem._input_goals.guided == [i % 2 == 1 for i in range(len(problem.scenarios))]
    with pytest.raises(ConfigError, match="guide_share"):
        TrainerConfig.from_dict({"robot": "ugv", "guide_share": 0})


def test_the_compiled_aims_are_numpys(monkeypatch: pytest.MonkeyPatch) -> None:
    # all robots of a decision in one compiled loop: bit for bit the per-scenario numpy
    # searches, in a world of many boxes with guided and unguided scenarios
    if waypoints._aims_numba is None:
        pytest.skip("numba is not importable")
    rng = np.random.default_rng(5)
    lo = np.round(rng.uniform(0.5, 10.0, (25, 2)), 1)
    world = World(12.0, np.concatenate([lo, lo + np.round(rng.uniform(0.1, 1.5, (25, 2)), 1)], 1))
    goals = np.round(rng.uniform(0.5, 11.5, (8, 2)), 1)
    scenarios = [Scenario(world, (0.3, 0.3, 0.0), tuple(g)) for g in goals]
    aims = WaypointGoals(scenarios, CONFIG, 0.5, guided=[True, False] * 4)
    poses = np.column_stack([np.round(rng.uniform(0.0, 12.0, (4000, 2)), 1),
                             rng.uniform(-3.0, 3.0, 4000)])  # fmt: skip
    robots = rng.integers(0, 100, 4000)
    fast = aims(poses, robots)
    with monkeypatch.context() as m:
        m.setattr(waypoints, "_aims_numba", None)
        m.setattr(goal_distance, "_first_corners_numba", None)
        slow = aims(poses, robots)
    bent = np.any(slow != goals[robots % 8], axis=1)
    assert bent.sum() > 500  # many robots are shown a way round, not their goal
    assert np.array_equal(fast, slow)
