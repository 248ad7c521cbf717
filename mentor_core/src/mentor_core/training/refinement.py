"""Refinement of a trained planner's weights (not in the paper): a (1 + lambda) search.

After evolution, the run's best genome is refined on training scenarios it was not evolved
on: ``scenarios`` of them in ``worlds`` worlds, drawn by the training generator from another
seed (never the benchmark's validation or test pairs) and given the benchmark's 50 s;
``families`` adds a world of each structured family named, drawn from the training seeds as
a curriculum's.
Each iteration draws ``offspring`` copies of the current genome with NEAT's weight
perturbation (each connection weight, with probability ``weight_rate``, plus
N(0, ``weight_sigma``); the topology stays) and moves to the copy of the highest path credit

    C = sum_i delta_i l_i / max(p_i, l_i)

(the sum of the per-pair terms of SPL, Anderson et al. 2018: ``delta_i`` whether scenario i
was reached, ``l_i`` its shortest path's length, ``p_i`` the length driven;
:func:`~mentor_core.objectives.performance.path_credit`) among those that reach at least as
many goals as the current genome, when its credit is higher. Goals reached and credit never
fall, on these scenarios.

Why: evolution ranks F (paper eq. 3), whose time credit hardly sees a detour, and every
attempt to press on the path within F cost goals (experiment E029, "Crediting the
path" and after). Refining the finished planner with goals held as a constraint does not
trade them. Chosen for both robots on the validation split (experiment E074,
"Refining the weights after evolution"; the UGV's on a sparse forest, "Seven more
refinements, and a memory of the last action").
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from functools import partial
from typing import Annotated

import numpy as np
from pydantic import Field, model_validator

from mentor_core.evolution.genome import Genome
from mentor_core.evolution.mutation import MutationConfig, mutate_weights
from mentor_core.objectives.performance import path_credit
from mentor_core.sim.families import family_names_fault
from mentor_core.training.problem import NavigationProblem, shortest_lengths
from mentor_core.validation import Float, Int, Str, config_dataclass, fault

#: called after each iteration with (iteration, iterations, goals reached, path credit)
Progress = Callable[[int, int, int, float], None]

#: goals reached and path credit C per genome of a list
Scores = tuple[np.ndarray, np.ndarray]

#: runs a scoring function on contiguous chunks of the copies, the results in order
#: (:meth:`~mentor_core.training.evaluators.Evaluator.map_chunks`: a run's workers)
ChunkMap = Callable[[Callable[[Sequence[Genome]], Scores], Sequence[Genome]], list[Scores]]


@config_dataclass
class RefinementConfig:
    """The refinement of a run's best genome (module docstring); off by default, as in the
    paper."""

    iterations: Annotated[Int, Field(ge=0)] = 0
    """Iterations of the (1 + lambda) search (0: no refinement, as in the paper)."""
    offspring: Annotated[Int, Field(ge=1)] = 16
    """Weight-perturbed copies of the current genome tried per iteration (lambda)."""
    scenarios: Annotated[Int, Field(ge=1)] = 600
    """Refinement scenarios, drawn as the training scenarios are (the config's pair distances
    and world layout) from scenario_seed, in worlds composite worlds."""
    worlds: Annotated[Int, Field(ge=1)] = 8
    """Composite worlds the refinement scenarios are spread over, at most scenarios."""
    scenario_seed: Annotated[Int, Field(ge=0)] = 1001
    """Seed of the refinement worlds and pairs; another than the training's scenario_seed."""
    time_budget: Annotated[Float, Field(gt=0.0)] = 50.0
    """Time budget of every refinement scenario, s (the benchmark's and the paper's 50 s)."""
    weight_rate: Annotated[Float, Field(gt=0.0, le=1.0)] = 0.3
    """Probability that a connection weight of a copy is perturbed."""
    weight_sigma: Annotated[Float, Field(gt=0.0)] = 0.15
    """Standard deviation of a weight's perturbation."""
    families: tuple[Str, ...] = ()
    """Structured worlds added to the refinement scenarios: one world of each named family
    (mentor_core.sim.families) with family_pairs pairs, drawn from the training seeds
    (mentor_core.training.curriculum), never the benchmark's; none by default."""
    family_pairs: Annotated[Int, Field(ge=1)] = 30
    """Start/goal pairs in each family's refinement world."""

    @model_validator(mode="after")
    def _consistent(self) -> RefinementConfig:
        why = family_names_fault(self.families)
        if why:
            raise fault("families", why)
        if self.worlds > self.scenarios:
            raise fault(
                "worlds", f"must be in [1, scenarios] ({self.scenarios}), got {self.worlds}"
            )
        return self


