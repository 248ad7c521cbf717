"""Occupancy grids: ``nav_msgs/OccupancyGrid`` as a frozen dataclass, worlds rasterised into
grids, and grids merged back into obstacle boxes.

A grid is ``height x width`` square cells of side ``resolution`` (m). Cell ``(row, col)``
covers ``[col r, (col + 1) r] x [row r, (row + 1) r]`` in the grid's own frame, whose pose in
``map`` is ``origin = (x, y, yaw)`` (the lower-left corner of cell ``(0, 0)``), as in
``nav_msgs/MapMetaData``; ``data[row, col]`` is ``data[row * width + col]`` of the message:
-1 unknown, 0 free .. 100 occupied.

A cell is an obstacle when its value is at least ``lethal`` (100 by default, as Nav2's static
costmap layer's ``lethal_cost_threshold``) or, with ``unknown_is_obstacle``, unknown.

Worlds and grids (``world_grid``, ``world_from_grid``): a world rasterised at resolution ``r``
marks every cell whose square shares positive area with an obstacle box, or reaches past the
arena, so the obstacles it marks cover the world's obstacles. A grid turned into a world
(``world_from_grid``) keeps the grid's frame shifted so that cell ``(0, 0)``'s corner is the
arena's corner ``(0, 0)``; the arena is the square of the grid's larger side, the part beyond
a non-square grid's cells is filled with an obstacle, and the obstacle cells are merged into
few boxes (``grid_boxes``: maximal runs of each row, a run merged with the identical run of
the rows above), so rasterising that world at the grid's resolution gives the grid's obstacle
cells back exactly.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from mentor_core.sim.world import World

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
BoolArray = NDArray[np.bool_]

FREE = 0
OCCUPIED = 100
UNKNOWN = -1
#: cells at or above this value are obstacles (Nav2's static layer ``lethal_cost_threshold``)
LETHAL = 100
#: the most cells a map may hold (a 100 m square of 0.05 m cells): a planner keeps several
#: arrays a cell, so a finer map would exhaust memory before it answered
MAX_CELLS = 4_000_000
# rounding slack (in cells) when a box edge falls on a cell edge: 2.0 / 0.1 is 20.000000000000004
_EDGE_SLACK = 1e-9


@dataclass(frozen=True, eq=False)
class OccupancyGrid:
    """An occupancy grid (module docstring): ``resolution`` m per cell, ``origin`` the pose
    ``(x, y, yaw)`` (m, m, rad) of cell ``(0, 0)``'s lower-left corner in ``map``, ``data``
    a read-only int8 ``(height, width)`` array, row 0 at the origin.

    The constructor copies and checks (ValueError naming the fault): a positive finite
    resolution, a finite origin, a non-empty 2-D array of values in -1..100.
    """

    resolution: float
    origin: tuple[float, float, float]
    data: NDArray[np.int8]

    def __post_init__(self) -> None:
        res = float(self.resolution)
        if not (math.isfinite(res) and res > 0.0):
            raise ValueError(f"resolution must be a positive finite number, got {self.resolution}")
        origin = tuple(float(v) for v in self.origin)
        if len(origin) != 3 or not all(math.isfinite(v) for v in origin):
            raise ValueError(f"origin must be three finite numbers (x, y, yaw), got {origin}")
        raw = np.asarray(self.data)
        if raw.ndim != 2 or raw.size == 0:
            raise ValueError(f"occupancy data must be a non-empty 2-D array, got {raw.shape}")
        if raw.dtype.kind not in "iu" or raw.min() < UNKNOWN or raw.max() > OCCUPIED:
            raise ValueError("occupancy values must be integers in -1..100")
        data = raw.astype(np.int8, copy=True)
        data.setflags(write=False)
        object.__setattr__(self, "resolution", res)
        object.__setattr__(self, "origin", origin)
        object.__setattr__(self, "data", data)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, OccupancyGrid):
            return NotImplemented
        return (
            self.resolution == other.resolution
            and self.origin == other.origin
            and np.array_equal(self.data, other.data)
        )

    def __hash__(self) -> int:
        return hash((self.resolution, self.origin, self.data.shape, self.data.tobytes()))

    def __repr__(self) -> str:
        return (
            f"OccupancyGrid({self.width}x{self.height} cells of {self.resolution} m, "
            f"origin={self.origin})"
        )

    @property
    def width(self) -> int:
        """Cells along the grid's x axis (columns)."""
        return int(self.data.shape[1])

    @property
    def height(self) -> int:
        """Cells along the grid's y axis (rows)."""
        return int(self.data.shape[0])

    def obstacles(self, lethal: int = LETHAL, unknown_is_obstacle: bool = True) -> BoolArray:
        """``(height, width)``: True where a cell is an obstacle (module docstring)."""
        blocked = self.data >= lethal
        if unknown_is_obstacle:
            blocked |= self.data == UNKNOWN
        return np.asarray(blocked, dtype=np.bool_)

    def to_local(self, points: ArrayLike) -> FloatArray:
        """Points ``(n, 2)`` of ``map`` in the grid's own frame (cell units are ``r``)."""
        p = np.asarray(points, dtype=np.float64).reshape(-1, 2)
        x0, y0, yaw = self.origin
        c, s = math.cos(yaw), math.sin(yaw)
        dx, dy = p[:, 0] - x0, p[:, 1] - y0
        return np.stack([c * dx + s * dy, -s * dx + c * dy], axis=1)

    def to_map(self, local: ArrayLike) -> FloatArray:
        """Points ``(n, 2)`` of the grid's own frame in ``map``."""
        q = np.asarray(local, dtype=np.float64).reshape(-1, 2)
        x0, y0, yaw = self.origin
        c, s = math.cos(yaw), math.sin(yaw)
        return np.stack([x0 + c * q[:, 0] - s * q[:, 1], y0 + s * q[:, 0] + c * q[:, 1]], axis=1)

    def cells_of(self, points: ArrayLike) -> tuple[IntArray, IntArray]:
        """``(rows, cols)`` of the cells holding points ``(n, 2)`` of ``map`` (possibly
        outside the grid: check with :meth:`inside`)."""
        q = self.to_local(points) / self.resolution
        return np.floor(q[:, 1]).astype(np.int64), np.floor(q[:, 0]).astype(np.int64)

    def inside(self, rows: ArrayLike, cols: ArrayLike) -> BoolArray:
        """Whether cells ``(rows, cols)`` lie in the grid."""
        r, c = np.asarray(rows), np.asarray(cols)
        return np.asarray((r >= 0) & (r < self.height) & (c >= 0) & (c < self.width))

    def centres(self, rows: ArrayLike, cols: ArrayLike) -> FloatArray:
        """Centres ``(n, 2)`` in ``map`` of cells ``(rows, cols)``."""
        r = np.asarray(rows, dtype=np.float64).reshape(-1)
        c = np.asarray(cols, dtype=np.float64).reshape(-1)
        return self.to_map(np.stack([(c + 0.5), (r + 0.5)], axis=1) * self.resolution)


