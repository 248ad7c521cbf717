"""The grid planner: paths that keep a disc clear of every obstacle, close to the shortest
path for that disc (known in closed form round a wall's end), unknown cells, no-path cases."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import ndimage, sparse
from scipy.sparse import csgraph

from mentor_core.navigation import grid_search
from mentor_core.navigation.follow import cumulative_length, point_at
from mentor_core.navigation.grid import UNKNOWN, OccupancyGrid, world_grid
from mentor_core.navigation.grid_planner import GridPlanner, plan_path
from mentor_core.sim.collision import robot_collides
from mentor_core.sim.robots import get_profile
from mentor_core.sim.world import World

RES = 0.05
# a thin wall from the floor up to y = 6 at x = 5.9..6.1; start and goal low on either side
WALL = World(12.0, np.array([[5.9, 0.0, 6.1, 6.0]]))
START, GOAL = (2.0, 1.0), (10.0, 2.0)


def _samples(path: np.ndarray, step: float = RES / 10) -> np.ndarray:
    length = cumulative_length(path)[-1]
    return np.array([point_at(path, s) for s in np.arange(0.0, length + step, step)])


def _around_wall_end(rho: float) -> float:
    """The shortest path length from START to GOAL for a disc of radius ``rho``: over the
    wall's end, the inflated wall's top a straight piece between two rounded corners; from
    each end point a tangent to its corner's circle, then the arc up to the top."""
    total = 0.2  # across the wall's top
    for point, corner in ((START, (5.9, 6.0)), (GOAL, (6.1, 6.0))):
        d = math.dist(point, corner)
        from_up = math.acos((point[1] - corner[1]) / d)  # angle of the point from straight up
        total += math.sqrt(d * d - rho * rho) + rho * (from_up - math.acos(rho / d))
    return total


def test_round_a_wall_end_the_path_is_clear_and_close_to_the_shortest() -> None:
    radius = 0.3
    path = plan_path(world_grid(WALL, RES), START, GOAL, radius)
    assert path is not None
    np.testing.assert_allclose(path[0], START)
    np.testing.assert_allclose(path[-1], GOAL)
    assert len(path) < 12  # pulled straight, not one vertex per cell
    # collision-free for the disc: every point at least `radius` from the wall and the arena
    assert WALL.signed_distance(_samples(path)).min() >= radius - 1e-9
    # and for the UGV's body (inside the disc) at any heading
    ugv = get_profile("ugv")
    pts = _samples(path, 0.05)
    for heading in np.linspace(-np.pi, np.pi, 9):
        poses = np.c_[pts, np.full(len(pts), heading)]
        assert not robot_collides(poses, ugv, WALL).any()
    # no path clear of the disc is shorter than the exact one; ours is within the grid's
    # inflation (the planner keeps radius + sqrt(2) r from cell centres) of it
    length = cumulative_length(path)[-1]
    assert _around_wall_end(radius) <= length <= 1.01 * _around_wall_end(radius + 3 * RES)


def test_in_open_space_the_path_is_the_straight_line() -> None:
    world = World(6.0, np.zeros((0, 4)))
    path = plan_path(world_grid(world, 0.1), (1.03, 1.21), (4.88, 5.02), 0.2)
    assert path is not None
    np.testing.assert_allclose(path, [(1.03, 1.21), (4.88, 5.02)])


def test_a_doorway_narrower_than_the_disc_is_closed() -> None:
    # a wall across the arena with a 0.8 m door
    world = World(6.0, np.array([[0.0, 2.9, 2.6, 3.1], [3.4, 2.9, 6.0, 3.1]]))
    grid = world_grid(world, RES)
    through = plan_path(grid, (3.0, 1.0), (3.0, 5.0), 0.3)
    assert through is not None
    assert world.signed_distance(_samples(through)).min() >= 0.3 - 1e-9
    assert plan_path(grid, (3.0, 1.0), (3.0, 5.0), 0.45) is None


