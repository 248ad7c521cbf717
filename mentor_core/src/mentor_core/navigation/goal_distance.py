"""The shortest way to a goal round the obstacles (the geodesic distance), for many points.

For one goal ``g`` with radius ``R`` (where an episode ends) and a disc footprint of radius
``r`` (a :class:`~mentor_core.navigation.shortest_path.VisibilityGraph`), the distance from a
point ``p`` of the free space into the goal's disc is::

    D(p) = min over v in {p} + corners, v seen from p, of |p - v| + L(v),
    L(v) = min over corners u of D_c(v, u) + leg(u)   (L(p) = leg(p) for v = p),
    leg(u) = max(|u - g| - R, 0) when the segment from u to the disc's point nearest u is free,

``D_c`` the graph's corner-to-corner shortest distances. ``L`` depends on the goal only, so it
is computed once. For a point, ``|p - v| + L(v)`` is exact for every corner it sees, so the
first corner it sees in ascending order of that sum is the minimum: a point costs one sum
per corner and, mostly, a few visibility tests (compiled; numpy, which tests every corner, is
the fallback).
Exact under the same condition as :meth:`VisibilityGraph.to_disc` (the path's last leg into
the disc is unobstructed), an upper bound otherwise.

Units: m, in the ``map`` frame of the world.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import ArrayLike, NDArray

from mentor_core.navigation import shortest_path
from mentor_core.navigation.shortest_path import VisibilityGraph, _segment_blocked

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]


class GoalDistance:
    """Shortest distances (m) into the disc of ``goal_radius`` (m) about ``goal`` in
    ``graph``'s free space; ``inf`` for a point outside it or cut off from the goal."""

    def __init__(self, graph: VisibilityGraph, goal: ArrayLike, goal_radius: float) -> None:
        self.graph = graph
        self.goal: FloatArray = np.asarray(goal, dtype=np.float64).reshape(-1)[:2].copy()
        self.goal_radius = max(float(goal_radius), 0.0)
        if not graph.free(self.goal)[0]:
            self._via = np.full(len(graph.nodes), np.inf)
            self._goal_free = False
            return
        self._goal_free = True
        leg = graph.legs_to_disc(graph.nodes, self.goal, self.goal_radius)
        # L(v): to the corner u whose leg into the disc is clear, then that leg
        self._via = (
            np.min(graph.corner_distances + leg[None, :], axis=1) if len(graph.nodes) else leg
        )  # fmt: skip

    @property
    def via(self) -> FloatArray:
        """``(n,)`` ``L(v)`` per corner of the graph (module docstring; m, inf: no way)."""
        return self._via

    @property
    def reachable(self) -> bool:
        """Whether the goal lies in the graph's free space (else every distance is inf)."""
        return self._goal_free

    def __call__(self, points: ArrayLike) -> FloatArray:
        """``(m,)`` distances from ``points`` (the first two values of each row, m)."""
        return self._search(points)[0]

    def waypoints(self, points: ArrayLike) -> FloatArray:
        """``(m, 2)`` where the shortest way from each point heads first (m): the goal when
        the point sees into its disc, else the first corner of the way round; NaN where the
        distance is ``inf``. A cost-to-go expert's next target from anywhere in the free
        space (``benchmarks/probes/imitation_ceiling.py``)."""
        return self.distances_and_waypoints(points)[1]

    def distances_and_waypoints(self, points: ArrayLike) -> tuple[FloatArray, FloatArray]:
        """``(m,)`` distances and ``(m, 2)`` waypoints (:meth:`waypoints`) of one search."""
        dist, corner = self._search(points)
        out = np.tile(self.goal, (len(dist), 1))
        via = corner >= 0
        out[via] = self.graph.nodes[corner[via]]
        out[~np.isfinite(dist)] = np.nan
        return dist, out

    def _search(self, points: ArrayLike) -> tuple[FloatArray, NDArray[np.int64]]:
        """Distances ``(m,)`` and the first corner of each way (index into the graph's
        nodes; -1 straight into the disc or no way)."""
        p = np.atleast_2d(np.asarray(points, dtype=np.float64))[:, :2]
        out = np.full(len(p), np.inf)
        first = np.full(len(p), -1, dtype=np.int64)
        free = self.graph.free(p)
        if not self._goal_free or not free.any():
            return out, first
        q = p[free]
        best = self.graph.legs_to_disc(q, self.goal, self.goal_radius)
        corner = np.full(len(q), -1, dtype=np.int64)
        corners = self.graph.nodes
        if len(corners):
            # a point that sees into the disc goes straight; the others need the corners
            around = np.flatnonzero(~np.isfinite(best))
            if _first_corners_numba is None:  # the fallback, and the tests' reference
                self._first_corners_numpy(q, around, best, corner)
            else:
                dist = np.empty(len(around))
                k = np.empty(len(around), dtype=np.int64)
                _first_corners_numba(np.ascontiguousarray(q[around]), corners, self._via,
                                     self.graph.shrunk, dist, k)  # fmt: skip
                best[around] = dist
                corner[around] = k
        out[free] = best
        first[free] = corner
        return out, first

    def _first_corners_numpy(
        self, q: FloatArray, around: NDArray[np.int64], best: FloatArray,
        corner: NDArray[np.int64],
    ) -> None:  # fmt: skip
        """The numpy twin of :func:`_first_corner` for the points ``q[around]``: every corner
        tested; lowers ``best`` and sets ``corner`` where a way round is shorter."""
        corners = self.graph.nodes
        for chunk in np.array_split(around, max(1, len(around) * len(corners) // 100_000)):
            if not len(chunk):
                continue
            a = np.repeat(q[chunk], len(corners), axis=0)
            b = np.tile(corners, (len(chunk), 1))
            seen = self.graph.visible(a, b).reshape(len(chunk), len(corners))
            diff = a - b
            d = np.sqrt(diff[:, 0] * diff[:, 0] + diff[:, 1] * diff[:, 1])
            d = d.reshape(len(chunk), len(corners))
            total = np.where(seen, d + self._via[None, :], np.inf)
            k = total.argmin(axis=1)
            shortest = total[np.arange(len(chunk)), k]
            better = shortest < best[chunk]
            best[chunk] = np.where(better, shortest, best[chunk])
            corner[chunk] = np.where(better, k, corner[chunk])


def _first_corner(
    px: float, py: float, nodes: FloatArray, via: FloatArray, boxes: FloatArray,
    totals: FloatArray,
) -> tuple[float, int]:  # fmt: skip
    """``min over corners j that p sees of |p - nodes[j]| + via[j]`` and its ``j`` (``inf,
    -1``: none seen), compiled by numba: the corners in ascending order of that sum, ties to
    the lower index as with ``argmin``; the first one seen is the minimum. Picked one by one,
    since most points see one of their first few (a heap or leaving out the corners a point's
    own box hides measured no faster). ``boxes``: the graph's shrunk boxes; ``totals``:
    scratch of at least n."""
    n = nodes.shape[0]
    for j in range(n):
        dx, dy = px - nodes[j, 0], py - nodes[j, 1]
        totals[j] = np.sqrt(dx * dx + dy * dy) + via[j]  # as the numpy path, not hypot: 3x
    for _ in range(n):
        k, low = -1, np.inf
        for j in range(n):
            if totals[j] < low:
                k, low = j, totals[j]
        if k < 0:
            break  # the rest cannot reach the goal
        if not _segment_blocked(px, py, nodes[k, 0], nodes[k, 1], boxes):
            return low, k
        totals[k] = np.inf
    return np.inf, -1


def _first_corners_loop(
    points: FloatArray, nodes: FloatArray, via: FloatArray, boxes: FloatArray,
    dist: FloatArray, first: IntArray,
) -> None:  # fmt: skip
    """:func:`_first_corner` for each of ``points`` (m, 2); writes ``dist`` and ``first``."""
    totals = np.empty(nodes.shape[0])
    for i in range(points.shape[0]):
        dist[i], first[i] = _first_corner(points[i, 0], points[i, 1], nodes, via, boxes, totals)


_first_corners_numba: Callable[..., None] | None
if shortest_path._blocked_numba is not None:
    from numba import njit

    _first_corner = njit(cache=True)(_first_corner)
    _first_corners_numba = njit(cache=True)(_first_corners_loop)
else:  # pragma: no cover - numba is in the lock file; numpy stays the fallback
    _first_corners_numba = None
