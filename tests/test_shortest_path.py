"""Shortest paths for a footprint on box worlds (navigation/shortest_path.py): exact lengths on
hand-made worlds, unreachable goals, and a check against a fine grid search."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import dijkstra

from mentor_core.navigation.shortest_path import VisibilityGraph, shortest_path
from mentor_core.sim.world import World


def test_round_one_box_exact() -> None:
    # box [4, 6]^2 grown by 0.5 to [3.5, 6.5]^2: round two of its corners
    world = World(10.0, np.array([[4.0, 4.0, 6.0, 6.0]]))
    found = shortest_path(world, (1.0, 5.0), (9.0, 5.0), 0.5)
    assert found is not None
    assert found.length == pytest.approx(2 * math.hypot(2.5, 1.5) + 3.0, abs=1e-12)
    assert found.points[0] == pytest.approx([1.0, 5.0])
    assert found.points[-1] == pytest.approx([9.0, 5.0])
    assert np.allclose(np.abs(found.points[1:3, 1] - 5.0), 1.5)  # via the grown corners
    assert found.length == pytest.approx(np.hypot(*np.diff(found.points, axis=0).T).sum())


def test_doorway_exact_and_closed_when_narrower_than_the_footprint() -> None:
    # a wall at x in [4, 4.3] with a door between y = 6 and y = 7.5
    wall = np.array([[4.0, 0.0, 4.3, 6.0], [4.0, 7.5, 4.3, 12.0]])
    world = World(12.0, wall)
    found = shortest_path(world, (1.0, 2.0), (9.0, 2.0), 0.5)
    assert found is not None
    # through the grown door corners (3.5, 6.5) and (4.8, 6.5)
    expected = math.hypot(2.5, 4.5) + 1.3 + math.hypot(4.2, 4.5)
    assert found.length == pytest.approx(expected, abs=1e-12)
    # a footprint of radius 0.76 m does not fit through the 1.5 m door
    assert shortest_path(world, (1.0, 2.0), (9.0, 2.0), 0.76) is None
    # exactly as wide as the door: the path touches both grown jambs and passes
    assert shortest_path(world, (1.0, 6.75), (9.0, 6.75), 0.75) is not None


def test_unreachable_goal_and_points_outside_free_space() -> None:
    world = World(10.0, np.array([[4.0, 0.0, 4.2, 10.0]]))  # splits the arena
    assert shortest_path(world, (1.0, 5.0), (9.0, 5.0), 0.2) is None
    graph = VisibilityGraph(world, 0.2)
    assert graph.length((1.0, 5.0), (9.0, 5.0)) == math.inf
    # too near the arena's wall, or inside a grown box
    assert graph.path((0.1, 5.0), (2.0, 5.0)) is None
    assert graph.path((3.9, 5.0), (2.0, 5.0)) is None


def test_empty_world_is_the_straight_line() -> None:
    world = World(10.0)
    found = shortest_path(world, (1.0, 1.0), (4.0, 5.0), 0.3)
    assert found is not None and found.length == pytest.approx(5.0)
    assert len(found.points) == 2


def test_visibility_touching_is_free_crossing_is_not() -> None:
    graph = VisibilityGraph(World(10.0, np.array([[4.0, 4.0, 6.0, 6.0]])), 0.0)
    a = np.array([[4.0, 2.0], [2.0, 2.0], [3.0, 5.0], [2.0, 4.0]])
    b = np.array([[4.0, 8.0], [8.0, 8.0], [7.0, 5.0], [6.0, 8.0]])
    # along an edge; through two opposite corners (the diagonal crosses the box); straight
    # through; touching one corner (4, 6) from outside
    assert graph.visible(a, b).tolist() == [True, False, False, True]
    corner = graph.visible([[2.0, 4.0]], [[4.0, 6.0]])  # ends on a corner, outside
    assert corner.tolist() == [True]


def test_to_disc_is_the_path_less_the_goal_radius_when_the_last_leg_is_clear() -> None:
    world = World(10.0, np.array([[4.0, 4.0, 6.0, 6.0]]))
    graph = VisibilityGraph(world, 0.5)
    full = graph.length((1.0, 5.0), (9.0, 5.0))
    assert graph.to_disc((1.0, 5.0), (9.0, 5.0), 1.0) == pytest.approx(full - 1.0)
    assert graph.to_disc((1.0, 1.0), (1.5, 1.0), 1.0) == 0.0
    assert VisibilityGraph(World(10.0), 0.2).to_disc((1.0, 1.0), (4.0, 5.0), 1.0) == (
        pytest.approx(4.0))


def test_ends_lets_start_and_goal_keep_a_smaller_clearance() -> None:
    world = World(10.0, np.array([[4.0, 4.0, 6.0, 6.0]]))
    wide, tight = VisibilityGraph(world, 1.0), VisibilityGraph(world, 0.3)
    start, goal = (3.4, 5.0), (6.6, 5.0)  # 0.6 m from the box: free for 0.3 m, not for 1 m
    assert wide.path(start, goal) is None
    found = wide.path(start, goal, ends=tight)
    assert found is not None
    # the middle of the path keeps 1 m: round the box grown by 1 m, [3, 7]^2
    assert np.allclose(np.abs(found.points[1:-1, 1] - 5.0), [2.0, 2.0])
    assert found.length == pytest.approx(2 * math.hypot(0.4, 2.0) + 4.0, abs=1e-12)


def _grid_length(world: World, radius: float, start: tuple[float, float],
                 goal: tuple[float, float], cell: float) -> float:
    """Shortest 8-connected grid path between cells free for the footprint (cell centres,
    both ends and every move's midpoint in free space): an upper bound of the exact path."""
    n = round(world.size / cell)
    centres = (np.arange(n) + 0.5) * cell
    gx, gy = np.meshgrid(centres, centres, indexing="ij")
    graph = VisibilityGraph(world, radius)
    free = graph.free(np.column_stack([gx.ravel(), gy.ravel()])).reshape(n, n)
    rows, cols, weights = [], [], []
    fi, fj = np.nonzero(free)
    for di, dj in ((1, 0), (0, 1), (1, 1), (1, -1)):
        i2, j2 = fi + di, fj + dj
        inside = (i2 >= 0) & (i2 < n) & (j2 >= 0) & (j2 < n)
        i1, j1, i2, j2 = fi[inside], fj[inside], i2[inside], j2[inside]
        keep = free[i2, j2]
        i1, j1, i2, j2 = i1[keep], j1[keep], i2[keep], j2[keep]
        ok = graph.visible(np.column_stack([centres[i1], centres[j1]]),
                           np.column_stack([centres[i2], centres[j2]]))
        rows += list((i1 * n + j1)[ok])
        cols += list((i2 * n + j2)[ok])
        weights += [cell * math.hypot(di, dj)] * int(ok.sum())
    matrix = coo_matrix((weights, (rows, cols)), shape=(n * n, n * n)).tocsr()
    si, sj = (int(v / cell) for v in start)
    ti, tj = (int(v / cell) for v in goal)
    dist = dijkstra(matrix, directed=False, indices=si * n + sj)[ti * n + tj]
    return float(dist)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_against_a_fine_grid_search(seed: int) -> None:
    """The exact length is never above an 8-connected grid path, and that path is at most
    the octile detour (8.3 %) plus a cell per end longer."""
    rng = np.random.default_rng(seed)
    boxes: list[list[float]] = []
    while len(boxes) < 6:
        x, y = rng.uniform(1.0, 8.0, 2)
        w, h = rng.uniform(0.3, 1.5, 2)
        box = [x, y, x + w, y + h]
        if all(min(box[2], b[2]) - max(box[0], b[0]) <= -0.3
               or min(box[3], b[3]) - max(box[1], b[1]) <= -0.3 for b in boxes):
            boxes.append(box)
    world = World(10.0, np.array(boxes))
    cell = 0.05
    start, goal = (0.525, 0.525), (9.475, 9.475)  # cell centres
    exact = VisibilityGraph(world, 0.3).length(start, goal)
    grid = _grid_length(world, 0.3, start, goal, cell)
    assert math.isfinite(exact)
    assert exact <= grid + 1e-9
    assert grid <= exact * (1.0 + (1.0 / math.cos(math.pi / 8) - 1.0)) + 2 * cell