def test_unknown_cells_are_free_or_obstacles_as_asked() -> None:
    data = np.zeros((60, 60), dtype=np.int8)
    data[28:32, :] = UNKNOWN  # an unexplored band across the map
    grid = OccupancyGrid(0.1, (0.0, 0.0, 0.0), data)
    assert plan_path(grid, (3.0, 1.0), (3.0, 5.0), 0.2, allow_unknown=True) is not None
    assert plan_path(grid, (3.0, 1.0), (3.0, 5.0), 0.2, allow_unknown=False) is None


def test_start_and_goal_beside_walls_move_onto_the_nearest_traversable_cell() -> None:
    world = World(6.0, np.array([[2.0, 0.0, 2.2, 6.0]]))
    planner = GridPlanner(world_grid(world, RES), 0.3)
    path = planner.plan((1.85, 3.0), (1.0, 1.0))  # start 0.15 m from the wall
    assert path is not None
    assert math.dist(path[0], (1.85, 3.0)) <= planner.tolerance + RES
    assert world.signed_distance(_samples(path)).min() >= 0.3 - 1e-9
    # deep inside the wall, or out of the arena: farther than the tolerance, no plan
    assert planner.plan((2.1, 3.0), (1.0, 1.0)) is None
    assert planner.plan((1.0, 1.0), (8.0, 1.0)) is None
    # the other side of a wall that closes the arena: no plan either
    assert planner.plan((1.0, 1.0), (4.0, 1.0)) is None


def test_crossed_cells_are_exactly_the_cells_a_segment_enters() -> None:
    grid = OccupancyGrid(1.0, (0.0, 0.0, 0.0), np.zeros((5, 5), dtype=np.int8))
    planner = GridPlanner(grid, 0.0)
    rows, cols = planner.crossed_cells((0.5, 0.5), (3.5, 1.5))
    assert sorted(zip(rows.tolist(), cols.tolist(), strict=True)) == [
        (0, 0), (0, 1), (1, 2), (1, 3)
    ]  # through the corner (2, 1): the two cells it only touches are not entered
    rows, cols = planner.crossed_cells((0.5, 0.5), (0.5, 3.2))
    assert cols.tolist() == [0, 0, 0, 0] and rows.tolist() == [0, 1, 2, 3]


def test_the_compiled_line_of_sight_is_the_crossed_cells_test() -> None:
    # visible() and line_cost() run a compiled kernel reading clearances as it goes; they
    # must answer as the crossed cells on scipy's whole-map distance transform do, on grids
    # turned and moved, segments on grid lines included
    rng = np.random.default_rng(7)
    boxes = rng.uniform(0.0, 11.0, (30, 2))
    world = World(12.0, np.c_[boxes, np.minimum(boxes + rng.uniform(0.1, 1.0, (30, 2)), 12.0)])
    segments = rng.uniform(-1.0, 13.0, (600, 4))
    segments[:200] = np.round(segments[:200] / 0.1) * 0.1  # ends on cell corners
    segments[200:300, 3] = segments[200:300, 1]  # along a row
    for origin in ((0.0, 0.0, 0.0), (1.3, -2.1, 0.6)):
        grid = OccupancyGrid(0.1, origin, world_grid(world, 0.1).data)
        planner = GridPlanner(grid, 0.2)
        costly = GridPlanner(grid, 0.1, preferred=0.3, clearance_cost=2.0)
        padded = np.pad(grid.obstacles(), 1, constant_values=True)
        edt = ndimage.distance_transform_edt(~padded)[1:-1, 1:-1]
        seen, want = [], []
        for s in segments:
            rows, cols = planner.crossed_cells(s[:2], s[2:])
            inside = grid.inside(rows, cols).all()
            for radius in (None, 0.1):
                seen.append(planner.visible(s[:2], s[2:], radius))
                need = (0.2 if radius is None else radius) + np.sqrt(2.0) * 0.1
                want.append(bool(inside and (edt[rows, cols] * 0.1 >= need).all()))
        assert seen == want
        assert 0 < sum(seen) < len(seen)  # both answers occur
        # the costs: as the same kernel run as Python on scipy's clearances
        memo = np.where(edt <= costly._cap, np.rint(edt**2), grid_search.FAR).astype(np.int32)
        python = grid_search._along.py_func
        costs = [costly.line_cost(s[:2], s[2:]) for s in segments]
        need = 0.1 + np.sqrt(2.0) * 0.1
        field = (*costly._field[:2], memo, *costly._field[3:])
        reference = [python(*s, *costly._frame, field, need, 0.3, 0.2, 2.0, True)
                     for s in segments]  # fmt: skip
        np.testing.assert_allclose(costs, reference, rtol=1e-12)
        finite = np.isfinite(costs)
        assert 0 < finite.sum() < len(segments)
        # a segment's cost is at least its length, at most 1 + w times it
        length = np.hypot(*(segments[finite, 2:] - segments[finite, :2]).T)
        assert (np.asarray(costs)[finite] >= length * (1 - 1e-12)).all()
        assert (np.asarray(costs)[finite] <= 3.0 * length * (1 + 1e-12)).all()


