"""The way round to a goal (navigation/goal_distance.py) and the geodesic final distance of the
performance objective (training/problem.py, ``goal_distance: geodesic``)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from mentor_core.navigation import goal_distance, shortest_path
from mentor_core.navigation.goal_distance import GoalDistance
from mentor_core.navigation.shortest_path import VisibilityGraph
from mentor_core.sim.episode import EpisodeBatch
from mentor_core.sim.robots import get_profile
from mentor_core.sim.world import Scenario, World
from mentor_core.training.config import TrainerConfig
from mentor_core.training.problem import NavigationProblem
from mentor_core.training.trainer import make_problem

# a wall at x in [5, 5.4] from the floor up to y = 8 (the way round goes over its top)
WALL = World(12.0, np.array([[5.0, 0.0, 5.4, 8.0]]))


def test_around_a_wall_exact() -> None:
    r, goal_radius = 0.1, 1.0
    to_goal = GoalDistance(VisibilityGraph(WALL, r), (8.0, 4.0), goal_radius)
    # from (2, 4): up to the grown corner (4.9, 8.1), along to (5.5, 8.1), down into the disc
    up = math.hypot(2.9, 4.1) + 0.6
    down = math.hypot(2.5, 4.1) - goal_radius
    assert to_goal([(2.0, 4.0)])[0] == pytest.approx(up + down, abs=1e-12)
    # in sight of the goal: the straight way, 0 inside the disc
    assert to_goal([(8.0, 1.0), (8.5, 4.0)]) == pytest.approx([2.0, 0.0], abs=1e-12)
    # inside the grown wall: not in the free space
    assert to_goal([(5.45, 4.0)])[0] == math.inf


def test_matches_the_graph_query_from_the_start() -> None:
    rng = np.random.default_rng(3)
    boxes = rng.uniform(0.0, 10.0, (12, 2))
    world = World(12.0, np.concatenate([boxes, boxes + rng.uniform(0.3, 2.0, (12, 2))], axis=1))
    graph = VisibilityGraph(world, 0.15)
    goal = (11.0, 11.0)
    to_goal = GoalDistance(graph, goal, 0.5)
    points = rng.uniform(0.0, 12.0, (300, 2))
    ours = to_goal(points)
    ref = np.array([graph.to_disc(p, goal, 0.5) for p in points])
    assert (np.isfinite(ours) == np.isfinite(ref)).all()
    assert (~np.isfinite(ours)).sum() < len(points)  # most points are free
    finite = np.isfinite(ref)
    assert ours[finite] == pytest.approx(ref[finite], rel=1e-12, abs=1e-12)
    # never shorter than the straight way
    straight = np.maximum(np.hypot(*(points - goal).T) - 0.5, 0.0)
    assert (ours[finite] >= straight[finite] - 1e-12).all()


def test_waypoints_head_along_the_shortest_way() -> None:
    to_goal = GoalDistance(VisibilityGraph(WALL, 0.1), (8.0, 4.0), 1.0)
    way = to_goal.waypoints([(2.0, 4.0), (8.0, 1.0), (5.45, 4.0)])
    assert way[0] == pytest.approx([4.9, 8.1], abs=1e-12)  # the grown wall's top corner
    assert way[1] == pytest.approx([8.0, 4.0])  # in sight: straight for the goal
    assert np.isnan(way[2]).all()  # inside the grown wall: no way
    # on random worlds, the way through the waypoint is the shortest way
    rng = np.random.default_rng(5)
    boxes = rng.uniform(0.0, 10.0, (12, 2))
    world = World(12.0, np.concatenate([boxes, boxes + rng.uniform(0.3, 2.0, (12, 2))], axis=1))
    to_goal = GoalDistance(VisibilityGraph(world, 0.15), (11.0, 11.0), 0.5)
    points = rng.uniform(0.0, 12.0, (200, 2))
    dist, way = to_goal(points), to_goal.waypoints(points)
    finite = np.isfinite(dist)
    assert (np.isnan(way[~finite])).all() and np.isfinite(way[finite]).all()
    corner = finite & (np.hypot(*(way - (11.0, 11.0)).T) > 1e-12)
    assert corner.sum() > 20
    through = np.hypot(*(points[corner] - way[corner]).T) + to_goal(way[corner])
    assert through == pytest.approx(dist[corner], rel=1e-12, abs=1e-12)


def test_compiled_visibility_gives_the_numpy_verdicts() -> None:
    if shortest_path._blocked_numba is None:
        pytest.skip("numba is not importable")
    rng = np.random.default_rng(1)
    lo = np.round(rng.uniform(0.0, 10.0, (30, 2)), 1)
    boxes = np.concatenate([lo, lo + np.round(rng.uniform(0.1, 2.0, (30, 2)), 1)], axis=1)
    p = np.round(rng.uniform(0.0, 12.0, (20_000, 2)), 1)
    q = np.round(rng.uniform(0.0, 12.0, (20_000, 2)), 1)
    q[::3, 0] = p[::3, 0]  # vertical, horizontal and zero-length segments, on box edges too
    q[1::5, 1] = p[1::5, 1]
    q[::17] = p[::17]
    compiled = np.empty(len(p), dtype=np.bool_)
    shortest_path._blocked_numba(p, q, boxes, compiled)
    assert (compiled == shortest_path._blocked(p, q, boxes)).all()


def _boxes_world(seed: int) -> World:
    """A 12 m world of 30 boxes on a 0.1 m grid: shared corners, touching and overlapping
    boxes, points on their edges."""
    rng = np.random.default_rng(seed)
    lo = np.round(rng.uniform(0.5, 10.0, (30, 2)), 1)
    return World(12.0, np.concatenate([lo, lo + np.round(rng.uniform(0.1, 1.5, (30, 2)), 1)], 1))


@pytest.mark.parametrize("radius", [0.0, 0.2, 0.35])
def test_compiled_search_gives_the_numpy_ways(
    radius: float, monkeypatch: pytest.MonkeyPatch
) -> None:  # fmt: skip
    # the compiled search visits the corners in order of their sums: the same distances and
    # first corners, bit for bit
    if goal_distance._first_corners_numba is None:
        pytest.skip("numba is not importable")
    graph = VisibilityGraph(_boxes_world(3), radius)
    rng = np.random.default_rng(4)
    points = np.round(rng.uniform(0.0, 12.0, (3000, 2)), 1)
    points[::7] = graph.nodes[rng.integers(0, len(graph.nodes), len(points[::7]))]
    for goal in ((11.0, 11.0), (1.0, 6.0), (6.0, 0.5)):
        way = GoalDistance(graph, goal, 0.5)
        fast = way.distances_and_waypoints(points)
        with monkeypatch.context() as m:
            m.setattr(goal_distance, "_first_corners_numba", None)
            slow = way.distances_and_waypoints(points)
        assert np.isfinite(fast[0]).sum() > 1000
        assert np.array_equal(fast[0], slow[0])
        assert np.array_equal(fast[1], slow[1], equal_nan=True)


def _batch(final: np.ndarray, goal: tuple[float, float], reached: bool = False) -> EpisodeBatch:
    n = len(final)
    start = np.tile([1.0, 4.0, 0.0], (n, 1))
    poses = np.stack([start, np.column_stack([final, np.zeros(n)])], axis=1)
    flag = np.full(n, reached)
    return EpisodeBatch(
        reached=flag, collided=~flag, timed_out=np.zeros(n, dtype=np.bool_),
        time_used=np.full(n, 5.0), time_budget=np.full(n, 50.0),
        final_distance=np.hypot(*(final - np.asarray(goal)).T),
        steps=np.ones(n, dtype=np.int64), trajectories=poses,
        experience=tuple(np.zeros((1, 4)) for _ in range(n)),
    )  # fmt: skip


def test_geodesic_final_distance_counts_the_way_round() -> None:
    ugv = get_profile("ugv")
    scenario = Scenario(WALL, (1.0, 4.0, 0.0), (8.0, 4.0))
    straight = NavigationProblem(ugv, [scenario])
    around = NavigationProblem(ugv, [scenario], goal_distance="geodesic")
    # two genomes: one stopped against the wall, one in the open in sight of the goal
    batch = _batch(np.array([[4.8, 4.0], [8.0, 10.0]]), scenario.goal)
    assert straight.final_distance(batch) == pytest.approx([3.2, 6.0])
    geodesic = around.final_distance(batch)
    assert geodesic[0] > 8.0  # up over the wall's top at y = 8 and down again
    assert geodesic[1] == pytest.approx(6.0, abs=1e-12)  # the straight way where it is free
    with pytest.raises(ValueError, match="goal_distance"):
        NavigationProblem(ugv, [scenario], goal_distance="manhattan")  # type: ignore[arg-type]


def test_config_key_builds_the_geodesic_problem() -> None:
    base = {"robot": "swarm", "n_scenarios": 3, "generations": 2, "stage1_generations": 1}
    assert make_problem(TrainerConfig.from_dict(base)).goal_distance == "euclidean"
    config = TrainerConfig.from_dict({**base, "goal_distance": "geodesic"})
    problem = make_problem(config)
    assert problem.goal_distance == "geodesic"
    with pytest.raises(ValueError, match="goal_distance"):
        TrainerConfig.from_dict({**base, "goal_distance": "sideways"})