@dataclass(frozen=True)
class Refinement:
    """What :func:`refine` returns: the refined genome, and goals reached and path credit on
    the refinement scenarios before and after (``accepted``: iterations that moved)."""

    genome: Genome
    reached_before: int
    reached: int
    credit_before: float
    credit: float
    accepted: int


def refine(
    genome: Genome,
    problem: NavigationProblem,
    config: RefinementConfig,
    rng: np.random.Generator,
    progress: Progress | None = None,
    evolution_mutation: MutationConfig | None = None,
    chunk_map: ChunkMap | None = None,
) -> Refinement:
    """Refine ``genome``'s weights on ``problem``'s scenarios (module docstring); the same
    ``rng`` state gives the same genome. Weights are clipped to ``evolution_mutation``'s
    ``weight_max``, the run's (default: NEAT's defaults). ``chunk_map`` spreads each
    iteration's copies over workers (default: in process); the genome is the same."""
    score_chunk = partial(_score, problem, shortest_lengths(problem.scenarios, problem.profile))

    def scores(genomes: list[Genome]) -> Scores:
        parts = [score_chunk(genomes)] if chunk_map is None else chunk_map(score_chunk, genomes)
        return np.concatenate([p[0] for p in parts]), np.concatenate([p[1] for p in parts])

    mutation = dataclasses.replace(
        evolution_mutation or MutationConfig(), weight_rate=config.weight_rate,
        weight_perturb_sigma=config.weight_sigma, weight_replace_rate=0.0,
    )  # fmt: skip
    reached, credit = score_chunk([genome])
    best, goals, score = genome, int(reached[0]), float(credit[0])
    first = (goals, score)
    accepted = 0
    for it in range(config.iterations):
        copies = [
            dataclasses.replace(best, connections=tuple(mutate_weights(best.connections,
                                                                       mutation, rng)))
            for _ in range(config.offspring)
        ]  # fmt: skip
        reached, credit = scores(copies)
        j = chosen(reached, credit, goals, score)
        if j is not None:
            best, goals, score = copies[j], int(reached[j]), float(credit[j])
            accepted += 1
        if progress is not None:
            progress(it + 1, config.iterations, goals, score)
    return Refinement(best, first[0], goals, first[1], score, accepted)


def chosen(
    reached: np.ndarray, credit: np.ndarray, goals: int, score: float
) -> int | None:
    """The copy to move to (module docstring): of the copies that reach at least ``goals``,
    the first of the highest ``credit``, if that is above ``score``; else None."""
    allowed = np.flatnonzero(np.asarray(reached) >= goals)
    if not len(allowed):
        return None
    j = int(allowed[np.argmax(np.asarray(credit)[allowed])])
    return j if credit[j] > score else None


def _score(
    problem: NavigationProblem, shortest: np.ndarray, genomes: Sequence[Genome]
) -> Scores:
    """Goals reached and path credit C (module docstring) per genome; module level, so that
    it pickles for a run's workers."""
    batch = problem.simulate(genomes)
    n = len(problem.scenarios)
    driven = batch.path_length(problem.profile)
    terms = np.where(batch.reached, path_credit(np.tile(shortest, len(genomes)), driven), 0.0)
    terms = terms.reshape(len(genomes), n)
    return batch.reached.reshape(len(genomes), n).sum(axis=1), terms.sum(axis=1)


__all__ = ["ChunkMap", "Progress", "Refinement", "RefinementConfig", "chosen", "refine"]
