"""The exact Euclidean distance from every cell of a grid to the nearest blocked cell, in
linear time (Felzenszwalb & Huttenlocher 2012, "Distance transforms of sampled functions").

Squared distances between cell centres, in cells: first along each column (the 1-D distance to
the nearest blocked cell of the column), then along each row the lower envelope of the
parabolas ``f(q) + (p - q)^2``, ``f`` the column pass. Integers throughout, so the distances
(``sqrt`` of them) are exactly ``scipy.ndimage.distance_transform_edt``'s, which
:mod:`~mentor_core.navigation.grid_planner` used before; compiled by numba without the GIL, so
a plan made on another thread does not hold back the controller deciding on this one.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

BoolArray = NDArray[np.bool_]
IntArray = NDArray[np.int64]
FloatArray = NDArray[np.float64]


def _squared(blocked: BoolArray) -> IntArray:
    """``(h, w)`` squared distances (cells) of each cell's centre to the nearest blocked
    cell's (module docstring); ``big`` where the grid has none."""
    h, w = blocked.shape
    big = (h + w) * (h + w) + 1  # more than any distance on the grid
    column = np.empty((h, w), dtype=np.int64)
    for j in range(w):  # row by row, so that memory is read in order
        column[0, j] = 0 if blocked[0, j] else big
    for i in range(1, h):
        for j in range(w):
            column[i, j] = 0 if blocked[i, j] else min(column[i - 1, j] + 1, big)
    for i in range(h - 2, -1, -1):
        for j in range(w):
            if column[i + 1, j] + 1 < column[i, j]:
                column[i, j] = column[i + 1, j] + 1
    out = np.empty((h, w), dtype=np.int64)
    f = np.empty(w, dtype=np.int64)
    v = np.empty(w, dtype=np.int64)  # the parabolas of the lower envelope
    z = np.empty(w + 1, dtype=np.float64)  # where each takes over
    for i in range(h):
        for j in range(w):
            c = column[i, j]
            f[j] = c * c if c < big else big * big
        k = 0
        v[0] = 0
        z[0], z[1] = -np.inf, np.inf
        for q in range(1, w):
            while True:
                p = v[k]
                s = ((f[q] + q * q) - (f[p] + p * p)) / (2.0 * (q - p))
                if s <= z[k] and k > 0:
                    k -= 1
                    continue
                if s <= z[k]:  # k == 0: the new parabola is lower everywhere
                    v[0] = q
                    z[1] = np.inf
                    break
                k += 1
                v[k] = q
                z[k] = s
                z[k + 1] = np.inf
                break
        k = 0
        for q in range(w):
            while z[k + 1] < q:
                k += 1
            p = v[k]
            out[i, q] = min((q - p) * (q - p) + f[p], big)
    return out


_squared_numba: Callable[[BoolArray], IntArray] | None
try:
    from numba import njit

    _squared_numba = njit(cache=True, nogil=True)(_squared)
except ImportError:  # pragma: no cover - numba is in the lock file
    _squared_numba = None


def squared_distances(blocked: BoolArray) -> IntArray:
    """``(h, w)`` squared distances (cells) from each cell's centre to the nearest ``blocked``
    cell's centre, exact (module docstring); larger than ``(h + w)^2`` where none is
    blocked."""
    mask = np.ascontiguousarray(blocked, dtype=np.bool_)
    kernel = _squared_numba or _squared
    return kernel(mask)


def distances(blocked: BoolArray) -> FloatArray:
    """``(h, w)`` Euclidean distances (cells) to the nearest ``blocked`` cell:
    ``scipy.ndimage.distance_transform_edt(~blocked)`` exactly (module docstring)."""
    return np.sqrt(squared_distances(blocked).astype(np.float64))
