"""Property tests of the evolution operators on randomly grown populations: offspring genes
come from the parents, innovation numbers stay consistent, no cycles ever, distance is
symmetric and zero with itself."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from mentor_core.evolution.crossover import crossover
from mentor_core.evolution.genome import Genome, minimal_genome, validate_genome
from mentor_core.evolution.innovation import InnovationTracker
from mentor_core.evolution.mutation import MutationConfig, mutate
from mentor_core.evolution.network import FeedForwardNetwork
from mentor_core.evolution.species import distance

PROPERTY = settings(max_examples=50, deadline=None)
# a cap on genome size that keeps every example fast, whatever rates hypothesis draws
MAX_GENES = 600


@dataclass(frozen=True)
class RunSpec:
    """Everything needed to grow a small population reproducibly."""

    seed: int
    n_inputs: int
    n_outputs: int
    generations: int
    rates: tuple[tuple[float, float], ...]  # (node_rate, edge_rate) per generation
    crossover_rate: float


run_specs = st.builds(
    RunSpec,
    seed=st.integers(0, 2**32 - 1),
    n_inputs=st.integers(0, 4),
    n_outputs=st.integers(1, 3),
    generations=st.integers(0, 4),
    rates=st.lists(
        st.tuples(st.floats(0.0, 0.25), st.floats(0.0, 0.1)), min_size=4, max_size=4
    ).map(tuple),
    crossover_rate=st.floats(0.0, 1.0),
)
a_better_values = st.sampled_from([True, False, None])


def grow(spec: RunSpec, size: int = 5) -> tuple[list[Genome], InnovationTracker]:
    """A population after ``spec.generations`` rounds of crossover and mutation.

    Every genome is validated (acyclic, no repeated pair, ...) after every operator; growth
    stops early once a genome has more than ``MAX_GENES`` genes, to keep the test fast.
    """
    rng = np.random.default_rng(spec.seed)
    tracker = InnovationTracker(spec.n_inputs + 1 + spec.n_outputs)
    pop = [minimal_genome(spec.n_inputs, spec.n_outputs, tracker, rng) for _ in range(size)]
    for gen in range(spec.generations):
        if max(len(g.connections) for g in pop) > MAX_GENES:
            break
        node_rate, edge_rate = spec.rates[gen]
        cfg = MutationConfig(node_rate=node_rate, edge_rate=edge_rate)
        children = []
        for _ in range(size):
            i, j = (int(k) for k in rng.integers(0, size, 2))
            child = pop[i]
            if rng.random() < spec.crossover_rate:
                a_better = [True, False, None][int(rng.integers(0, 3))]
                child = crossover(pop[i], pop[j], a_better, rng)
                validate_genome(child)
            child = mutate(child, cfg, tracker, rng)
            validate_genome(child)
            children.append(child)
        pop = children
        tracker.new_generation()
    return pop, tracker


def gene_keys(g: Genome) -> set[tuple[int, int, int]]:
    return {(c.innovation, c.in_node, c.out_node) for c in g.connections}


@PROPERTY
@given(spec=run_specs, a_better=a_better_values, pick=st.integers(0, 2**16))
def test_offspring_genes_come_from_the_parents(
    spec: RunSpec, a_better: bool | None, pick: int
) -> None:
    pop, _ = grow(spec)
    a, b = pop[pick % len(pop)], pop[(pick // 7) % len(pop)]
    child = crossover(a, b, a_better, np.random.default_rng(pick))
    validate_genome(child)
    genes_a = {(c.innovation, c.in_node, c.out_node): c for c in a.connections}
    genes_b = {(c.innovation, c.in_node, c.out_node): c for c in b.connections}
    for c in child.connections:
        key = (c.innovation, c.in_node, c.out_node)
        sources = [genes[key] for genes in (genes_a, genes_b) if key in genes]
        assert sources  # same innovation with the same endpoints exists in a parent
        assert c.weight in {s.weight for s in sources}  # a copy, not a blend
    assert set(child.nodes) <= set(a.nodes) | set(b.nodes)
    if a_better is not None:
        better, worse = (a, b) if a_better else (b, a)
        assert gene_keys(child) <= gene_keys(better)  # lone genes only from the better one
        assert gene_keys(better) & gene_keys(worse) <= gene_keys(child)  # matching: always


@PROPERTY
@given(spec=run_specs)
def test_innovation_numbers_consistent_across_population(spec: RunSpec) -> None:
    pop, tracker = grow(spec)
    by_pair: dict[tuple[int, int], int] = {}
    by_innovation: dict[int, tuple[int, int]] = {}
    for g in pop:
        for c in g.connections:
            pair = (c.in_node, c.out_node)
            assert by_pair.setdefault(pair, c.innovation) == c.innovation
            assert by_innovation.setdefault(c.innovation, pair) == pair
    before = tracker.next_innovation
    for pair, innovation in by_pair.items():
        assert tracker.connection(*pair) == innovation  # the run's record agrees
    assert tracker.next_innovation == before  # and had every pair already


@PROPERTY
@given(
    spec=run_specs,
    steps=st.lists(st.tuples(st.floats(0.0, 0.3), st.floats(0.0, 0.05)), min_size=1, max_size=4),
)
def test_no_cycles_after_any_sequence_of_mutations(
    spec: RunSpec, steps: list[tuple[float, float]]
) -> None:
    pop, tracker = grow(spec, size=2)
    g = pop[0]
    rng = np.random.default_rng(spec.seed + 1)
    x = rng.normal(size=(3, g.n_inputs))
    for node_rate, edge_rate in steps:
        if len(g.connections) > MAX_GENES:
            break
        g = mutate(g, MutationConfig(node_rate=node_rate, edge_rate=edge_rate), tracker, rng)
        validate_genome(g)  # raises on any cycle, enabled or disabled genes
        pairs = [(c.in_node, c.out_node) for c in g.connections]
        assert len(set(pairs)) == len(pairs)
        out = FeedForwardNetwork.from_genome(g).activate(x)
        assert out.shape == (3, g.n_outputs) and np.isfinite(out).all()


@PROPERTY
@given(
    spec=run_specs,
    pick=st.integers(0, 2**16),
    coefficients=st.tuples(st.floats(0.0, 5.0), st.floats(0.0, 5.0), st.floats(0.0, 5.0)),
)
def test_distance_symmetric_nonnegative_and_zero_with_itself(
    spec: RunSpec, pick: int, coefficients: tuple[float, float, float]
) -> None:
    pop, _ = grow(spec)
    a, b = pop[pick % len(pop)], pop[(pick // 7) % len(pop)]
    d_ab = distance(a, b, *coefficients)
    assert d_ab == distance(b, a, *coefficients)
    assert d_ab >= 0.0 and np.isfinite(d_ab)
    assert distance(a, a, *coefficients) == 0.0
    if gene_keys(a) != gene_keys(b) and min(coefficients[:2]) > 0.0:
        assert d_ab > 0.0  # different structure is never at distance zero
