"""One generation of MENTOR breeding: elites, niche growth and shrinkage, global champions.

Paper, section II ("Speciation and Selection", "Niche Growth and Shrinkage", "Crossover and
Mutation"), and the design brief ("MENTOR evolution"). :func:`reproduce` is pure given its
arguments: the genomes, their scalar fitness (higher is better; NSGA-II rank first, crowding
second, from ``ranking.scalar_fitness``), their species labels, the configuration, the run's
innovation tracker and the run's generator. The same inputs and the same generator state give
the same offspring.

How the paper's text maps onto the steps, for a population of N genomes:

1. **Elitism** ("Elitist Preservation 2%", Table I). ``n_elite = round(elitism * N)``, at least
   one when ``elitism > 0``; the ``n_elite`` genomes with the highest fitness (lowest index on
   ties) pass into the next population unchanged, before everything else.
2. **Global reproduction** ("champions from each species are combined and put through these
   reproductive operations"; "rank-based proportionate selection is used in global
   reproduction"). ``n_global = round(global_fraction * N)`` offspring are bred from the
   champions (best member) of all species present, both parents drawn with
   ``selection.rank_proportionate``. The paper does not give the share; it is
   ``EvolutionConfig.global_fraction``.
3. **Niche sizes** (eq. 2, N'_i = sum_j Fbar_ij / Fbar): ``selection.niche_sizes`` distributes
   the ``N - n_elite - n_global`` remaining slots over the species (largest-remainder rounding,
   so they sum exactly).
4. **Shrinkage** ("If the current size is greater than the desired size, some genomes are
   discarded"): a species with more members than N'_i keeps only its N'_i best members as its
   parent pool; the worst are dropped. A species with N'_i = 0 goes extinct.
5. **Growth** ("If the current size of a niche is smaller than its desired size ... some
   candidate genomes in the niche will undergo mutation"): every surviving species breeds
   exactly N'_i children from its pool, so a small niche with a large N'_i grows. Intra-species
   reproduction uses tournament selection ("We use tournament selection in intra-species
   reproduction"): the first parent by ``selection.tournament`` in the pool; with probability
   ``crossover_rate`` (0.85, Table I) a second parent, also by tournament, and
   ``crossover.crossover`` with ``a_better`` from the fitness comparison (``None`` on equal
   fitness, "randomly, if both parents belong to the same rank"); otherwise a copy of the first
   parent. Every child is then mutated by ``mutation.mutate`` (per-edge weight and node-addition
   mutation; edge addition: each hidden or output node gains one new in-edge with the rate).

Choices the paper leaves open, fixed here:

- Elites and global offspring are taken off the top before eq. 2 is applied, so the niche
  targets sum to ``N - n_elite - n_global`` and the total is exactly N.
- A niche is bred from its own surviving (pool) members only; its members are ranked by the
  same scalar fitness as the whole population.
- The two tournament parents may be the same genome (as in NEAT); crossover of a genome with
  itself returns a copy of it, which is then mutated.
- The champion of a species is its member with the highest fitness (lowest population index on
  ties). Champions are drawn with replacement; the two global parents may coincide.
- Order of the offspring (and of the generator draws): elites by descending fitness, then the
  niches in ascending species id, then the global offspring. ``tracker.new_generation()`` is
  called once, first, so identical structural mutations within this generation share ids.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from mentor_core.evolution.crossover import crossover
from mentor_core.evolution.genome import Genome
from mentor_core.evolution.innovation import InnovationTracker
from mentor_core.evolution.mutation import MutationConfig, mutate
from mentor_core.evolution.selection import niche_sizes, rank_proportionate, tournament

if TYPE_CHECKING:
    from mentor_core.evolution.config import EvolutionConfig


@dataclass(frozen=True)
class Offspring:
    """The next population and how it was made.

    ``genomes``: N genomes in breeding order (elites, niches by id, global offspring);
    ``niche_targets``: N'_i of every species of the parents (0 for an extinct one);
    ``elites``: population indices of the elites; ``n_global``: number of global offspring.
    """

    genomes: tuple[Genome, ...]
    niche_targets: Mapping[int, int]
    elites: tuple[int, ...]
    n_global: int


def elite_count(elitism: float, population_size: int) -> int:
    """Number of elites: ``round(elitism * N)``, at least 1 when ``elitism > 0``."""
    if elitism <= 0.0:
        return 0
    return max(1, round(elitism * population_size))


def global_count(global_fraction: float, population_size: int) -> int:
    """Number of offspring bred from the species champions: ``round(global_fraction * N)``."""
    return round(global_fraction * population_size)


def order_by_fitness(fitness: np.ndarray, indices: np.ndarray | None = None) -> np.ndarray:
    """``indices`` (default all) sorted by descending fitness, lower index first on ties."""
    idx = np.arange(len(fitness)) if indices is None else np.asarray(indices, dtype=np.intp)
    # lexsort sorts by the last key first: fitness descending, then index ascending
    return idx[np.lexsort((idx, -fitness[idx]))]


def _breed(
    first: Genome,
    second: Genome | None,
    f_first: float,
    f_second: float,
    mutation: MutationConfig,
    tracker: InnovationTracker,
    rng: np.random.Generator,
) -> Genome:
    """Crossover (when ``second`` is given) or copy, then mutation."""
    if second is None:
        child = first
    else:
        a_better: bool | None = None if f_first == f_second else bool(f_first > f_second)
        child = crossover(first, second, a_better, rng)
    return mutate(child, mutation, tracker, rng)


def reproduce(
    genomes: Sequence[Genome],
    fitness: np.ndarray,
    labels: np.ndarray,
    config: EvolutionConfig,
    tracker: InnovationTracker,
    rng: np.random.Generator,
) -> Offspring:
    """Breed the next population of ``config.population_size`` genomes (see module docstring).

    ``fitness``: (n,) float, higher is better; ``labels``: (n,) int species id of each genome.
    Raises ``ValueError`` when the lengths disagree or the population is empty.
    """
    fitness = np.asarray(fitness, dtype=np.float64)
    labels = np.asarray(labels, dtype=np.int64)
    n = len(genomes)
    if n == 0:
        raise ValueError("cannot breed from an empty population")
    if fitness.shape != (n,) or labels.shape != (n,):
        raise ValueError(
            f"fitness {fitness.shape} and labels {labels.shape} must both have shape ({n},)"
        )
    if not np.all(np.isfinite(fitness)):
        raise ValueError("fitness must be finite")

    tracker.new_generation()
    size = config.population_size
    n_elite = min(elite_count(config.elitism, size), n, size)
    n_global = min(global_count(config.global_fraction, size), size - n_elite)
    ranked = order_by_fitness(fitness)
    elites = tuple(int(i) for i in ranked[:n_elite])
    children: list[Genome] = [genomes[i] for i in elites]

    species_ids = sorted({int(s) for s in labels})
    members = {s: order_by_fitness(fitness, np.flatnonzero(labels == s)) for s in species_ids}
    targets = niche_sizes(fitness, labels, size - n_elite - n_global)
    targets = {s: int(targets.get(s, 0)) for s in species_ids}

    for s in species_ids:
        target = targets[s]
        if target <= 0:
            continue  # extinct
        pool = members[s][:target]  # shrinkage: the worst members are dropped
        pool_fitness = fitness[pool]
        for _ in range(target):
            i = int(pool[tournament(pool_fitness, rng, config.tournament_size)])
            j: int | None = None
            if rng.random() < config.crossover_rate:
                j = int(pool[tournament(pool_fitness, rng, config.tournament_size)])
            children.append(
                _breed(
                    genomes[i],
                    None if j is None else genomes[j],
                    float(fitness[i]),
                    float(fitness[j]) if j is not None else 0.0,
                    config.mutation,
                    tracker,
                    rng,
                )
            )

    if n_global > 0:
        champions = np.array([members[s][0] for s in species_ids], dtype=np.intp)
        champ_order = order_by_fitness(fitness, champions)
        champ_fitness = fitness[champ_order]
        firsts = rank_proportionate(champ_fitness, rng, n_global)
        seconds = rank_proportionate(champ_fitness, rng, n_global)
        for a, b in zip(firsts, seconds, strict=True):
            i = int(champ_order[int(a)])
            j = int(champ_order[int(b)]) if rng.random() < config.crossover_rate else None
            children.append(
                _breed(
                    genomes[i],
                    None if j is None else genomes[j],
                    float(fitness[i]),
                    float(fitness[j]) if j is not None else 0.0,
                    config.mutation,
                    tracker,
                    rng,
                )
            )

    if len(children) != size:  # a broken niche_sizes contract, not a user error
        raise RuntimeError(f"bred {len(children)} genomes instead of {size}")
    return Offspring(
        genomes=tuple(children), niche_targets=targets, elites=elites, n_global=n_global
    )
