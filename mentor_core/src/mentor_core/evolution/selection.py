"""MENTOR selection: niche growth and shrinkage (paper eq. 2), tournament, rank-proportionate.

Niche sizes say how many members each niche (species) may hold next generation; tournament
selection picks parents inside a niche; rank-based proportionate selection picks among the
niche champions in global reproduction (paper, section II).
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np
from numpy.typing import ArrayLike


def _fitness_vector(fitness: ArrayLike) -> np.ndarray:
    values = np.asarray(fitness, dtype=np.float64)
    if values.ndim != 1 or values.size == 0:
        raise ValueError(f"fitness: expected a non-empty 1-D array, got shape {values.shape}")
    if not np.isfinite(values).all():
        raise ValueError("fitness: values must be finite")
    return values


def niche_sizes(fitness: ArrayLike, labels: ArrayLike, total: int) -> dict[int, int]:
    """Allowed size of each niche next generation (paper eq. 2), summing exactly to ``total``.

        N'_i = sum_j Fbar_ij / Fbar,   Fbar_ij = F_ij / N_i,   Fbar = (1/n) sum_i sum_j Fbar_ij

    F_ij is the fitness of member j of niche i, N_i the niche's current size and n the
    population size, so N'_i is n times niche i's share of the summed mean niche fitness and the
    N'_i sum to n. Sharing by N_i is what shrinks a crowded niche: with equal fitness every
    niche gets n / (number of niches), whatever its size. The real sizes are scaled to ``total``
    and rounded by largest remainder (ties to the lower label). The arithmetic is exact
    (rationals), so equal inputs give equal sizes and ties are true ties.

    Args:
        fitness: (n,) positive fitness (higher is better).
        labels: (n,) integer niche label of each genome.
        total: number of places to share out (often n; may differ).

    Returns:
        {label: size} with keys sorted ascending and values summing to ``total``.

    Raises:
        ValueError: empty or mismatched inputs, non-positive or non-finite fitness, non-integer
            labels or a negative ``total``.
    """
    values = _fitness_vector(fitness)
    niche = np.asarray(labels)
    if niche.shape != values.shape:
        raise ValueError(f"labels: shape {niche.shape} does not match fitness {values.shape}")
    if not np.issubdtype(niche.dtype, np.integer):
        raise ValueError(f"labels: expected integers, got dtype {niche.dtype}")
    if np.any(values <= 0.0):
        raise ValueError("fitness: niche sizing needs positive fitness")
    if isinstance(total, bool) or not isinstance(total, int | np.integer) or total < 0:
        raise ValueError(f"total: expected a non-negative integer, got {total!r}")

    keys = [int(key) for key in np.unique(niche)]
    # Sum over the niche of F_ij / N_i is the niche's mean fitness; exact in rationals.
    mean_fitness = []
    for key in keys:
        members = values[niche == key]
        mean_fitness.append(sum((Fraction(float(f)) for f in members), Fraction(0)) / len(members))
    grand = sum(mean_fitness, Fraction(0))
    quotas = [Fraction(int(total)) * share / grand for share in mean_fitness]

    sizes = [int(quota) for quota in quotas]  # floor: quotas are non-negative
    left = int(total) - sum(sizes)
    # Largest remainder first; sorted() is stable, so equal remainders keep label order.
    by_remainder = sorted(range(len(keys)), key=lambda i: quotas[i] - sizes[i], reverse=True)
    for i in by_remainder[:left]:
        sizes[i] += 1
    return dict(zip(keys, sizes, strict=True))


def tournament(fitness: ArrayLike, rng: np.random.Generator, size: int = 2) -> int:
    """Index of the fittest of ``size`` genomes drawn uniformly with replacement.

    Ties go to the lower index.

    Args:
        fitness: (n,) fitness, higher is better.
        rng: the run's random generator.
        size: number of contestants, >= 1.

    Raises:
        ValueError: empty or non-finite fitness, or ``size`` < 1.
    """
    values = _fitness_vector(fitness)
    if size < 1:
        raise ValueError(f"size: a tournament needs at least one contestant, got {size}")
    contestants = rng.integers(0, values.size, size=size)
    best = values[contestants].max()
    return int(contestants[values[contestants] == best].min())


def rank_proportionate(fitness: ArrayLike, rng: np.random.Generator, n: int) -> np.ndarray:
    """Draw ``n`` indices with replacement by rank-based proportionate selection.

    Genomes are sorted by fitness, best first (stable: ties keep index order); the genome at
    position p (0-based) of L is drawn with probability

        P(p) = (L - p) / (L (L + 1) / 2).

    Args:
        fitness: (L,) fitness, higher is better.
        rng: the run's random generator.
        n: number of draws, >= 0.

    Returns:
        (n,) int64 indices into ``fitness``.

    Raises:
        ValueError: empty or non-finite fitness, or a negative ``n``.
    """
    values = _fitness_vector(fitness)
    if n < 0:
        raise ValueError(f"n: expected a non-negative number of draws, got {n}")
    order = np.argsort(-values, kind="stable")
    weights = np.arange(values.size, 0, -1, dtype=np.float64)
    positions = rng.choice(values.size, size=n, p=weights / weights.sum())
    return order[positions].astype(np.int64)
