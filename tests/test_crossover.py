"""Crossover: genes aligned by innovation; matching at random, lone genes from the better
parent (either, at random, on equal rank); the child is a valid, acyclic genome."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from mentor_core.evolution.crossover import crossover
from mentor_core.evolution.genome import (
    Genome,
    InvalidGenomeError,
    genome_from_edges,
    minimal_genome,
    validate_genome,
)
from mentor_core.evolution.innovation import InnovationTracker
from mentor_core.evolution.mutation import MutationConfig, mutate
from mentor_core.evolution.network import FeedForwardNetwork

Edge = tuple[int, int, float] | tuple[int, int, float, bool]

# 2 inputs (0, 1), bias 2, outputs 3, 4; hidden from 5
COMMON: list[Edge] = [(0, 3, 1.0), (1, 3, 1.0), (2, 3, 1.0), (0, 4, 1.0)]
A_ONLY: list[Edge] = [(1, 4, 1.0), (2, 4, 1.0)]
B_ONLY: list[Edge] = [(0, 5, 2.0), (5, 4, 2.0)]


def build(tracker: InnovationTracker, edges: list[Edge], **kw: str) -> Genome:
    """A hand-built genome (2 inputs, 2 outputs) numbered by the run's tracker."""
    g = genome_from_edges(2, 2, edges, **kw)
    conns = [
        dataclasses.replace(c, innovation=tracker.connection(c.in_node, c.out_node))
        for c in g.connections
    ]
    g = g.with_connections(conns)
    validate_genome(g)
    return g


def parents() -> tuple[Genome, Genome]:
    tracker = InnovationTracker(10)
    a = build(tracker, COMMON + A_ONLY)
    b = build(tracker, [(i, o, 2.0) for i, o, *_ in COMMON] + B_ONLY, hidden_activation="relu")
    return a, b


def genes(g: Genome) -> set[tuple[int, int, int]]:
    return {(c.innovation, c.in_node, c.out_node) for c in g.connections}


def test_matching_genes_come_from_either_parent_at_random() -> None:
    a, b = parents()
    matching = genes(a) & genes(b)
    assert len(matching) == 4
    from_a = 0
    n_children = 200
    for seed in range(n_children):
        child = crossover(a, b, True, np.random.default_rng(seed))
        weights = {c.innovation: c.weight for c in child.connections}
        for innovation, _, _ in matching:
            assert weights[innovation] in (1.0, 2.0)  # a copy, not a blend
            from_a += weights[innovation] == 1.0
    assert 0.43 < from_a / (4 * n_children) < 0.57  # 800 fair coins


@pytest.mark.parametrize("a_better", [True, False])
def test_lone_genes_come_from_the_better_parent_only(a_better: bool) -> None:
    a, b = parents()
    better, worse = (a, b) if a_better else (b, a)
    for seed in range(30):
        child = crossover(a, b, a_better, np.random.default_rng(seed))
        validate_genome(child)
        assert genes(child) == genes(better)
        assert child.node_ids == better.node_ids
        assert child.hidden_activation == better.hidden_activation
        lone = genes(better) - genes(worse)
        kept = {c for c in child.connections if (c.innovation, c.in_node, c.out_node) in lone}
        assert kept == {c for c in better.connections if c.innovation in {x[0] for x in lone}}


def test_lone_genes_of_both_parents_at_equal_rank() -> None:
    a, b = parents()
    lone = genes(a) ^ genes(b)
    seen = dict.fromkeys(sorted(lone), 0)
    n_children = 200
    for seed in range(n_children):
        child = crossover(a, b, None, np.random.default_rng(seed))
        validate_genome(child)
        assert genes(a) & genes(b) <= genes(child) <= genes(a) | genes(b)
        for gene in genes(child) & lone:
            seen[gene] += 1
        hidden = {n.id for n in child.hidden_nodes}
        used = {x for c in child.connections for x in (c.in_node, c.out_node)}
        assert hidden <= used  # no hidden node is carried without a gene that needs it
    for gene, count in seen.items():
        assert 0.38 < count / n_children < 0.62, gene  # each lone gene: a fair coin


def test_disabled_matching_gene_is_disabled_with_probability_three_quarters() -> None:
    tracker = InnovationTracker(10)
    a = build(tracker, [(0, 3, 1.0, False), (1, 3, 1.0), (0, 4, 1.0)])
    b = build(tracker, [(0, 3, 2.0), (1, 3, 2.0), (0, 4, 2.0)])
    disabled = 0
    n_children = 400
    for seed in range(n_children):
        child = crossover(a, b, None, np.random.default_rng(seed))
        by_pair = {(c.in_node, c.out_node): c for c in child.connections}
        disabled += not by_pair[(0, 3)].enabled
        assert by_pair[(1, 3)].enabled and by_pair[(0, 4)].enabled
    assert 0.68 < disabled / n_children < 0.82


def test_child_is_acyclic_when_parents_order_hidden_nodes_oppositely() -> None:
    tracker = InnovationTracker(10)
    # a: 0 -> 5 -> 6 -> 3, b: 0 -> 6 -> 5 -> 3; both 5 -> 6 and 6 -> 5 would be a cycle
    a = build(tracker, [(0, 5, 1.0), (5, 6, 1.0), (6, 3, 1.0), (2, 4, 1.0)])
    b = build(tracker, [(0, 6, 1.0), (6, 5, 1.0), (5, 3, 1.0), (2, 4, 1.0)])
    pair_inn = {(c.in_node, c.out_node): c.innovation for c in (*a.connections, *b.connections)}
    assert pair_inn[(5, 6)] < pair_inn[(6, 5)]
    forward = backward = 0
    n_children = 200
    for seed in range(n_children):
        child = crossover(a, b, None, np.random.default_rng(seed))
        validate_genome(child)  # raises on a cycle
        FeedForwardNetwork.from_genome(child).activate(np.zeros((2, 2)))
        inns = {c.innovation for c in child.connections}
        forward += pair_inn[(5, 6)] in inns
        backward += pair_inn[(6, 5)] in inns
    # 5 -> 6 (earlier innovation) is kept w.p. 1/2; 6 -> 5 only when 5 -> 6 was not: 1/4
    assert 0.4 < forward / n_children < 0.6
    assert 0.16 < backward / n_children < 0.34


def test_child_of_evolved_parents_is_valid_and_reproducible() -> None:
    tracker = InnovationTracker(3 + 1 + 2)
    rng = np.random.default_rng(0)
    pop = [minimal_genome(3, 2, tracker, rng) for _ in range(6)]
    cfg = MutationConfig(node_rate=0.2, edge_rate=0.1)
    for _ in range(4):
        pop = [mutate(g, cfg, tracker, rng) for g in pop]
        tracker.new_generation()
    for k in range(len(pop) - 1):
        for a_better in (True, False, None):
            child = crossover(pop[k], pop[k + 1], a_better, np.random.default_rng(k))
            validate_genome(child)
            assert child == crossover(pop[k], pop[k + 1], a_better, np.random.default_rng(k))


def test_parents_of_different_shapes_are_refused() -> None:
    a = genome_from_edges(2, 2, [(0, 3, 1.0)])
    b = genome_from_edges(3, 2, [(0, 4, 1.0)])
    with pytest.raises(InvalidGenomeError, match="shape"):
        crossover(a, b, True, np.random.default_rng(0))
