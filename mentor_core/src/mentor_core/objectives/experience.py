"""Experience gain G: length of the Euclidean minimum spanning tree of experience points.

Paper eqs. 4-8: a genome's experience points V = [U(t), A(t), U(t+1)] from all its scenarios
(the union, exact duplicates removed) are the nodes of a complete graph whose edge weights are
the Euclidean distances W_ij = |V_i - V_j|; the criterion is the total weight of its minimum
spanning tree,

    G = sum_{e in MST} W_e.

The MST weight is the same for every exact algorithm (the paper uses Kruskal). A duplicate point
only adds zero-length edges, so G over the unique rows equals G over all rows: the kd-tree kernel
collapses duplicates for speed, the Prim kernel keeps them, the numpy path removes them first.

Methods:
    "boruvka"  numba, Boruvka's algorithm with a kd-tree: each round finds every component's
               shortest outgoing edge by nearest-neighbour queries that skip tree nodes lying
               inside the querying component; never forms the n^2 edges.
    "prim"     numba, Prim's algorithm on the fly: O(n d) memory, O(n^2 d) time.
    "numpy"    pure numpy Prim (one vectorised distance row per step); the fallback and the
               reference the tests compare the kernels with.
    "auto"     "prim" when numba imports, else "numpy". Measured with
               benchmarks/experience_bench.py: Prim wins at the trainer's <= 4,000 points in
               8-18 D (the actions make the points truly high-dimensional, so kd-tree boxes prune
               little); "boruvka" wins on sensor-like data from about 16,000 points.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any, Literal, TypeVar, cast

import numpy as np
from numpy.typing import ArrayLike

_numba: Any
try:  # numba is a speed-up only: without it "auto" falls back to numpy
    import numba as _numba
except ImportError:  # pragma: no cover - exercised only where numba is missing
    _numba = None

Method = Literal["auto", "boruvka", "prim", "numpy"]
METHODS: tuple[str, ...] = ("auto", "boruvka", "prim", "numpy")
HAVE_NUMBA = _numba is not None

_F = TypeVar("_F", bound=Callable[..., Any])

# Points per kd-tree leaf: small enough to prune well, large enough to amortise node visits.
_LEAF_SIZE = 16


def _compiled(parallel: bool = False) -> Callable[[_F], _F]:
    """numba.njit with on-disk caching and strict IEEE arithmetic (no fastmath)."""
    if _numba is None:
        return lambda function: function
    return cast(Callable[[_F], _F], _numba.njit(cache=True, fastmath=False, parallel=parallel))


_prange: Callable[..., Any] = range if _numba is None else _numba.prange


def _as_points(points: ArrayLike) -> np.ndarray:
    """(n, d) float64 C-contiguous copy of ``points``; -0.0 becomes 0.0 (equal as a point)."""
    values = np.asarray(points, dtype=np.float64)
    if values.ndim != 2:
        raise ValueError(f"points: expected an (n, d) matrix, got shape {values.shape}")
    if not np.isfinite(values).all():
        raise ValueError("points: coordinates must be finite (NaN or inf found)")
    return np.ascontiguousarray(values + 0.0)


# --------------------------------------------------------------------------------------------
# numpy reference


def _prim_numpy(points: np.ndarray) -> float:
    """Prim's algorithm with O(n) memory: one vectorised row of distances per step."""
    unique = np.unique(points, axis=0)
    n = unique.shape[0]
    if n < 2:
        return 0.0
    best = np.full(n, np.inf)  # squared distance from each outside point to the tree
    outside = np.ones(n, dtype=bool)
    outside[0] = False
    last = 0
    total = 0.0
    for _ in range(n - 1):
        diff = unique - unique[last]
        np.minimum(best, np.einsum("ij,ij->i", diff, diff), out=best, where=outside)
        candidates = np.where(outside, best, np.inf)
        last = int(np.argmin(candidates))
        total += float(np.sqrt(candidates[last]))
        outside[last] = False
    return total


# --------------------------------------------------------------------------------------------
# numba kernels


