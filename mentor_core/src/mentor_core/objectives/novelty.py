"""Novelty of a behaviour against the population and an archive (not in the paper).

Novelty search (Lehman and Stanley 2011, "Abandoning objectives: evolution through the search
for novelty alone", Evolutionary Computation 19(2)) scores how far a genome's behaviour lies
from the behaviours seen so far, so that a search whose objective leads into a dead end (a
planner pressing against a wall with its goal behind it) keeps exploring. Mouret 2011
("Novelty-based multiobjectivization") ranks it beside the task objective with NSGA-II, which
is how ``mentor_core.training`` uses it: a third column of the ranked objectives.

A behaviour is a vector (here a planner's final positions in every training scenario); the
novelty of x is its sparseness, Lehman and Stanley's eq. (1):

    rho(x) = (1 / k) sum_{i=1}^{k} dist(x, mu_i)

with mu_i the i-th nearest of the other behaviours of the population and the archive
(Euclidean distance; fewer than k others: the mean over those there are).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray


def _matrix(values: ArrayLike, name: str, width: int | None = None) -> NDArray[np.float64]:
    out = np.asarray(values, dtype=np.float64)
    if out.ndim != 2 or (width is not None and out.shape[1] != width):
        shape = f"(n, {width})" if width is not None else "(n, b)"
        raise ValueError(f"{name}: expected a {shape} matrix, got shape {out.shape}")
    if not np.isfinite(out).all():
        raise ValueError(f"{name}: values must be finite")
    return out


def sparseness(behaviours: ArrayLike, archive: ArrayLike, k: int) -> NDArray[np.float64]:
    """Novelty rho (n,) of each behaviour (n, b) against the others and the archive (a, b).

    Each behaviour's own row is left out; a copy of it elsewhere counts (distance 0).

    Raises:
        ValueError: not matrices of one width, non-finite values, or ``k`` < 1.
    """
    if isinstance(k, bool) or not isinstance(k, int | np.integer) or k < 1:
        raise ValueError(f"k: expected a positive int, got {k!r}")
    current = _matrix(behaviours, "behaviours")
    past = _matrix(archive, "archive", current.shape[1])
    n = current.shape[0]
    if n == 0:
        return np.zeros(0, dtype=np.float64)
    others = np.concatenate([current, past], axis=0)
    # (n, n + a) distances, each summed over the dimensions in order: the same on every run
    dist = np.sqrt(((current[:, None, :] - others[None, :, :]) ** 2).sum(axis=2))
    dist[np.arange(n), np.arange(n)] = np.inf  # not its own neighbour
    count = min(int(k), others.shape[0] - 1)
    if count == 0:
        return np.zeros(n, dtype=np.float64)
    nearest = np.sort(dist, axis=1)[:, :count]
    return np.asarray(nearest.mean(axis=1), dtype=np.float64)


def most_novel(novelty: ArrayLike, count: int) -> NDArray[np.int64]:
    """Indices of the ``count`` highest novelties, highest first (ties: the lower index).

    The archive grows by these each generation: deterministic, unlike Lehman and Stanley's
    adaptive threshold, and a fixed growth per generation (as in Gomes et al. 2015).
    """
    values = np.asarray(novelty, dtype=np.float64)
    if values.ndim != 1:
        raise ValueError(f"novelty: expected a 1-D array, got shape {values.shape}")
    if isinstance(count, bool) or not isinstance(count, int | np.integer) or count < 0:
        raise ValueError(f"count: expected a non-negative int, got {count!r}")
    order = np.argsort(-values, kind="stable")
    return np.asarray(order[: int(count)], dtype=np.int64)