def disc_touches(occupied: BoolArray, point: ArrayLike, radius: float) -> bool:
    """Whether ``occupied`` ``(rows, cols)`` (cells of side 1, row 0 at y = 0) is True at the
    cell holding ``point`` (x, y, in cells) or at a cell whose centre lies within ``radius``
    cells of it: a robot of that radius cannot stand there."""
    x, y = (float(v) for v in np.asarray(point, dtype=np.float64).reshape(2))
    rows, cols = occupied.shape
    r0, r1 = max(0, math.floor(y - radius)), min(rows, math.floor(y + radius) + 1)
    c0, c1 = max(0, math.floor(x - radius)), min(cols, math.floor(x + radius) + 1)
    if r0 < r1 and c0 < c1:
        rr, cc = np.mgrid[r0:r1, c0:c1]
        near = (cc + 0.5 - x) ** 2 + (rr + 0.5 - y) ** 2 <= radius * radius
        if occupied[r0:r1, c0:c1][near].any():
            return True
    row, col = math.floor(y), math.floor(x)
    return bool(0 <= row < rows and 0 <= col < cols and occupied[row, col])


def grid_fault(size_x: float, size_y: float, resolution: float, what: str = "map") -> str:
    """Why a grid of ``size_x`` x ``size_y`` m in cells of ``resolution`` m must not be
    made (one line: it would hold more than :data:`MAX_CELLS` cells), or ''."""
    cells = math.ceil(size_x / resolution) * math.ceil(size_y / resolution)
    if cells <= MAX_CELLS:
        return ""
    return (f"{what} of {size_x:g} x {size_y:g} m in {resolution:g} m cells would hold "
            f"{cells:.3g} cells, more than {MAX_CELLS:.3g} (a coarser resolution or a "
            "smaller map)")