@_compiled()
def _prim_kernel(points: np.ndarray) -> float:  # pragma: no cover - compiled
    """Prim's algorithm on the fly; distances are recomputed, never stored (O(n d) memory).

    The points outside the tree are kept compacted in a (d, m) array (a point joining the tree
    is replaced by the last one), so each step is a branch-free sweep over contiguous rows that
    the compiler vectorises; the squared distance still sums the dimensions in order 0..d-1.
    """
    n, d = points.shape
    if n < 2:
        return 0.0
    outside = np.ascontiguousarray(points[1:].T)  # (d, m) coordinates of the outside points
    best = np.full(n - 1, np.inf)  # squared distance of each outside point to the tree
    dist2 = np.empty(n - 1)
    last = points[0].copy()
    total = 0.0
    for m in range(n - 1, 0, -1):
        dist2[:m] = 0.0
        for k in range(d):
            row = outside[k]
            value = last[k]
            for j in range(m):
                delta = row[j] - value
                dist2[j] += delta * delta
        nearest = 0
        nearest_dist2 = np.inf
        for j in range(m):
            if dist2[j] < best[j]:
                best[j] = dist2[j]
            if best[j] < nearest_dist2:
                nearest_dist2 = best[j]
                nearest = j
        total += np.sqrt(nearest_dist2)
        for k in range(d):
            last[k] = outside[k, nearest]
            outside[k, nearest] = outside[k, m - 1]
        best[nearest] = best[m - 1]
    return total


@_compiled()
def _build_kdtree(points: np.ndarray) -> tuple[Any, ...]:  # pragma: no cover - compiled
    """kd-tree over ``points``: median split on the widest dimension, ``_LEAF_SIZE`` leaves.

    Returns the points reordered so each node owns a contiguous slice [start, end), and per
    node: start, end, left child (-1 for a leaf), right child, split dimension, split value and
    bounding box. A node whose box has zero extent holds copies of one point: it is cut to its
    first point (duplicates add nothing to the MST) and ``active`` marks the points kept.
    """
    n, d = points.shape
    order = np.arange(n)
    max_nodes = 2 * n + 1
    start = np.empty(max_nodes, dtype=np.int64)
    end = np.empty(max_nodes, dtype=np.int64)
    left = np.full(max_nodes, -1, dtype=np.int64)
    right = np.full(max_nodes, -1, dtype=np.int64)
    split_dim = np.zeros(max_nodes, dtype=np.int64)
    split_value = np.zeros(max_nodes)
    lo = np.empty((max_nodes, d))
    hi = np.empty((max_nodes, d))
    active = np.ones(n, dtype=np.bool_)
    start[0] = 0
    end[0] = n
    n_nodes = 1
    stack = [0]
    while len(stack) > 0:
        node = stack.pop()
        a = start[node]
        b = end[node]
        for k in range(d):
            lo[node, k] = points[order[a], k]
            hi[node, k] = points[order[a], k]
        for i in range(a + 1, b):
            for k in range(d):
                value = points[order[i], k]
                if value < lo[node, k]:
                    lo[node, k] = value
                if value > hi[node, k]:
                    hi[node, k] = value
        widest = 0
        spread = -1.0
        for k in range(d):
            if hi[node, k] - lo[node, k] > spread:
                spread = hi[node, k] - lo[node, k]
                widest = k
        if spread == 0.0:
            for i in range(a + 1, b):
                active[order[i]] = False
            end[node] = a + 1
            continue
        if b - a <= _LEAF_SIZE:
            continue
        segment = order[a:b]
        ranked = np.argsort(points[segment, widest], kind="mergesort")
        order[a:b] = segment[ranked]
        middle = a + (b - a) // 2
        split_dim[node] = widest
        split_value[node] = points[order[middle], widest]
        left[node] = n_nodes
        right[node] = n_nodes + 1
        start[n_nodes] = a
        end[n_nodes] = middle
        start[n_nodes + 1] = middle
        end[n_nodes + 1] = b
        stack.append(n_nodes)
        stack.append(n_nodes + 1)
        n_nodes += 2
    return (
        np.ascontiguousarray(points[order]),
        active[order],
        start[:n_nodes],
        end[:n_nodes],
        left[:n_nodes],
        right[:n_nodes],
        split_dim[:n_nodes],
        split_value[:n_nodes],
        lo[:n_nodes],
        hi[:n_nodes],
    )