def test_planning_on_a_rotated_map() -> None:
    # the wall map turned a quarter turn about the map origin: the path turns with it
    grid = world_grid(WALL, 0.1)
    turned = OccupancyGrid(0.1, (0.0, 0.0, math.pi / 2), grid.data)
    path = plan_path(turned, (-START[1], START[0]), (-GOAL[1], GOAL[0]), 0.3)
    assert path is not None
    back = np.c_[path[:, 1], -path[:, 0]]  # undo the turn
    assert WALL.signed_distance(_samples(back)).min() >= 0.3 - 1e-9


# two boxes 0.7 m apart across the way from START_GAP to GOAL_GAP; the way round them is long
GAP = World(6.0, np.array([[2.8, 0.0, 3.2, 2.65], [2.8, 3.35, 3.2, 6.0]]))
START_GAP, GOAL_GAP = (1.0, 3.0), (5.0, 3.0)


def _length(path: np.ndarray | None) -> float:
    assert path is not None
    return float(cumulative_length(path)[-1])


def test_a_clearance_cost_takes_a_narrow_gap_rather_than_the_long_way_round() -> None:
    grid = world_grid(GAP, RES)
    # a disc of 0.4 cannot pass the 0.7 m gap (and the boxes close the arena): no plan
    assert plan_path(grid, START_GAP, GOAL_GAP, 0.4) is None
    # a disc of 0.2 must be kept, 0.4 preferred: through the gap, keeping at least 0.2
    path = plan_path(grid, START_GAP, GOAL_GAP, 0.2, preferred=0.4, clearance_cost=3.0)
    assert _length(path) < 4.2
    assert path is not None and GAP.signed_distance(_samples(path)).min() >= 0.2 - 1e-9


def test_a_clearance_cost_keeps_the_preferred_disc_where_that_costs_little() -> None:
    # round a wall's end the cost keeps the preferred disc (to within a cell: the segments
    # pulled straight may cut into it where that costs less than the cells they skip), and
    # the path is about as long as the hard preferred disc's (the detour it saves is short)
    grid = world_grid(WALL, RES)
    hard = plan_path(grid, START, GOAL, 0.4)
    costly = plan_path(grid, START, GOAL, 0.2, preferred=0.4, clearance_cost=3.0)
    tight = plan_path(grid, START, GOAL, 0.2)
    assert costly is not None and hard is not None
    assert WALL.signed_distance(_samples(costly)).min() >= 0.4 - RES
    assert _length(tight) < _length(costly) <= 1.01 * _length(hard)
    # without a cost the preferred disc changes nothing
    np.testing.assert_array_equal(
        plan_path(grid, START, GOAL, 0.2, preferred=0.4, clearance_cost=0.0), tight
    )