def world_grid(world: World, resolution: float) -> OccupancyGrid:
    """The world rasterised (module docstring): ``ceil(size / resolution)`` cells a side,
    origin ``(0, 0, 0)``; a cell is occupied (100) when its square shares positive area with
    an obstacle box or reaches past the arena, else free (0)."""
    res = float(resolution)
    if not (math.isfinite(res) and res > 0.0):
        raise ValueError(f"resolution must be a positive finite number, got {resolution}")
    fault = grid_fault(world.size, world.size, res, "a map of the world")
    if fault:
        raise ValueError(fault)
    n = max(1, math.ceil(world.size / res - _EDGE_SLACK))
    data = np.zeros((n, n), dtype=np.int8)
    lo, hi = _cell_span(world.obstacles, res)
    for (c0, r0), (c1, r1) in zip(lo.tolist(), hi.tolist(), strict=True):
        data[max(r0, 0) : r1, max(c0, 0) : c1] = OCCUPIED
    if n * res > world.size * (1.0 + _EDGE_SLACK):  # the last cells reach past the wall
        data[:, n - 1] = OCCUPIED
        data[n - 1, :] = OCCUPIED
    return OccupancyGrid(res, (0.0, 0.0, 0.0), data)


def _cell_span(boxes: FloatArray, res: float) -> tuple[IntArray, IntArray]:
    """First cells ``(k, 2)`` (col, row) and one-past-last cells of the boxes' interiors."""
    b = np.asarray(boxes, dtype=np.float64).reshape(-1, 4) / res
    lo = np.floor(b[:, :2] + _EDGE_SLACK).astype(np.int64)
    hi = np.maximum(np.ceil(b[:, 2:] - _EDGE_SLACK).astype(np.int64), lo + 1)
    return lo, hi


def grid_boxes(
    grid: OccupancyGrid, lethal: int = LETHAL, unknown_is_obstacle: bool = True
) -> FloatArray:
    """The obstacle cells merged into boxes ``(k, 4)`` ``[xmin, ymin, xmax, ymax]`` of the
    grid's own frame (m): each row's maximal runs, a run merged with the identical run of the
    next rows; the boxes cover the obstacle cells exactly and never overlap."""
    blocked = grid.obstacles(lethal, unknown_is_obstacle)
    rects: list[tuple[int, int, int, int]] = []  # col0, row0, col1, row1 (exclusive ends)
    open_runs: dict[tuple[int, int], int] = {}  # (col0, col1) -> first row
    for row in range(grid.height + 1):
        runs = set(_runs(blocked[row])) if row < grid.height else set()
        for run in [r for r in open_runs if r not in runs]:
            rects.append((run[0], open_runs.pop(run), run[1], row))
        for run in runs:
            open_runs.setdefault(run, row)
    rects.sort(key=lambda t: (t[1], t[0]))
    r = grid.resolution
    return np.array(
        [[c0 * r, r0 * r, c1 * r, r1 * r] for c0, r0, c1, r1 in rects], dtype=np.float64
    ).reshape(-1, 4)


def _runs(line: BoolArray) -> list[tuple[int, int]]:
    """Maximal runs ``[start, end)`` of True in a 1-D array."""
    edges = np.flatnonzero(np.diff(np.concatenate([[0], line.astype(np.int8), [0]])))
    return [(int(a), int(b)) for a, b in zip(edges[0::2], edges[1::2], strict=True)]


def world_from_grid(
    grid: OccupancyGrid,
    name: str = "",
    lethal: int = LETHAL,
    unknown_is_obstacle: bool = True,
) -> World:
    """The grid as a world (module docstring): arena side ``max(width, height) r``, cell
    ``(0, 0)``'s corner at ``(0, 0)``, the obstacle cells as boxes. ValueError for a grid
    rotated in ``map`` (yaw != 0): its cells are not axis-aligned boxes."""
    if grid.origin[2] != 0.0:
        raise ValueError(
            f"a map rotated by yaw {grid.origin[2]} rad cannot become axis-aligned boxes"
        )
    r = grid.resolution
    w, h = grid.width * r, grid.height * r
    size = max(grid.width, grid.height) * r
    boxes = [grid_boxes(grid, lethal, unknown_is_obstacle)]
    if grid.width < grid.height:  # beyond the map's cells: not free space
        boxes.append(np.array([[w, 0.0, size, size]]))
    elif grid.height < grid.width:
        boxes.append(np.array([[0.0, h, size, size]]))
    return World(size=size, obstacles=np.concatenate(boxes), name=name)
