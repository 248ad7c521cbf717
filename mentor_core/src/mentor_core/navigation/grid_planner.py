"""Shortest paths on an occupancy grid for a robot's footprint (a global planner, as Nav2's).

1. Inflation. A cell is *traversable* when the distance from its centre to the nearest
   obstacle cell's centre (``scipy.ndimage.distance_transform_edt``; the outside of the grid
   counts as obstacle) is at least ``radius + sqrt(2) r`` (``r`` the resolution). Then every
   point of a traversable cell's square is at least ``radius`` from every obstacle cell's
   square (centre to square: ``- r / sqrt(2)``; point to its cell's centre: ``- r /
   sqrt(2)``), so a disc of radius ``radius`` (the footprint's circumscribed circle, plus a
   margin) anywhere on such a square touches no obstacle cell.
2. Search. Dijkstra (``scipy.sparse.csgraph.dijkstra``) on the 8-connected graph of
   traversable cells, edges of length ``r`` and ``sqrt(2) r``; a diagonal step only where
   both cells beside it are traversable too, so the segments between cell centres stay on
   traversable squares.
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
from collections.abc import Callable

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import ndimage, sparse
from scipy.sparse import csgraph

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
        blocked = np.pad(grid.obstacles(lethal, not allow_unknown), 1, constant_values=True)
        #: (height, width): distance (m) from each cell's centre to the nearest obstacle cell's
        self.clearance: FloatArray = ndimage.distance_transform_edt(~blocked)[1:-1, 1:-1] * r
        #: (height, width): cells a disc of ``radius`` may stand on anywhere
        self.traversable: BoolArray = self.free_for(self.radius)
        self._traversable_values = self.traversable.astype(np.float64)  # 1 / 0, for _along
        x0, y0, yaw = grid.origin  # OccupancyGrid.to_local's terms, for _along
        self._frame = (float(x0), float(y0), math.cos(yaw), math.sin(yaw), grid.resolution)
        self._node = np.full(self.traversable.shape, -1, dtype=np.int64)
        self._node[self.traversable] = np.arange(int(self.traversable.sum()))
        self._penalty = np.zeros(self.traversable.shape)  # q of the module docstring
        if self.clearance_cost > 0.0:
            kept = self.clearance - _SQRT2 * r  # what each cell's square keeps clear
            span = self.preferred - self.radius
            self._penalty = np.clip((self.preferred - kept) / span, 0.0, 1.0)
        self._cell_cost = 1.0 + self.clearance_cost * self._penalty
        self._graph = self._build_graph()
        # nearest traversable cell of every cell (for moving a start or goal onto one)
        if self.traversable.any():
            dist, nearest = ndimage.distance_transform_edt(
                ~self.traversable, return_indices=True
            )
            self._snap_dist, self._snap_cell = dist * r, nearest
        else:
            self._snap_dist, self._snap_cell = None, None

    def free_for(self, radius: float) -> BoolArray:
        """``(height, width)``: cells a disc of ``radius`` m may stand on anywhere."""
        return np.asarray(self.clearance >= radius + _SQRT2 * self.grid.resolution)

    def _build_graph(self) -> sparse.csr_matrix:
        t, node, r = self.traversable, self._node, self.grid.resolution
        rows: list[NDArray[np.int64]] = []
        cols: list[NDArray[np.int64]] = []
        weights: list[FloatArray] = []
        penalty, cost = self._penalty, self.clearance_cost

        def link(a: tuple[slice, slice], b: tuple[slice, slice], ok: BoolArray, w: float) -> None:
            rows.append(node[a][ok])
            cols.append(node[b][ok])
            if cost == 0.0:  # a hard disc: every step weighs its length
                weights.append(np.full(int(ok.sum()), w))
            else:
                weights.append(w * (1.0 + cost * (penalty[a][ok] + penalty[b][ok]) / 2.0))

        whole, head, tail = slice(None), slice(None, -1), slice(1, None)
        link((whole, head), (whole, tail), t[:, :-1] & t[:, 1:], r)  # east
        link((head, whole), (tail, whole), t[:-1, :] & t[1:, :], r)  # north
        square = t[:-1, :-1] & t[1:, 1:] & t[:-1, 1:] & t[1:, :-1]  # no corner cutting
        link((head, head), (tail, tail), square, _SQRT2 * r)  # north-east
        link((head, tail), (tail, head), square, _SQRT2 * r)  # north-west
        n = int(t.sum())
        return sparse.coo_matrix(
            (np.concatenate(weights), (np.concatenate(rows), np.concatenate(cols))),
            shape=(n, n),
        ).tocsr()

    def _cell(self, xy: ArrayLike) -> tuple[int, int, bool] | None:
        """Traversable cell ``(row, col, exact)`` for a point: its own (``exact``) or the
        nearest within ``tolerance``; None when there is none."""
        rows, cols = self.grid.cells_of(np.asarray(xy, dtype=np.float64)[:2])
        row, col = int(rows[0]), int(cols[0])
        if self._snap_dist is None or self._snap_cell is None:
            return None
        h, w = self.traversable.shape
        inside = 0 <= row < h and 0 <= col < w
        if inside and self.traversable[row, col]:
            return row, col, True
        # outside the grid: the nearest border cell's nearest traversable cell, checked below
        r_in, c_in = min(max(row, 0), h - 1), min(max(col, 0), w - 1)
        rr, cc = int(self._snap_cell[0, r_in, c_in]), int(self._snap_cell[1, r_in, c_in])
        centre = self.grid.centres([rr], [cc])[0]
        point = np.asarray(xy, dtype=np.float64)[:2]
        if float(np.hypot(*(centre - point))) > self.tolerance + self.grid.resolution:
            return None
        return rr, cc, False

    def plan(self, start: ArrayLike, goal: ArrayLike) -> FloatArray | None:
        """A collision-free path ``(k, 2)`` (m, ``map``) from ``start`` to ``goal`` (x, y),
        shortest on the grid then pulled straight; None when there is none."""
        a, b = self._cell(start), self._cell(goal)
        if a is None or b is None:
            return None
        source, target = int(self._node[a[0], a[1]]), int(self._node[b[0], b[1]])
        _, pred = csgraph.dijkstra(
            self._graph, directed=False, indices=source, return_predecessors=True
        )
        if source != target and pred[target] < 0:
            return None
        chain = [target]
        while chain[-1] != source:
            chain.append(int(pred[chain[-1]]))
        cells = np.argwhere(self.traversable)[chain[::-1]]  # node order is row-major
        points = self.grid.centres(cells[:, 0], cells[:, 1])
        ends = [np.asarray(start, dtype=np.float64)[None, :2]] if a[2] else []
        tail = [np.asarray(goal, dtype=np.float64)[None, :2]] if b[2] else []
        return self.shortcut(np.concatenate([*ends, points, *tail]))

    def shortcut(self, points: FloatArray) -> FloatArray:
        """The path pulled straight (module docstring, step 3); with a clearance cost, a
        segment replaces the points it skips only where it costs no more than they do
        (:meth:`line_cost`), so it does not cut nearer an obstacle than the search chose."""
        costly = self.clearance_cost > 0.0
        if costly:
            legs = [self.line_cost(points[k], points[k + 1]) for k in range(len(points) - 1)]
            along = np.concatenate([[0.0], np.cumsum(legs)])
        keep = [0]
        i, last = 0, len(points) - 1
        while i < last:
            j = i + 1
            while j < last:
                if costly:
                    bar = (along[j + 1] - along[i]) * (1.0 + 1e-9)
                    if not self.line_cost(points[i], points[j + 1]) <= bar:
                        break
                elif not self.visible(points[i], points[j + 1]):
                    break
                j += 1
            keep.append(j)
            i = j
        return points[keep]

    def visible(self, a: ArrayLike, b: ArrayLike, radius: float | None = None) -> bool:
        """Whether a disc of ``radius`` m (None: the planner's) may travel the segment
        ``a -> b``: every cell it crosses is free for it (:meth:`free_for`)."""
        if _along_numba is not None:  # the same cells and tests, compiled (a scan map's hot spot)
            if radius is None:
                values, need = self._traversable_values, 0.5
            else:
                values, need = self.clearance, radius + _SQRT2 * self.grid.resolution
            return math.isfinite(self._segment(a, b, values, need, False))
        rows, cols = self.crossed_cells(a, b)
        h, w = self.traversable.shape
        if rows.min() < 0 or cols.min() < 0 or rows.max() >= h or cols.max() >= w:
            return False
        if radius is None:
            return bool(self.traversable[rows, cols].all())
        need = radius + _SQRT2 * self.grid.resolution
        return bool((self.clearance[rows, cols] >= need).all())

    def line_cost(self, a: ArrayLike, b: ArrayLike) -> float:
        """The search's cost of the segment ``a -> b`` (m): its length in each cell it
        crosses times that cell's ``1 + w q`` (module docstring); inf where it crosses a cell
        that is not traversable or leaves the grid."""
        return self._segment(a, b, self._traversable_values, 0.5, True)

    def _segment(self, a: ArrayLike, b: ArrayLike, values: FloatArray, need: float,
                 weighted: bool) -> float:  # fmt: skip
        """:func:`_along` on this grid, compiled where numba is there."""
        pa, pb = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
        kernel = _along_numba or _along
        return float(kernel(float(pa[0]), float(pa[1]), float(pb[0]), float(pb[1]),
                            *self._frame, values, need, self._cell_cost, weighted))  # fmt: skip

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


def _along(
    ax: float, ay: float, bx: float, by: float, x0: float, y0: float, c: float, s: float,
    r: float, values: FloatArray, need: float, costs: FloatArray, weighted: bool,
) -> float:  # fmt: skip
    """The segment ``a -> b`` (``map``) on a grid of origin ``(x0, y0)``, heading ``(cos,
    sin) = (c, s)`` and cells of ``r`` m: inf unless every cell of
    :meth:`GridPlanner.crossed_cells` (the same arithmetic) lies on the grid and holds a
    value of at least ``need``; else its length (m), each cell's share times ``costs`` there
    when ``weighted``."""
    px, py = (c * (ax - x0) + s * (ay - y0)) / r, (-s * (ax - x0) + c * (ay - y0)) / r
    qx, qy = (c * (bx - x0) + s * (by - y0)) / r, (-s * (bx - x0) + c * (by - y0)) / r
    p, q = (px, py), (qx, qy)
    d = (qx - px, qy - py)
    counts, first = [0, 0], [0.0, 0.0]
    for k in range(2):
        if d[k] != 0.0:  # the grid lines it crosses across axis k
            first[k] = float(math.ceil(min(p[k], q[k])))
            counts[k] = max(0, math.floor(max(p[k], q[k])) - int(first[k]) + 1)
    ts = np.empty(2 + counts[0] + counts[1], dtype=np.float64)
    ts[0], ts[1] = 0.0, 1.0
    n = 2
    for k in range(2):
        for i in range(counts[k]):
            ts[n] = ((first[k] + i) - p[k]) / d[k]
            n += 1
    t = np.unique(np.minimum(np.maximum(ts, 0.0), 1.0))
    h, w = values.shape
    length = math.hypot(d[0], d[1]) * r
    total = 0.0
    for i in range(len(t) - 1):
        m = (t[i] + t[i + 1]) / 2.0
        col, row = math.floor(px + m * d[0]), math.floor(py + m * d[1])
        if row < 0 or col < 0 or row >= h or col >= w or not values[row, col] >= need:
            return math.inf
        total += (t[i + 1] - t[i]) * length * (costs[row, col] if weighted else 1.0)
    return total


_along_numba: Callable[..., float] | None
try:
    from numba import njit

    _along_numba = njit(cache=True)(_along)
except ImportError:  # pragma: no cover - numba is in the lock file; numpy stays the fallback
    _along_numba = None


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
