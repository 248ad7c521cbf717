"""MENTOR breeding: elites, niche growth/shrinkage, extinction, global champions, determinism."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from mentor_core.evolution.config import EvolutionConfig
from mentor_core.evolution.genome import Genome, minimal_genome
from mentor_core.evolution.innovation import InnovationTracker
from mentor_core.evolution.mutation import MutationConfig
from mentor_core.evolution.reproduction import (
    elite_count,
    global_count,
    order_by_fitness,
    reproduce,
)
from mentor_core.evolution.selection import niche_sizes

# No mutation and no crossover: every child is an exact copy of its (first) parent, so each
# child can be traced back to the genome it came from.
FROZEN = MutationConfig(weight_rate=0.0, node_rate=0.0, edge_rate=0.0)


def population(n: int, seed: int = 0) -> tuple[list[Genome], InnovationTracker]:
    tracker = InnovationTracker(next_node_id=4)
    rng = np.random.default_rng(seed)
    return [minimal_genome(2, 1, tracker, rng) for _ in range(n)], tracker


def config(n: int, **kw: object) -> EvolutionConfig:
    base = {"population_size": n, "crossover_rate": 0.0, "mutation": FROZEN}
    base.update(kw)
    return EvolutionConfig(**base)  # type: ignore[arg-type]


def parent_of(child: Genome, genomes: list[Genome]) -> int:
    matches = [i for i, g in enumerate(genomes) if g == child]
    assert len(matches) == 1
    return matches[0]


def test_counts() -> None:
    assert elite_count(0.02, 100) == 2
    assert elite_count(0.02, 150) == 3
    assert elite_count(0.001, 100) == 1  # at least one when elitism > 0
    assert elite_count(0.0, 100) == 0
    assert global_count(0.1, 150) == 15
    assert global_count(0.0, 150) == 0


def test_order_by_fitness_ties_to_lower_index() -> None:
    f = np.array([1.0, 3.0, 2.0, 3.0])
    assert order_by_fitness(f).tolist() == [1, 3, 2, 0]
    assert order_by_fitness(f, np.array([0, 2, 3])).tolist() == [3, 2, 0]


@pytest.mark.parametrize("seed", range(5))
def test_total_is_population_size_and_elites_first(seed: int) -> None:
    rng = np.random.default_rng(seed)
    n = 50
    genomes, tracker = population(n, seed)
    fitness = rng.uniform(0.1, 5.0, n)
    labels = rng.integers(0, 6, n)
    cfg = config(n, elitism=0.06, global_fraction=0.1)
    out = reproduce(genomes, fitness, labels, cfg, tracker, rng)
    assert len(out.genomes) == n
    best3 = np.argsort(-fitness)[:3].tolist()
    assert list(out.elites) == best3
    for k, i in enumerate(best3):
        assert out.genomes[k] is genomes[i]
    assert out.n_global == 5
    assert sum(out.niche_targets.values()) == n - 3 - 5
    assert out.niche_targets == niche_sizes(fitness, labels, n - 3 - 5)


def test_niche_children_come_from_their_niche_and_shrinkage_drops_the_worst() -> None:
    n = 20
    genomes, tracker = population(n)
    # niche 0: 12 weak members; niche 1: 8 strong members -> niche 0 must shrink
    labels = np.array([0] * 12 + [1] * 8)
    fitness = np.concatenate([np.linspace(1.0, 2.0, 12), np.linspace(5.0, 6.0, 8)])
    cfg = config(n, elitism=0.0, global_fraction=0.0)
    out = reproduce(genomes, fitness, labels, cfg, tracker, np.random.default_rng(1))
    t0, t1 = out.niche_targets[0], out.niche_targets[1]
    assert t0 + t1 == n
    assert t0 < 12  # shrinks
    children = [parent_of(c, genomes) for c in out.genomes]
    # niches bred in id order: first t0 children from niche 0, then t1 from niche 1
    first, second = children[:t0], children[t0:]
    assert all(labels[p] == 0 for p in first)
    assert all(labels[p] == 1 for p in second)
    # the pool of niche 0 is its t0 best members: the worst 12 - t0 never breed
    pool0 = set(np.argsort(-fitness[:12])[:t0].tolist())
    assert set(first) <= pool0


def test_small_strong_niche_grows() -> None:
    n = 20
    genomes, tracker = population(n)
    labels = np.array([0] * 18 + [1] * 2)
    fitness = np.array([1.0] * 18 + [10.0] * 2)
    cfg = config(n, elitism=0.0, global_fraction=0.0)
    out = reproduce(genomes, fitness, labels, cfg, tracker, np.random.default_rng(2))
    assert out.niche_targets[1] > 2
    children = [parent_of(c, genomes) for c in out.genomes]
    assert sum(labels[p] == 1 for p in children) == out.niche_targets[1]


def test_zero_target_niche_goes_extinct() -> None:
    n = 10
    genomes, tracker = population(n)
    labels = np.array([0] * 9 + [1])
    fitness = np.array([10.0] * 9 + [0.01])
    cfg = config(n, elitism=0.0, global_fraction=0.0)
    out = reproduce(genomes, fitness, labels, cfg, tracker, np.random.default_rng(3))
    assert out.niche_targets[1] == 0
    assert all(parent_of(c, genomes) != 9 for c in out.genomes)


def test_global_offspring_come_from_champions() -> None:
    n = 30
    genomes, tracker = population(n)
    rng = np.random.default_rng(4)
    labels = np.repeat(np.arange(5), 6)
    fitness = rng.uniform(1.0, 2.0, n)
    cfg = config(n, elitism=0.0, global_fraction=0.2)
    out = reproduce(genomes, fitness, labels, cfg, tracker, rng)
    champions = {int(np.flatnonzero(labels == s)[np.argmax(fitness[labels == s])]) for s in
                 range(5)}
    tail = [parent_of(c, genomes) for c in out.genomes[-out.n_global:]]
    assert out.n_global == 6
    assert set(tail) <= champions


def test_same_generator_state_same_offspring() -> None:
    n = 40
    genomes, tracker = population(n)
    labels = np.repeat(np.arange(4), 10)
    fitness = np.random.default_rng(5).uniform(0.5, 3.0, n)
    cfg = EvolutionConfig(population_size=n, mutation=MutationConfig(node_rate=0.3, edge_rate=0.3))
    t1 = InnovationTracker.from_state(tracker.to_state())
    t2 = InnovationTracker.from_state(tracker.to_state())
    a = reproduce(genomes, fitness, labels, cfg, t1, np.random.default_rng(9))
    b = reproduce(genomes, fitness, labels, cfg, t2, np.random.default_rng(9))
    c = reproduce(genomes, fitness, labels, cfg, tracker, np.random.default_rng(10))
    assert a == b
    assert t1.to_state() == t2.to_state()
    assert a.genomes != c.genomes
    # structural mutations happened and every child is a valid network of the right shape
    assert any(len(g.hidden_nodes) > 0 for g in a.genomes)
    assert all((g.n_inputs, g.n_outputs) == (2, 1) for g in a.genomes)


def test_crossover_and_mutation_change_children() -> None:
    n = 20
    genomes, tracker = population(n)
    labels = np.zeros(n, dtype=np.int64)
    fitness = np.linspace(1.0, 2.0, n)
    cfg = dataclasses.replace(config(n, elitism=0.0), mutation=MutationConfig(weight_rate=1.0))
    out = reproduce(genomes, fitness, labels, cfg, tracker, np.random.default_rng(6))
    assert all(g not in genomes for g in out.genomes)


def test_new_generation_clears_split_cache() -> None:
    genomes, tracker = population(10)
    tracker.split(0, taken_nodes=set())
    assert tracker.to_state()["splits"]
    reproduce(
        genomes, np.ones(10), np.zeros(10, dtype=np.int64), config(10), tracker,
        np.random.default_rng(0),
    )
    assert tracker.to_state()["splits"] == []


def test_bad_inputs() -> None:
    genomes, tracker = population(5)
    rng = np.random.default_rng(0)
    cfg = config(5)
    with pytest.raises(ValueError, match="shape"):
        reproduce(genomes, np.ones(4), np.zeros(5, dtype=np.int64), cfg, tracker, rng)
    with pytest.raises(ValueError, match="finite"):
        reproduce(genomes, np.full(5, np.nan), np.zeros(5, dtype=np.int64), cfg, tracker, rng)
    with pytest.raises(ValueError, match="empty"):
        reproduce([], np.ones(0), np.zeros(0, dtype=np.int64), cfg, tracker, rng)
