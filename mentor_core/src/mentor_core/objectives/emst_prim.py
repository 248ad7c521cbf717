"""Exact Euclidean MST length by Prim's algorithm on the fly (numba kernel).

``prim_length`` measures, at every step, the point that just joined the tree against every
point outside it: O(n^2 d) time and O(n d) memory, no distance stored.
"""

from __future__ import annotations

import numpy as np

from mentor_core.objectives.jit import compiled


@compiled()
def prim_length(points: np.ndarray) -> float:  # pragma: no cover - compiled
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