@_compiled()
def _find(parent: np.ndarray, i: int) -> int:  # pragma: no cover - compiled
    """Union-find root of i, with path halving."""
    while parent[i] != i:
        parent[i] = parent[parent[i]]
        i = parent[i]
    return i


@_compiled()
def _boruvka_kernel(raw_points: np.ndarray) -> float:  # pragma: no cover - compiled
    """Exact Euclidean MST length by Boruvka rounds with kd-tree nearest-neighbour queries.

    Per round every component finds its shortest edge to another component; a point's query
    skips subtrees that lie wholly in its own component or are farther than the component's
    best edge so far. A point's nearest outside neighbour stays valid while that neighbour is
    still outside (the outside set only shrinks), so most points need one query in all.
    """
    n, d = raw_points.shape
    if n < 2:
        return 0.0
    (points, active, start, end, left, right, split_dim, split_value, lo, hi) = _build_kdtree(
        raw_points
    )
    n_nodes = start.shape[0]
    parent = np.arange(n)
    component = np.arange(n)  # root per point, refreshed after each round
    node_component = np.full(n_nodes, -1, dtype=np.int64)  # -1: several components
    near = np.full(n, -1, dtype=np.int64)  # nearest point in another component, -1 unknown
    near_dist2 = np.zeros(n)  # its squared distance: a lower bound even when stale
    comp_best = np.full(n, np.inf)
    comp_from = np.full(n, -1, dtype=np.int64)
    comp_to = np.full(n, -1, dtype=np.int64)
    n_active = 0
    for i in range(n):
        if active[i]:
            n_active += 1
    edges = 0
    total = 0.0
    stack = np.empty(n_nodes, dtype=np.int64)
    while edges < n_active - 1:
        # Which nodes lie inside one component (children were created after their parent).
        for node in range(n_nodes - 1, -1, -1):
            if left[node] == -1:
                c = component[start[node]]
                for i in range(start[node] + 1, end[node]):
                    if component[i] != c:
                        c = -1
                        break
                node_component[node] = c
            else:
                c = node_component[left[node]]
                node_component[node] = c if c == node_component[right[node]] else -1
        for i in range(n):
            if active[i]:
                comp_best[component[i]] = np.inf
        # Still-valid cached neighbours first: they give tight bounds for the queries.
        for i in range(n):
            if active[i] and near[i] >= 0:
                c = component[i]
                if component[near[i]] == c:
                    near[i] = -1
                elif near_dist2[i] < comp_best[c]:
                    comp_best[c] = near_dist2[i]
                    comp_from[c] = i
                    comp_to[c] = near[i]
        for i in range(n):
            c = component[i]
            if not active[i] or near[i] >= 0 or near_dist2[i] >= comp_best[c]:
                continue
            bound = comp_best[c]
            found = -1
            stack[0] = 0  # the root
            top = 1
            while top > 0:
                top -= 1
                node = stack[top]
                if node_component[node] == c:
                    continue
                box2 = 0.0
                for k in range(d):
                    x = points[i, k]
                    if x < lo[node, k]:
                        delta = lo[node, k] - x
                        box2 += delta * delta
                    elif x > hi[node, k]:
                        delta = x - hi[node, k]
                        box2 += delta * delta
                    if box2 >= bound:
                        break
                if box2 >= bound:
                    continue
                if left[node] == -1:
                    for j in range(start[node], end[node]):
                        if component[j] == c:
                            continue
                        dist2 = 0.0
                        for k in range(d):
                            delta = points[j, k] - points[i, k]
                            dist2 += delta * delta
                            if dist2 >= bound:
                                break
                        if dist2 < bound:
                            bound = dist2
                            found = j
                elif points[i, split_dim[node]] < split_value[node]:
                    stack[top] = right[node]  # farther child below, nearer child on top
                    stack[top + 1] = left[node]
                    top += 2
                else:
                    stack[top] = left[node]
                    stack[top + 1] = right[node]
                    top += 2
            if found >= 0:
                # The query only pruned what was worse than ``found``: it is i's true nearest.
                near[i] = found
                near_dist2[i] = bound
                comp_best[c] = bound
                comp_from[c] = i
                comp_to[c] = found
            else:
                near_dist2[i] = comp_best[c]  # nothing nearer than the bound: a lower bound
        for i in range(n):
            if active[i] and component[i] == i and comp_to[i] >= 0:
                a = _find(parent, comp_from[i])
                b = _find(parent, comp_to[i])
                if a != b:  # equal-weight choices can close a cycle: keep the first edge
                    parent[b] = a
                    total += np.sqrt(comp_best[i])
                    edges += 1
                comp_to[i] = -1
        for i in range(n):
            component[i] = _find(parent, i)
    return total


