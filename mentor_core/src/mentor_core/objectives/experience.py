"""Experience gain G: length of the Euclidean minimum spanning tree of experience points.

Paper eqs. 5-8: a genome's experience points V = [U(t), A(t), U(t+1)] (eq. 7) from all its
scenarios (the union, eq. 5; exact duplicates removed) are the nodes of a complete graph whose
edge weights are the Euclidean distances W_ij = |V_i - V_j| (eq. 6); the criterion is the total
weight of its minimum spanning tree (eq. 8),

    G = sum_{e in MST} W_e.

The MST weight is the same for every exact algorithm (the paper uses Kruskal). A duplicate point
only adds zero-length edges, so G over the unique rows equals G over all rows: the kd-tree kernel
collapses duplicates for speed, the Prim kernel keeps them, the numpy path removes them first.

Methods:
    "bounded"  numba, Prim's algorithm that skips the distances which provably cannot shorten a
               link (a float32 filter with rigorous error bounds, triangle-inequality bounds
               along the chain of newcomers, repeated points): the same edges in the same order
               as "prim", so the same G bit for bit (``emst_prim``).
    "prim"     numba, Prim's algorithm on the fly (``emst_prim``): O(n d) memory, O(n^2 d) time.
    "boruvka"  numba, Boruvka's algorithm with a kd-tree (``emst_boruvka``); never forms the
               n^2 edges.
    "numpy"    pure numpy Prim (one vectorised distance row per step); the fallback and the
               reference the tests compare the kernels with.
    "auto"     "bounded" when numba imports, else "numpy". Measured with
               benchmarks/perf/experience_bench.py: at the trainer's <= 4,000 points in 8-18 D
               "bounded" is about 1.6x "prim" (1-3x, most where experiences repeat) and
               kd-tree boxes prune little (the actions make the points truly
               high-dimensional); "boruvka" wins on sensor-like data from about 16,000 points.
"""

from __future__ import annotations

from collections.abc import Sequence
from itertools import pairwise
from typing import Literal, cast

import numpy as np
from numpy.typing import ArrayLike

from mentor_core.objectives.emst_boruvka import boruvka_length
from mentor_core.objectives.emst_prim import bounded_prim_length, prim_length
from mentor_core.objectives.jit import HAVE_NUMBA, compiled, prange

Method = Literal["auto", "bounded", "prim", "boruvka", "numpy"]
METHODS: tuple[str, ...] = ("auto", "bounded", "prim", "boruvka", "numpy")
# The compiled kernels by number, for the batch kernel (numba passes no functions around).
_KERNELS: tuple[str, ...] = ("bounded", "prim", "boruvka")


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
# compiled dispatch


@compiled()
def _gain_kernel(points: np.ndarray, kernel: int) -> float:  # pragma: no cover - compiled
    if kernel == 2:
        return boruvka_length(points)
    if kernel == 1:
        return prim_length(points)
    return bounded_prim_length(points)


@compiled(parallel=True)
def _gains_kernel(
    points: np.ndarray, offsets: np.ndarray, kernel: int
) -> np.ndarray:  # pragma: no cover - compiled
    """One MST length per slice points[offsets[s]:offsets[s + 1]], slices in parallel.

    Each slice is computed serially by one thread, so results do not depend on threads.
    """
    n_sets = offsets.shape[0] - 1
    gains = np.zeros(n_sets)
    for s in prange(n_sets):
        gains[s] = _gain_kernel(points[offsets[s] : offsets[s + 1]], kernel)
    return gains


@compiled(nogil=True)
def _gains_claimed(
    points: np.ndarray,
    offsets: np.ndarray,
    kernel: int,
    gains: np.ndarray,
    claimed: np.ndarray,
    reverse: bool,
) -> None:  # pragma: no cover - compiled
    """``gains[s]`` for every slice whose ``claimed[s]`` is 0, claiming it first, in the
    calling thread without the GIL; slices in order, or last first."""
    n_sets = offsets.shape[0] - 1
    for i in range(n_sets):
        s = n_sets - 1 - i if reverse else i
        if claimed[s] == 0:
            claimed[s] = 1
            gains[s] = _gain_kernel(points[offsets[s] : offsets[s + 1]], kernel)


