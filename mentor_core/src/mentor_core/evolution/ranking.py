"""NSGA-II ranking: non-dominated sorting, crowding distance and MENTOR's scalar fitness.

MENTOR (paper, section II "Speciation and Selection") adopts the elitist non-dominated sorting of
Deb et al. (NSGA-II) on a max-max problem: a genome's Pareto front comes first, its crowding
distance inside that front second. Both agree exactly with pymoo 0.6.2 run on the negated
objectives (pymoo minimises): the fronts of its fast non-dominated sort and the ``"cd"``
crowding function of its rank-and-crowding survival, ties included. Every function here takes
the objectives as the problem states them, with ``maximize`` (default True) saying which way.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

# Bound on the booleans held at once while building the dominance matrix (about 16 MB).
_DOMINANCE_BLOCK_ELEMENTS = 1 << 24


def _objective_matrix(objectives: ArrayLike, name: str) -> np.ndarray:
    """Return ``objectives`` as a float64 (n, m) matrix; a 1-D input is one objective (m = 1)."""
    values = np.asarray(objectives, dtype=np.float64)
    if values.ndim == 1:
        values = values.reshape(-1, 1)
    if values.ndim != 2:
        raise ValueError(f"{name}: expected an (n, m) matrix, got shape {values.shape}")
    if values.shape[1] < 1:
        raise ValueError(f"{name}: need at least one objective, got shape {values.shape}")
    if np.isnan(values).any():
        raise ValueError(f"{name}: objectives contain NaN")
    return values


def _dominance_matrix(costs: np.ndarray) -> np.ndarray:
    """``D[i, j]`` is True when i dominates j under minimisation.

    i dominates j when ``costs[i] <= costs[j]`` in every objective and ``<`` in at least one.
    Rows are built in blocks so the (block, n, m) comparison stays small.
    """
    n, m = costs.shape
    dominates = np.empty((n, n), dtype=bool)
    block = max(1, _DOMINANCE_BLOCK_ELEMENTS // max(1, n * m))
    for start in range(0, n, block):
        rows = costs[start : start + block, None, :]
        no_worse = np.all(rows <= costs[None, :, :], axis=2)
        better = np.any(rows < costs[None, :, :], axis=2)
        dominates[start : start + block] = no_worse & better
    return dominates


def non_dominated_ranks(objectives: ArrayLike, maximize: bool = True) -> np.ndarray:
    """Pareto front index of every row of ``objectives`` (0 = non-dominated front).

    Fronts are peeled as in NSGA-II's fast non-dominated sort: front 0 holds the rows no other
    row dominates; front r + 1 the rows dominated only by rows of fronts <= r. With
    ``maximize`` a row dominates another when it is >= in every objective and > in one.

    Args:
        objectives: (n, m) objective values, n >= 0, m >= 1 (1-D means m = 1).
        maximize: True for a max-max problem (the paper's), False to minimise.

    Returns:
        (n,) int64 front index per row.

    Raises:
        ValueError: wrong shape or a NaN objective.
    """
    values = _objective_matrix(objectives, "objectives")
    costs = -values if maximize else values
    n = costs.shape[0]
    ranks = np.full(n, -1, dtype=np.int64)
    if n == 0:
        return ranks
    dominates = _dominance_matrix(costs)
    # dominated_by[j]: rows of the not yet ranked fronts that dominate j.
    dominated_by = dominates.sum(axis=0, dtype=np.int64)
    front = np.flatnonzero(dominated_by == 0)
    rank = 0
    while front.size:
        ranks[front] = rank
        dominated_by -= dominates[front].sum(axis=0, dtype=np.int64)
        dominated_by[front] = -1  # ranked rows never come back
        front = np.flatnonzero(dominated_by == 0)
        rank += 1
    return ranks


def crowding_distance(front_objectives: ArrayLike, maximize: bool = True) -> np.ndarray:
    """NSGA-II crowding distance of each point of one front, exactly as pymoo's ``"cd"``.

    With the points sorted (stable) in objective o, point p's distance is

        cd_p = (1 / m) * sum_o (f_o[next] - f_o[prev]) / (max f_o - min f_o)

    where the first and last points of each sorted column have an infinite gap on their open
    side (so boundary points get +inf). Rules copied from pymoo 0.6.2 so values are identical:
    a front of 1 or 2 points is all +inf; an objective with zero range contributes 0 to every
    point, its boundary points included; exact duplicates are not filtered, they sit next to
    each other in the stable sort with a gap of 0.

    Ties: pymoo minimises, sorting each objective's costs ascending with a stable sort, so of
    duplicates at the *best* value the one with the lowest index is the boundary point (+inf)
    and at the *worst* value the one with the highest index. Like :func:`non_dominated_ranks`,
    this function takes the objectives as the problem states them and sorts the costs pymoo
    sorts (``-objectives`` with ``maximize``), so it equals pymoo's ``"cd"`` on the negated
    objectives, ties included (``tests/test_ranking.py``).

    Args:
        front_objectives: (k, m) objective values of the points of one front.
        maximize: True for a max-max problem (the paper's), False when they are costs.

    Returns:
        (k,) float64 crowding distances, +inf for boundary points.

    Raises:
        ValueError: wrong shape or a NaN objective.
    """
    values = _objective_matrix(front_objectives, "front_objectives")
    if maximize:
        values = -values
    k, m = values.shape
    if k <= 2:
        return np.full(k, np.inf)
    order = np.argsort(values, axis=0, kind="mergesort")
    ordered = np.take_along_axis(values, order, axis=0)
    gaps = ordered[1:] - ordered[:-1]
    norm = ordered[-1] - ordered[0]
    norm[norm == 0] = np.nan  # zero range: every ratio becomes NaN, then 0 below
    open_side = np.full((1, m), np.inf)
    to_previous = np.vstack([open_side, gaps]) / norm
    to_next = np.vstack([gaps, open_side]) / norm
    to_previous[np.isnan(to_previous)] = 0.0
    to_next[np.isnan(to_next)] = 0.0
    per_objective = np.empty((k, m))
    np.put_along_axis(per_objective, order, to_previous + to_next, axis=0)
    # Same operations in the same order as pymoo: sum over objectives, then divide by m.
    distances: np.ndarray = np.sum(per_objective, axis=1) / m
    return distances


def scalar_fitness(objectives: ArrayLike, maximize: bool = True) -> np.ndarray:
    """MENTOR's scalar fitness: front first, crowding distance second; higher is better.

        fitness_i = (n_fronts - rank_i) + 0.5 * c_i / (1 + c_i)

    with c_i the crowding distance of genome i inside its own front (c_i = inf gives 0.5).
    The crowding term lies in [0, 0.5], so every genome of front r scores above every genome of
    front r + 1, and every fitness is >= 1 (positive, as niche sizing needs).

    Args:
        objectives: (n, m) objective values (1-D means m = 1, single-objective use).
        maximize: True for the paper's max-max problem.

    Returns:
        (n,) float64 fitness.

    Raises:
        ValueError: wrong shape or a NaN objective.
    """
    values = _objective_matrix(objectives, "objectives")
    ranks = non_dominated_ranks(values, maximize=maximize)
    fitness = np.empty(ranks.shape[0])
    if ranks.size == 0:
        return fitness
    n_fronts = int(ranks.max()) + 1
    for rank in range(n_fronts):
        members = np.flatnonzero(ranks == rank)
        crowd = crowding_distance(values[members], maximize=maximize)
        bonus = np.full(members.size, 0.5)
        finite = np.isfinite(crowd)
        bonus[finite] = 0.5 * crowd[finite] / (1.0 + crowd[finite])
        fitness[members] = (n_fronts - rank) + bonus
    return fitness
