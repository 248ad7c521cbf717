"""Exact shortest paths for a robot's footprint on a box world: a visibility graph.

The footprint is a disc of radius ``r`` about the body centre. The default, and what the
benchmark uses, is the body's circumscribed radius (``RobotProfile.half_diagonal``): a path
that keeps ``r`` from every obstacle and wall can be driven in ANY orientation, so the
robot never has to turn on the spot to fit through (the inscribed radius, half the width,
would accept gaps the robot passes only when it is aligned with them, and a path length no
drivable path reaches).

Configuration space: every box grown by ``r`` on each side (its Minkowski sum with the square
``[-r, r]^2``, which holds the disc) and the arena shrunk to ``[r, size - r]^2``. The grown
boxes keep square corners, so the free space is a polygonal domain; in it the shortest path
between two points is a polyline whose inner vertices are corners of the grown boxes
(Lozano-Pérez & Wesley 1979), and Dijkstra's algorithm on the visibility graph of those
corners (edges: segments that do not enter a grown box's interior) finds it exactly. Square
corners are conservative for the disc: a path found is clear of the obstacles by ``r``; it
is at most ``(2 - pi / 2) r`` per quarter turn round a corner longer than the path round a
rounded (disc-grown) corner (0.08 m for the UGV's 0.195 m), and diagonal gaps between two box
corners narrower than ``2 sqrt(2) r`` count as closed.

A segment may touch a grown box's boundary (run along an edge, pass through a corner); it is
blocked when it enters the interior by more than ``EPSILON`` (1e-9 m), which absorbs the
rounding of corners that lie exactly on a segment.

Units: m, in the ``map`` frame of the world.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import dijkstra

from mentor_core.sim.world import World

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]
EPSILON = 1e-9  # m; a segment entering a grown box by less than this is not blocked
# segment-box tests per numpy chunk (bounds the temporary arrays to a few MB)
_CHUNK = 200_000


@dataclass(frozen=True)
class ShortestPath:
    """A shortest path: ``points`` ``(k, 2)`` from the start to the goal (m) and its
    ``length`` (m)."""

    points: FloatArray
    length: float


class VisibilityGraph:
    """The visibility graph of a world for a disc footprint of radius ``radius`` (m).

    Built once per world (corners and all their shortest distances), then answers any number
    of start/goal queries (:meth:`path`, :meth:`length`).
    """

    def __init__(self, world: World, radius: float) -> None:
        if not np.isfinite(radius) or radius < 0.0:
            raise ValueError(f"footprint radius must be finite and >= 0, got {radius}")
        self.world = world
        self.radius = float(radius)
        b = np.asarray(world.obstacles, dtype=np.float64).reshape(-1, 4)
        grown = b + np.array([-radius, -radius, radius, radius])
        self.boxes: FloatArray = grown
        # what free() and visible() test against: the grown boxes' open interiors less
        # EPSILON, and the arena's free square widened by it (the compiled twins read them)
        self.shrunk: FloatArray = grown + np.array([EPSILON, EPSILON, -EPSILON, -EPSILON])
        self.bounds = (self.radius - EPSILON, world.size - self.radius + EPSILON)
        corners = np.concatenate([grown[:, [0, 1]], grown[:, [2, 1]],
                                  grown[:, [2, 3]], grown[:, [0, 3]]])  # fmt: skip
        corners = np.unique(corners, axis=0) if len(corners) else corners.reshape(0, 2)
        self.nodes: FloatArray = corners[self.free(corners)]
        n = len(self.nodes)
        ii, jj = np.triu_indices(n, k=1)
        ok = self.visible(self.nodes[ii], self.nodes[jj])
        w = np.hypot(*(self.nodes[jj[ok]] - self.nodes[ii[ok]]).T)
        # zero-length edges cannot occur (corners are unique); csr drops explicit zeros
        graph = csr_matrix((np.concatenate([w, w]),
                            (np.concatenate([ii[ok], jj[ok]]), np.concatenate([jj[ok], ii[ok]]))),
                           shape=(n, n))  # fmt: skip
        if n:
            self._dist, self._pred = dijkstra(graph, directed=False, return_predecessors=True)
        else:
            self._dist = np.zeros((0, 0))
            self._pred = np.zeros((0, 0), dtype=np.int32)

    @property
    def corner_distances(self) -> FloatArray:
        """(n, n) shortest distances between the corners ``nodes`` (m; inf: no way)."""
        dist: FloatArray = self._dist
        return dist

    def free(self, points: ArrayLike) -> BoolArray:
        """(n,) True where a point lies in the free configuration space: inside
        ``[r, size - r]^2`` and not inside a grown box (its boundary is free)."""
        p = np.asarray(points, dtype=np.float64).reshape(-1, 2)
        lo, hi = self.bounds
        inside_arena = np.asarray(np.all((p >= lo) & (p <= hi), axis=1), dtype=np.bool_)
        if not len(self.boxes):
            return inside_arena
        b = self.shrunk
        x, y = p[:, 0:1], p[:, 1:2]
        inside = ((b[None, :, 0] < x) & (x < b[None, :, 2])
                  & (b[None, :, 1] < y) & (y < b[None, :, 3]))  # fmt: skip
        return np.asarray(inside_arena & ~inside.any(axis=1), dtype=np.bool_)

    def visible(self, a: ArrayLike, b: ArrayLike) -> BoolArray:
        """(n,) True where the segment ``a[i] -> b[i]`` enters no grown box's interior.

        The arena needs no test: it is convex, so a segment between two free points stays
        inside it. Per box, the parameters ``t in [0, 1]`` at which the segment is strictly
        inside the box (shrunk by ``EPSILON``) form the interval ``(max(lo_x, lo_y, 0),
        min(hi_x, hi_y, 1))`` (Liang-Barsky); the segment is blocked when it is not empty.
        """
        p = np.asarray(a, dtype=np.float64).reshape(-1, 2)
        q = np.asarray(b, dtype=np.float64).reshape(-1, 2)
        out = np.ones(len(p), dtype=np.bool_)
        if not len(self.boxes) or not len(p):
            return out
        shrunk = self.shrunk
        if _blocked_numba is not None:
            blocked = np.empty(len(p), dtype=np.bool_)
            _blocked_numba(np.ascontiguousarray(p), np.ascontiguousarray(q), shrunk, blocked)
            return ~blocked
        step = max(1, _CHUNK // len(self.boxes))
        for s in range(0, len(p), step):
            out[s : s + step] = ~_blocked(p[s : s + step], q[s : s + step], shrunk)
        return out

    def path(
        self, start: ArrayLike, goal: ArrayLike, ends: VisibilityGraph | None = None
    ) -> ShortestPath | None:
        """The shortest path from ``start`` to ``goal`` (the first two values of each, m), or
        None when either is not free or the goal cannot be reached.

        ``ends``: a graph of the same world for a smaller radius whose free space the first
        and last legs need only keep (start and goal may then lie nearer to obstacles than
        this graph's radius); the path between runs through this graph's corners.
        """
        near = self if ends is None else ends
        s = np.asarray(start, dtype=np.float64).reshape(-1)[:2]
        g = np.asarray(goal, dtype=np.float64).reshape(-1)[:2]
        if not near.free(np.stack([s, g])).all():
            return None
        if near.visible(s, g)[0]:
            return ShortestPath(np.stack([s, g]), float(np.hypot(*(g - s))))
        n = len(self.nodes)
        if n == 0:
            return None
        from_s = self._reach(s, near)
        to_g = self._reach(g, near)
        total = from_s[:, None] + self._dist + to_g[None, :]
        i, j = np.unravel_index(int(np.argmin(total)), total.shape)
        length = float(total[i, j])
        if not np.isfinite(length):
            return None
        chain = [int(j)]
        while chain[-1] != i:
            chain.append(int(self._pred[i, chain[-1]]))
        points = np.concatenate([s[None], self.nodes[chain[::-1]], g[None]])
        return ShortestPath(points, length)

    def to_disc(self, start: ArrayLike, goal: ArrayLike, goal_radius: float) -> float:
        """Length (m) of the shortest path from ``start`` into the disc of ``goal_radius`` (m)
        about ``goal`` (where an episode ends), ``inf`` when there is none.

        ``min over v of D(s, v) + max(|v - g| - R, 0)``, ``v`` the start and the corners,
        ``D`` the shortest distance to ``v``, where the segment from ``v`` towards ``g`` up
        to the disc (the disc's point nearest ``v``) is free. Exact when the path's last leg
        into the disc is unobstructed, the common case; where an obstacle cuts the disc so
        that only another of its points can be reached first, it is an upper bound.
        """
        s = np.asarray(start, dtype=np.float64).reshape(-1)[:2]
        g = np.asarray(goal, dtype=np.float64).reshape(-1)[:2]
        if not self.free(np.stack([s, g])).all():
            return float("inf")
        radius = max(float(goal_radius), 0.0)
        if float(np.hypot(*(g - s))) <= radius:
            return 0.0
        n = len(self.nodes)
        if n:
            from_s = self._reach(s)
            d_s = np.min(from_s[:, None] + self._dist, axis=0)  # (n,) shortest s -> corner
        else:
            d_s = np.zeros(0)
        points = np.concatenate([s[None], self.nodes])
        dist = np.concatenate([[0.0], d_s])
        total = np.where(np.isfinite(dist), dist + self.legs_to_disc(points, g, radius), np.inf)
        return float(total.min())

    def legs_to_disc(self, points: ArrayLike, goal: ArrayLike, goal_radius: float) -> FloatArray:
        """(m,) length of the straight leg from each point into the disc of ``goal_radius``
        (m) about ``goal`` (to the disc's point nearest it; 0 inside), inf where that leg is
        blocked."""
        p = np.asarray(points, dtype=np.float64).reshape(-1, 2)
        g = np.asarray(goal, dtype=np.float64).reshape(-1)[:2]
        radius = max(float(goal_radius), 0.0)
        gap = np.hypot(*(g - p).T)
        inside = gap <= radius
        unit = (g - p) / np.where(gap > 0.0, gap, 1.0)[:, None]
        entry = g - radius * unit  # the disc's point nearest each point
        ok = inside | self.visible(p, np.where(inside[:, None], p, entry))
        return np.where(ok, np.maximum(gap - radius, 0.0), np.inf)

    def length(self, start: ArrayLike, goal: ArrayLike) -> float:
        """Length (m) of :meth:`path`, ``inf`` when there is none."""
        found = self.path(start, goal)
        return float("inf") if found is None else found.length

    def _reach(self, point: FloatArray, near: VisibilityGraph | None = None) -> FloatArray:
        """(n,) straight distance from ``point`` to each corner it sees (in ``near``'s free
        space, by default this graph's), inf to the others."""
        seen = (near or self).visible(np.broadcast_to(point, self.nodes.shape), self.nodes)
        d = np.hypot(*(self.nodes - point).T)
        return np.where(seen, d, np.inf)


def _blocked(p: FloatArray, q: FloatArray, boxes: FloatArray) -> BoolArray:
    """(n,) whether segment ``p[i] -> q[i]`` enters the open interior of any box (k, 4)."""
    d = (q - p)[:, None, :]  # (n, 1, 2)
    lo_box = boxes[None, :, 0:2]  # (1, k, 2)
    hi_box = boxes[None, :, 2:4]
    origin = p[:, None, :]
    with np.errstate(divide="ignore", invalid="ignore"):
        ta = (lo_box - origin) / d
        tb = (hi_box - origin) / d
    moving = d != 0.0
    # an axis the segment does not move along: strictly inside that slab for all t, or never
    inside = (lo_box < origin) & (origin < hi_box)
    t_lo = np.where(moving, np.minimum(ta, tb), np.where(inside, -np.inf, np.inf))
    t_hi = np.where(moving, np.maximum(ta, tb), np.where(inside, np.inf, -np.inf))
    enter = np.maximum(np.maximum(t_lo[..., 0], t_lo[..., 1]), 0.0)
    leave = np.minimum(np.minimum(t_hi[..., 0], t_hi[..., 1]), 1.0)
    return np.asarray((enter < leave).any(axis=1), dtype=np.bool_)


def _segment_blocked(px: float, py: float, qx: float, qy: float, boxes: FloatArray) -> bool:
    """Whether the segment ``(px, py) -> (qx, qy)`` enters the open interior of any box
    (k, 4): the scalar twin of :func:`_blocked` (compiled by numba), the same arithmetic per
    box, so the same verdicts."""
    dx, dy = qx - px, qy - py
    x0, x1, y0, y1 = min(px, qx), max(px, qx), min(py, qy), max(py, qy)
    for k in range(boxes.shape[0]):
        # a box the segment's bounding box does not overlap: Liang-Barsky's own verdict
        # (rounding is monotone), at the cost of four comparisons
        if x1 <= boxes[k, 0] or x0 >= boxes[k, 2] or y1 <= boxes[k, 1] or y0 >= boxes[k, 3]:
            continue
        enter, leave = 0.0, 1.0
        for axis in range(2):
            o = px if axis == 0 else py
            d = dx if axis == 0 else dy
            lo, hi = boxes[k, axis], boxes[k, axis + 2]
            if d != 0.0:
                ta, tb = (lo - o) / d, (hi - o) / d
                enter = max(enter, min(ta, tb))
                leave = min(leave, max(ta, tb))
            elif not (lo < o < hi):
                leave = -np.inf  # outside this slab for all t
        if enter < leave:
            return True
    return False


def _point_free(px: float, py: float, boxes: FloatArray, lo: float, hi: float) -> bool:
    """Scalar twin of :meth:`VisibilityGraph.free` for one point (compiled by numba):
    ``lo``/``hi`` the arena's free bounds and ``boxes`` the grown boxes, both already widened
    or shrunk by ``EPSILON`` as there."""
    if not (lo <= px <= hi and lo <= py <= hi):
        return False
    for k in range(boxes.shape[0]):
        if boxes[k, 0] < px < boxes[k, 2] and boxes[k, 1] < py < boxes[k, 3]:
            return False
    return True


def _blocked_loop(p: FloatArray, q: FloatArray, boxes: FloatArray, out: BoolArray) -> None:
    """:func:`_blocked` by :func:`_segment_blocked`, segment by segment; writes ``out``."""
    for i in range(p.shape[0]):
        out[i] = _segment_blocked(p[i, 0], p[i, 1], q[i, 0], q[i, 1], boxes)


_blocked_numba: Callable[..., None] | None
try:
    from numba import njit

    # the scalar helpers first, so that the loops calling them compile against them
    _segment_blocked = njit(cache=True)(_segment_blocked)
    _point_free = njit(cache=True)(_point_free)
    _blocked_numba = njit(cache=True)(_blocked_loop)
except ImportError:  # pragma: no cover - numba is in the lock file; numpy stays the fallback
    _blocked_numba = None


def shortest_path(
    world: World, start: ArrayLike, goal: ArrayLike, radius: float
) -> ShortestPath | None:
    """The shortest path ``(k, 2)`` and its length (m) from ``start`` to ``goal`` for a disc
    footprint of ``radius`` (m; the circumscribed radius ``profile.half_diagonal`` makes it
    drivable in any orientation), or None when the goal cannot be reached. For many queries
    in one world build a :class:`VisibilityGraph` once."""
    return VisibilityGraph(world, radius).path(start, goal)
