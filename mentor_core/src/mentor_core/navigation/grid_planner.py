"""Shortest paths on an occupancy grid for a robot's footprint (a global planner, as Nav2's).

1. Inflation. A cell is *traversable* when the distance from its centre to the nearest
   obstacle cell's centre (``scipy.ndimage.distance_transform_edt``; the outside of the grid
   counts as obstacle) is at least ``radius + sqrt(2) r`` (``r`` the resolution). Then every
   point of a traversable cell's square is at least ``radius`` from every obstacle cell's
   square (centre to square: ``- r / sqrt(2)``; point to its cell's centre: ``- r /
   sqrt(2)``), so a disc of radius ``radius`` (the footprint's circumscribed circle, plus a
   margin) anywhere on such a square touches no obstacle cell.
2. Search. A* (:mod:`~mentor_core.navigation.grid_search`, compiled) on the 8-connected
   graph of traversable cells, edges of length ``r`` and ``sqrt(2) r``; a diagonal step only
   where both cells beside it are traversable too, so the segments between cell centres stay
   on traversable squares. Its cost is Dijkstra's on that graph (what this planner ran
   before, ``scipy.sparse.csgraph.dijkstra``); each cell's clearance is found when the search
   first reaches it, so a plan across a large map reads only the cells near its way.
3. Shortcut. The cell path (from the start point to the goal point where their cells are
   traversable) is pulled straight: from each kept point, the farthest next point in sight
   (every cell the segment crosses, found exactly from its grid-line crossings, is
   traversable) is kept, so the path is no longer grid-jagged and still lies on traversable
   squares: collision-free for the disc.

A start or goal whose cell is not traversable (a robot close to a wall, a goal beside one)
is moved to the nearest traversable cell within ``tolerance``; farther, or with no path
between them, there is no plan (None). Unknown cells are free with ``allow_unknown`` (Nav2's
NavFn default), obstacles otherwise.

A clearance cost (``preferred > radius``; Nav2's inflation layer, which makes cells near an
obstacle costly rather than forbidden): the disc of ``radius`` is all a cell must give, and
a step onto cells that give less than ``preferred`` costs more. A cell whose square keeps
``c = clearance - sqrt(2) r`` from every obstacle has the penalty

    q = clip((preferred - c) / (preferred - radius), 0, 1),

and a step of length ``l`` between cells of penalties ``q_a, q_b`` weighs
``l (1 + w (q_a + q_b) / 2)`` (``w`` = ``clearance_cost``). So the plan keeps ``preferred``
clear where that costs little and takes a narrower gap where the way round is long: the
hard disc of ``preferred`` alone closes every gap narrower than ``2 preferred``. Pulled
straight (step 3), a segment replaces the points it skips only where it costs no more than
they do, its length in each cell it crosses weighed by that cell's ``1 + w q``
(Theta*'s test with costs): the shortcut does not cut nearer an obstacle than the search
chose to.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import ndimage

from mentor_core.navigation import grid_search
from mentor_core.navigation.grid import LETHAL, OccupancyGrid

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]
_SQRT2 = math.sqrt(2.0)


class GridPlanner:
    """Shortest paths on ``grid`` for a disc of ``radius`` m (module docstring).

    Args:
        grid: the map.
        radius: m, the footprint's circumscribed radius (``RobotProfile.half_diagonal``) plus
            any safety margin.
        allow_unknown: unknown cells are free (True) or obstacles.
        lethal: cells at or above this value are obstacles.
        tolerance: m, how far a start or goal may be moved onto a traversable cell (None:
            ``radius + 2 r``).
        preferred: m, the clearance the plan keeps where it can, at least ``radius`` (None,
            or no ``clearance_cost``: ``radius``, no cost).
        clearance_cost: ``w`` of the clearance cost (module docstring), >= 0.
    """

    def __init__(
        self,
        grid: OccupancyGrid,
        radius: float,
        *,
        allow_unknown: bool = True,
        lethal: int = LETHAL,
        tolerance: float | None = None,
        preferred: float | None = None,
        clearance_cost: float = 0.0,
    ) -> None:
        if not (math.isfinite(radius) and radius >= 0.0):
            raise ValueError(f"radius must be a finite number >= 0, got {radius}")
        if preferred is not None and not (math.isfinite(preferred) and preferred >= radius):
            raise ValueError(f"preferred must be a finite number >= radius ({radius}), "
                             f"got {preferred}")  # fmt: skip
        if not (math.isfinite(clearance_cost) and clearance_cost >= 0.0):
            raise ValueError(f"clearance_cost must be a finite number >= 0, got {clearance_cost}")
        self.grid = grid
        self.radius = float(radius)
        #: the clearance the plan keeps where it can (m; ``radius``: no clearance cost)
        self.preferred = (
            self.radius if preferred is None or clearance_cost == 0.0 else float(preferred)
        )
        self.clearance_cost = float(clearance_cost) if self.preferred > self.radius else 0.0
        r = grid.resolution
        self.tolerance = self.radius + 2.0 * r if tolerance is None else float(tolerance)
        #: the obstacle cells, padded by one obstacle cell each side (the outside of the grid)
        self._blocked = np.pad(grid.obstacles(lethal, not allow_unknown), 1, constant_values=True)
        self._blocks = grid_search.block_counts(self._blocked)
        # clearances matter up to the preferred disc's need: beyond, every cell is alike
        self._cap = math.ceil(self._need(self.preferred) / r) + 1
        #: the squared clearances (cells) found so far (:mod:`.grid_search`)
        self._memo: NDArray[np.int32] = np.full((grid.height, grid.width), -1, dtype=np.int32)
        x0, y0, yaw = grid.origin  # OccupancyGrid.to_local's terms, for the line tests
        self._frame = (float(x0), float(y0), math.cos(yaw), math.sin(yaw))
        self._field: grid_search.Field = (self._blocked, self._blocks, self._memo, self._cap, r)

    def _need(self, radius: float) -> float:
        """The clearance (m) a cell's centre needs for a disc of ``radius`` on all its square."""
        return radius + _SQRT2 * self.grid.resolution

    def free_for(self, radius: float) -> BoolArray:
        """``(height, width)``: cells a disc of ``radius`` m may stand on anywhere (the whole
        map at once: for inspection; the search reads cells as it goes)."""
        clearance = ndimage.distance_transform_edt(~self._blocked)[1:-1, 1:-1]
        clearance = clearance * self.grid.resolution
        return np.asarray(clearance >= self._need(radius))

    def _cell(self, xy: ArrayLike) -> tuple[int, int, bool] | None:
        """Traversable cell ``(row, col, exact)`` for a point: its own (``exact``) or the
        nearest within ``tolerance``; None when there is none."""
        rows, cols = self.grid.cells_of(np.asarray(xy, dtype=np.float64)[:2])
        row, col = int(rows[0]), int(cols[0])
        h, w = self.grid.height, self.grid.width
        need, r = self._need(self.radius), self.grid.resolution
        inside = 0 <= row < h and 0 <= col < w
        if inside and self._clearance(row, col) >= need:
            return row, col, True
        # the nearest traversable cell (from the nearest border cell for a point outside the
        # grid), within the tolerance checked below
        r_in, c_in = min(max(row, 0), h - 1), min(max(col, 0), w - 1)
        reach = math.ceil((self.tolerance + r) / r) + 2
        found = grid_search.nearest(self._field, need, r_in, c_in, reach)
        if found < 0:
            return None
        rr, cc = divmod(found, w)
        centre = self.grid.centres([rr], [cc])[0]
        point = np.asarray(xy, dtype=np.float64)[:2]
        if float(np.hypot(*(centre - point))) > self.tolerance + r:
            return None
        return rr, cc, False

    def _clearance(self, row: int, col: int) -> float:
        return grid_search.clearance(self._field, row, col)

    def plan(self, start: ArrayLike, goal: ArrayLike) -> FloatArray | None:
        """A collision-free path ``(k, 2)`` (m, ``map``) from ``start`` to ``goal`` (x, y),
        shortest on the grid then pulled straight; None when there is none."""
        a, b = self._cell(start), self._cell(goal)
        if a is None or b is None:
            return None
        w = self.grid.width
        source, target = a[0] * w + a[1], b[0] * w + b[1]
        if source == target:
            chain = np.array([source], dtype=np.int64)
        else:
            chain = grid_search.astar(self._field, self._need(self.radius), self.preferred,
                                      self._span, self.clearance_cost, source, target)  # fmt: skip
            if not len(chain):
                return None
        points = self.grid.centres(chain // w, chain % w)
        ends = [np.asarray(start, dtype=np.float64)[None, :2]] if a[2] else []
        tail = [np.asarray(goal, dtype=np.float64)[None, :2]] if b[2] else []
        return self.shortcut(np.concatenate([*ends, points, *tail]))

    @property
    def _span(self) -> float:
        """``preferred - radius``: the width of the clearance cost's ramp (0: none)."""
        return self.preferred - self.radius if self.clearance_cost > 0.0 else 0.0

    def shortcut(self, points: FloatArray) -> FloatArray:
        """The path pulled straight (module docstring, step 3); with a clearance cost, a
        segment replaces the points it skips only where it costs no more than they do
        (:meth:`line_cost`), so it does not cut nearer an obstacle than the search chose."""
        keep = grid_search.shortcut(points, self._frame, self._field, self._need(self.radius),
                                    self.preferred, self._span, self.clearance_cost)  # fmt: skip
        return points[keep]

    def visible(self, a: ArrayLike, b: ArrayLike, radius: float | None = None) -> bool:
        """Whether a disc of ``radius`` m (None: the planner's; at most its preferred disc)
        may travel the segment ``a -> b``: every cell it crosses is free for it
        (:meth:`free_for`)."""
        if radius is not None and radius > self.preferred:
            raise ValueError(f"radius {radius} m is beyond the preferred disc "
                             f"({self.preferred} m) the planner reads clearances for")
        need = self._need(self.radius if radius is None else radius)
        return math.isfinite(self._segment(a, b, need, False))

    def line_cost(self, a: ArrayLike, b: ArrayLike) -> float:
        """The search's cost of the segment ``a -> b`` (m): its length in each cell it
        crosses times that cell's ``1 + w q`` (module docstring); inf where it crosses a cell
        that is not traversable or leaves the grid."""
        return self._segment(a, b, self._need(self.radius), True)

    def _segment(self, a: ArrayLike, b: ArrayLike, need: float, weighted: bool) -> float:
        pa, pb = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
        return grid_search.along((float(pa[0]), float(pa[1])), (float(pb[0]), float(pb[1])),
                                 self._frame, self._field, need, self.preferred, self._span,
                                 self.clearance_cost, weighted)  # fmt: skip

    def crossed_cells(self, a: ArrayLike, b: ArrayLike) -> tuple[NDArray[np.int64], ...]:
        """``(rows, cols)`` of every cell whose interior the segment ``a -> b`` enters: the
        cells of the midpoints between its successive grid-line crossings."""
        p, q = self.grid.to_local(np.stack([a, b])[:, :2]) / self.grid.resolution
        d = q - p
        ts = [np.array([0.0, 1.0])]
        for k in (0, 1):
            if d[k] != 0.0:
                lo, hi = sorted((p[k], q[k]))
                lines = np.arange(math.ceil(lo), math.floor(hi) + 1, dtype=np.float64)
                ts.append((lines - p[k]) / d[k])
        t = np.unique(np.clip(np.concatenate(ts), 0.0, 1.0))
        mid = p + ((t[:-1] + t[1:]) / 2.0)[:, None] * d if len(t) > 1 else p[None, :]
        cells = np.floor(mid).astype(np.int64)
        return cells[:, 1], cells[:, 0]


def plan_path(
    grid: OccupancyGrid,
    start: ArrayLike,
    goal: ArrayLike,
    radius: float,
    *,
    allow_unknown: bool = True,
    tolerance: float | None = None,
    preferred: float | None = None,
    clearance_cost: float = 0.0,
) -> FloatArray | None:
    """One path with a fresh :class:`GridPlanner` (see there); None when there is none."""
    planner = GridPlanner(grid, radius, allow_unknown=allow_unknown, tolerance=tolerance,
                          preferred=preferred, clearance_cost=clearance_cost)  # fmt: skip
    return planner.plan(start, goal)
