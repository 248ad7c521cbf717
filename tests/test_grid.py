"""Occupancy grids: invariants, frames, worlds rasterised into grids, grids merged into boxes."""

from __future__ import annotations

import math

import numpy as np
import pytest

from mentor_core.navigation.grid import (
    OCCUPIED,
    UNKNOWN,
    OccupancyGrid,
    grid_boxes,
    world_from_grid,
    world_grid,
)
from mentor_core.sim.world import World


def _blobs(rng: np.random.Generator, shape: tuple[int, int], n: int) -> np.ndarray:
    """A grid of free cells with ``n`` random occupied rectangles and some unknown cells."""
    data = np.zeros(shape, dtype=np.int8)
    for _ in range(n):
        r0, c0 = rng.integers(0, shape[0]), rng.integers(0, shape[1])
        data[r0 : r0 + rng.integers(1, 8), c0 : c0 + rng.integers(1, 8)] = OCCUPIED
    data[rng.random(shape) < 0.02] = UNKNOWN
    return data


@pytest.mark.parametrize(
    ("kwargs", "fault"),
    [
        ({"resolution": 0.0}, "resolution"),
        ({"resolution": math.nan}, "resolution"),
        ({"origin": (0.0, 0.0)}, "origin"),
        ({"origin": (0.0, math.inf, 0.0)}, "origin"),
        ({"data": np.zeros((0, 3), dtype=np.int8)}, "non-empty 2-D"),
        ({"data": np.zeros(4, dtype=np.int8)}, "non-empty 2-D"),
        ({"data": np.full((2, 2), 101)}, "-1..100"),
        ({"data": np.full((2, 2), -2)}, "-1..100"),
        ({"data": np.full((2, 2), 0.5)}, "integers"),
    ],
)
def test_bad_grids_are_refused(kwargs: dict[str, object], fault: str) -> None:
    args: dict[str, object] = {
        "resolution": 0.1, "origin": (0.0, 0.0, 0.0), "data": np.zeros((2, 2), dtype=np.int8)
    }
    args.update(kwargs)
    with pytest.raises(ValueError, match=fault):
        OccupancyGrid(**args)  # type: ignore[arg-type]


def test_grid_data_is_a_read_only_int8_copy_and_equality_compares_values() -> None:
    source = np.zeros((2, 3), dtype=np.int64)
    grid = OccupancyGrid(0.5, (1.0, 2.0, 0.0), source)
    source[0, 0] = 100
    assert grid.data.dtype == np.int8 and grid.data[0, 0] == 0
    assert (grid.width, grid.height) == (3, 2)
    with pytest.raises(ValueError):
        grid.data[0, 0] = 1
    assert grid == OccupancyGrid(0.5, (1.0, 2.0, 0.0), np.zeros((2, 3), dtype=np.int8))
    assert grid != OccupancyGrid(0.5, (1.0, 2.5, 0.0), np.zeros((2, 3), dtype=np.int8))
    assert len({grid, OccupancyGrid(0.5, (1.0, 2.0, 0.0), np.zeros((2, 3)).astype(int))}) == 1


def test_cells_and_centres_follow_the_origin_pose() -> None:
    grid = OccupancyGrid(0.5, (1.0, 2.0, math.pi / 2), np.zeros((4, 6), dtype=np.int8))
    # rotated a quarter turn: the grid's x axis is map's y axis
    centre = grid.centres([0], [2])[0]
    np.testing.assert_allclose(centre, (1.0 - 0.25, 2.0 + 1.25), atol=1e-12)
    rows, cols = grid.cells_of([centre, (0.0, 0.0)])
    assert (rows[0], cols[0]) == (0, 2)
    assert not grid.inside(rows, cols)[1]
    np.testing.assert_allclose(grid.to_map(grid.to_local([(3.0, -1.0)])), [(3.0, -1.0)])


def test_a_world_rasterises_to_the_cells_its_boxes_cover() -> None:
    # one box on cell edges, one between them, one thinner than a cell
    world = World(2.0, np.array([[0.5, 0.5, 1.0, 0.75], [1.22, 1.31, 1.38, 1.49],
                                 [0.02, 1.9, 0.03, 1.95]]))
    grid = world_grid(world, 0.25)
    expected = np.zeros((8, 8), dtype=bool)
    expected[2, 2:4] = True  # exactly [0.5, 1.0] x [0.5, 0.75]
    expected[5, 4:6] = True  # x 1.22-1.38 touches columns 4, 5; y 1.31-1.49 row 5
    expected[7, 0] = True
    np.testing.assert_array_equal(grid.data == OCCUPIED, expected)
    assert grid.origin == (0.0, 0.0, 0.0) and grid.resolution == 0.25
    # an arena that is no whole number of cells: the last row and column reach past the wall
    partial = world_grid(World(1.1, np.zeros((0, 4))), 0.25)
    assert partial.data.shape == (5, 5)
    assert (partial.data[-1] == OCCUPIED).all() and (partial.data[:, -1] == OCCUPIED).all()
    assert (partial.data[:-1, :-1] == 0).all()


def test_boxes_cover_the_obstacle_cells_exactly_without_overlap() -> None:
    rng = np.random.default_rng(3)
    data = _blobs(rng, (40, 40), 25)
    grid = OccupancyGrid(0.1, (0.0, 0.0, 0.0), data)
    boxes = grid_boxes(grid)
    cells = np.zeros(data.shape, dtype=int)
    for x0, y0, x1, y1 in np.rint(boxes / 0.1).astype(int):
        cells[y0:y1, x0:x1] += 1
    np.testing.assert_array_equal(cells, grid.obstacles().astype(int))  # once each, exactly
    assert len(boxes) < 0.5 * grid.obstacles().sum()  # merged, not one box per cell
    free_unknown = grid_boxes(grid, unknown_is_obstacle=False)
    assert len(free_unknown) < len(boxes)
    # one rectangle is one box; an L is two
    rect = np.zeros((10, 10), dtype=np.int8)
    rect[2:6, 3:9] = OCCUPIED
    assert grid_boxes(OccupancyGrid(1.0, (0, 0, 0), rect)).tolist() == [[3.0, 2.0, 9.0, 6.0]]
    rect[6:9, 3:5] = OCCUPIED
    assert len(grid_boxes(OccupancyGrid(1.0, (0, 0, 0), rect))) == 2


@pytest.mark.parametrize(("shape", "res"), [((40, 40), 0.1), ((30, 50), 0.05), ((50, 30), 0.3)])
def test_grid_to_boxes_to_grid_round_trip(shape: tuple[int, int], res: float) -> None:
    rng = np.random.default_rng(shape[0] + shape[1])
    grid = OccupancyGrid(res, (-3.0, 7.5, 0.0), _blobs(rng, shape, 30))
    world = world_from_grid(grid, name="blobs")
    assert world.name == "blobs"
    assert world.size == pytest.approx(max(shape) * res)
    back = world_grid(world, res)
    assert back.data.shape == (max(shape), max(shape))
    h, w = shape
    np.testing.assert_array_equal(back.data[:h, :w] == OCCUPIED, grid.obstacles())
    # beyond a non-square map's cells: obstacle
    assert (back.data[h:, :] == OCCUPIED).all() and (back.data[:, w:] == OCCUPIED).all()


def test_a_rotated_grid_cannot_become_boxes() -> None:
    grid = OccupancyGrid(0.1, (0.0, 0.0, 0.3), np.zeros((3, 3), dtype=np.int8))
    with pytest.raises(ValueError, match="rotated"):
        world_from_grid(grid)