# --------------------------------------------------------------------------------------------
# public API


def _resolve(method: str) -> str:
    if method not in METHODS:
        raise ValueError(f"method: expected one of {METHODS}, got {method!r}")
    if method == "auto":
        return "bounded" if HAVE_NUMBA else "numpy"
    return method


def experience_gain(points: ArrayLike, method: Method = "auto") -> float:
    """Experience gain G (paper eq. 8): total length of the Euclidean MST of the unique points.

    Args:
        points: (n, d) experience points, one row per decision, in experience-space units.
        method: "auto", "bounded", "prim", "boruvka" or "numpy" (see the module docstring).
            Without numba the compiled methods run as plain Python (correct but slow).

    Returns:
        G >= 0; 0.0 for fewer than two distinct points.

    Raises:
        ValueError: not an (n, d) matrix, a NaN or infinite coordinate, or an unknown method.
    """
    values = _as_points(points)
    chosen = _resolve(method)
    if chosen == "numpy":
        return _prim_numpy(values)
    return float(_gain_kernel(values, _KERNELS.index(chosen)))


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
    return experience_gains_packed(np.concatenate(sets), offsets, cast(Method, chosen))


def experience_gains_packed(
    points: ArrayLike, offsets: ArrayLike, method: Method = "auto"
) -> np.ndarray:
    """``experience_gains`` of the consecutive slices ``points[offsets[s]:offsets[s + 1]]``
    of one ``(n, d)`` array (the trainer's layout: every genome's experience points in a
    row), without copying them; rows outside the slices are not read.

    Returns:
        (len(offsets) - 1,) float64 gains, equal to ``experience_gains`` of the slices.

    Raises:
        ValueError: as ``experience_gain``; offsets not rising within ``[0, n]``.
    """
    values, at = _packed(points, offsets)
    chosen = _resolve(method)
    if chosen == "numpy":
        return np.array([_prim_numpy(values[a:b] + 0.0) for a, b in pairwise(at.tolist())])
    gains: np.ndarray = _gains_kernel(values, at, _KERNELS.index(chosen))
    return gains


def experience_gains_shared(
    points: ArrayLike,
    offsets: ArrayLike,
    gains: np.ndarray,
    claimed: np.ndarray,
    *,
    reverse: bool = False,
) -> None:
    """Fill ``gains[s]`` with ``experience_gains_packed(points, offsets)[s]`` for every slice
    whose ``claimed[s]`` is 0, claiming it first; last slice first with ``reverse``.

    For threads sharing one batch of slices (``training.gain_overlap``): the compiled kernel
    releases the GIL, so several threads can call this on the same arrays at once; a slice
    two threads claim together is computed by both, to the same value. Read ``gains`` after
    every call has returned. Without numba it runs as plain Python (correct but slow).

    Raises:
        ValueError: as ``experience_gains_packed``; ``gains`` not a float64 vector or
            ``claimed`` not an int8 vector of one entry per slice.
    """
    values, at = _packed(points, offsets)
    n_sets = len(at) - 1
    if gains.dtype != np.float64 or gains.shape != (n_sets,):
        raise ValueError(f"gains: expected a float64 vector of {n_sets}")
    if claimed.dtype != np.int8 or claimed.shape != (n_sets,):
        raise ValueError(f"claimed: expected an int8 vector of {n_sets}")
    _gains_claimed(values, at, _KERNELS.index("bounded"), gains, claimed, reverse)


def _packed(points: ArrayLike, offsets: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """``points`` as a C-contiguous float64 matrix and ``offsets`` as int64, checked."""
    values = np.asarray(points, dtype=np.float64)
    if values.ndim != 2:
        raise ValueError(f"points: expected an (n, d) matrix, got shape {values.shape}")
    at = np.asarray(offsets, dtype=np.int64).reshape(-1)
    if len(at) < 1 or at[0] < 0 or np.any(np.diff(at) < 0) or at[-1] > len(values):
        raise ValueError(f"offsets: expected rising within [0, {len(values)}]")
    if not np.isfinite(values[at[0] : at[-1]]).all():
        raise ValueError("points: coordinates must be finite (NaN or inf found)")
    # the compiled kernels compare coordinates, never their bytes: -0.0 needs no copy
    return np.ascontiguousarray(values), at