def test_clearance_cost_settings_are_checked() -> None:
    grid = world_grid(WALL, 0.1)
    with pytest.raises(ValueError, match="preferred"):
        GridPlanner(grid, 0.3, preferred=0.2)
    with pytest.raises(ValueError, match="clearance_cost"):
        GridPlanner(grid, 0.3, preferred=0.5, clearance_cost=-1.0)


def _dijkstra_reference(
    clearance: np.ndarray, r: float, need: float, preferred: float, cost: float
) -> tuple[sparse.csr_matrix, np.ndarray]:
    """The planner's graph built whole, as it was before A*: traversable cells, 8-connected,
    no corner cutting, edges ``l (1 + w (q_a + q_b) / 2)``; and each cell's node (-1: none)."""
    t = clearance >= need
    node = np.full(t.shape, -1)
    node[t] = np.arange(int(t.sum()))
    span = preferred - (need - np.sqrt(2.0) * r)
    q = np.clip((preferred - (clearance - np.sqrt(2.0) * r)) / span, 0.0, 1.0) if cost else 0 * t
    rows, cols, weights = [], [], []
    h, w = t.shape
    for dr, dc in ((0, 1), (1, 0), (1, 1), (1, -1)):
        for i in range(h):
            for j in range(w):
                k, m = i + dr, j + dc
                if not (0 <= k < h and 0 <= m < w and t[i, j] and t[k, m]):
                    continue
                if dr and dc and not (t[i, m] and t[k, j]):
                    continue
                length = r * (np.sqrt(2.0) if dr and dc else 1.0)
                rows.append(node[i, j])
                cols.append(node[k, m])
                weights.append(length * (1.0 + cost * (q[i, j] + q[k, m]) / 2.0))
    n = int(t.sum())
    return sparse.coo_matrix((weights, (rows, cols)), shape=(n, n)).tocsr(), node


@pytest.mark.parametrize("cost", [0.0, 2.0])
def test_a_star_costs_what_dijkstra_on_the_whole_graph_costs(cost: float) -> None:
    # the independent reference: scipy's Dijkstra on the graph the planner built before
    rng = np.random.default_rng(3)
    r, radius, preferred = 0.1, 0.1, 0.3
    for trial in range(4):
        blocked = rng.random((40, 50)) < 0.08
        grid = OccupancyGrid(r, (0.0, 0.0, 0.0), np.where(blocked, 100, 0).astype(np.int8))
        planner = GridPlanner(grid, radius, preferred=preferred, clearance_cost=cost)
        padded = np.pad(blocked, 1, constant_values=True)
        clearance = ndimage.distance_transform_edt(~padded)[1:-1, 1:-1] * r
        need = radius + np.sqrt(2.0) * r
        graph, node = _dijkstra_reference(clearance, r, need, preferred, cost)
        cells = np.argwhere(clearance >= need)
        for _ in range(10):
            (a, b) = cells[rng.choice(len(cells), 2, replace=False)]
            want = csgraph.dijkstra(graph, directed=False, indices=node[a[0], a[1]])[
                node[b[0], b[1]]
            ]
            chain = grid_search.astar(planner._field, need, planner.preferred, planner._span,
                                      planner.clearance_cost, a[0] * 50 + a[1], b[0] * 50 + b[1])
            if not np.isfinite(want):
                assert len(chain) == 0
                continue
            rows, cols = chain // 50, chain % 50
            steps = np.hypot(np.diff(rows), np.diff(cols)) * r
            q = (np.clip((preferred - (clearance - np.sqrt(2.0) * r)) / (preferred - radius),
                         0.0, 1.0)[rows, cols] if cost else np.zeros(len(chain)))  # fmt: skip
            got = float(np.sum(steps * (1.0 + cost * (q[:-1] + q[1:]) / 2.0)))
            assert got == pytest.approx(want, rel=1e-12), trial
            assert (clearance[rows, cols] >= need).all()