@_compiled()
def _gain_kernel(points: np.ndarray, use_prim: bool) -> float:  # pragma: no cover - compiled
    if use_prim:
        return _prim_kernel(points)
    return _boruvka_kernel(points)


@_compiled(parallel=True)
def _gains_kernel(
    points: np.ndarray, offsets: np.ndarray, use_prim: bool
) -> np.ndarray:  # pragma: no cover - compiled
    """One MST length per slice points[offsets[s]:offsets[s + 1]], slices in parallel.

    Each slice is computed serially by one thread, so results do not depend on threads.
    """
    n_sets = offsets.shape[0] - 1
    gains = np.zeros(n_sets)
    for s in _prange(n_sets):
        gains[s] = _gain_kernel(points[offsets[s] : offsets[s + 1]], use_prim)
    return gains


# --------------------------------------------------------------------------------------------
# public API


def _resolve(method: str) -> str:
    if method not in METHODS:
        raise ValueError(f"method: expected one of {METHODS}, got {method!r}")
    if method == "auto":
        return "prim" if HAVE_NUMBA else "numpy"
    return method


def experience_gain(points: ArrayLike, method: Method = "auto") -> float:
    """Experience gain G (paper eq. 8): total length of the Euclidean MST of the unique points.

    Args:
        points: (n, d) experience points, one row per decision, in experience-space units.
        method: "auto", "boruvka", "prim" or "numpy" (see the module docstring). Without numba
            "boruvka" and "prim" run uncompiled (correct but slow).

    Returns:
        G >= 0; 0.0 for fewer than two distinct points.

    Raises:
        ValueError: not an (n, d) matrix, a NaN or infinite coordinate, or an unknown method.
    """
    values = _as_points(points)
    chosen = _resolve(method)
    if chosen == "numpy":
        return _prim_numpy(values)
    return float(_gain_kernel(values, chosen == "prim"))


def experience_gains(point_sets: Sequence[ArrayLike], method: Method = "auto") -> np.ndarray:
    """Experience gain of many genomes at once (one (n_s, d) point set per genome).

    With numba the sets are spread over threads; every set is computed by one thread alone, so
    the values equal ``experience_gain`` of each set whatever the thread count.

    Returns:
        (len(point_sets),) float64 gains.

    Raises:
        ValueError: as ``experience_gain``.
    """
    sets = [_as_points(points) for points in point_sets]
    chosen = _resolve(method)
    if not sets:
        return np.zeros(0)
    dims = {values.shape[1] for values in sets}
    if chosen == "numpy" or len(dims) != 1:
        return np.array([experience_gain(values, cast(Method, chosen)) for values in sets])
    offsets = np.zeros(len(sets) + 1, dtype=np.int64)
    offsets[1:] = np.cumsum([values.shape[0] for values in sets])
    gains: np.ndarray = _gains_kernel(np.concatenate(sets), offsets, chosen == "prim")
    return gains
