"""Mutation: per-edge weight and add-node rates, add-edge without cycles or duplicates, and
shared innovation numbers for the same structural mutation within a generation."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from mentor_core.errors import ConfigError
from mentor_core.evolution.genome import (
    Genome,
    genome_from_edges,
    minimal_genome,
    validate_genome,
)
from mentor_core.evolution.innovation import InnovationTracker
from mentor_core.evolution.mutation import MutationConfig, mutate, mutate_weights
from mentor_core.evolution.network import FeedForwardNetwork

WEIGHTS_ONLY = MutationConfig(node_rate=0.0, edge_rate=0.0)
NODES_ONLY = MutationConfig(weight_rate=0.0, node_rate=1.0, edge_rate=0.0)
EDGES_ONLY = MutationConfig(weight_rate=0.0, node_rate=0.0, edge_rate=1.0)


def tracked(
    n_inputs: int, n_outputs: int, edges: list[tuple[int, int, float, bool]]
) -> tuple[Genome, InnovationTracker]:
    """A hand-built genome whose innovation numbers come from a fresh run tracker."""
    g = genome_from_edges(n_inputs, n_outputs, edges)
    first_free = max([n.id for n in g.nodes]) + 1
    tracker = InnovationTracker(first_free)
    conns = [
        dataclasses.replace(c, innovation=tracker.connection(c.in_node, c.out_node))
        for c in g.connections
    ]
    g = g.with_connections(conns)
    validate_genome(g)
    return g, tracker


def pairs(g: Genome) -> list[tuple[int, int]]:
    return [(c.in_node, c.out_node) for c in g.connections]


def test_weight_mutation_hits_each_edge_with_its_probability() -> None:
    tracker = InnovationTracker(50 + 1 + 4)
    rng = np.random.default_rng(11)
    g = minimal_genome(50, 4, tracker, rng)
    cfg = MutationConfig(weight_rate=0.25, node_rate=0.0, edge_rate=0.0)
    changed = 0
    trials = 20
    for _ in range(trials):
        child = mutate(g, cfg, tracker, rng)
        assert pairs(child) == pairs(g)  # no structural change at rates 0
        pairs_of_genes = zip(g.connections, child.connections, strict=True)
        changed += sum(a.weight != b.weight for a, b in pairs_of_genes)
    frac = changed / (trials * len(g.connections))  # 4080 coins, sd ~ 0.007
    assert 0.21 < frac < 0.29


@pytest.mark.parametrize(("rate", "expected"), [(0.0, 0), (1.0, 204)])
def test_weight_rate_extremes(rate: float, expected: int) -> None:
    g = minimal_genome(50, 4, InnovationTracker(55), np.random.default_rng(0))
    cfg = MutationConfig(weight_rate=rate)
    new = mutate_weights(g.connections, cfg, np.random.default_rng(1))
    assert sum(a.weight != b.weight for a, b in zip(g.connections, new, strict=True)) == expected


def test_perturbation_and_replacement_laws() -> None:
    g = minimal_genome(100, 10, InnovationTracker(111), np.random.default_rng(0))
    fives = tuple(dataclasses.replace(c, weight=5.0) for c in g.connections)  # 1010 genes
    perturb = MutationConfig(weight_rate=1.0, weight_replace_rate=0.0, weight_perturb_sigma=0.5,
                             weight_max=100.0)
    delta = np.array([c.weight for c in mutate_weights(fives, perturb, np.random.default_rng(2))])
    delta -= 5.0
    assert abs(delta.mean()) < 0.05 and 0.45 < delta.std() < 0.55
    replace = MutationConfig(weight_rate=1.0, weight_replace_rate=1.0, weight_init_sigma=2.0,
                             weight_max=100.0)
    fresh = np.array([c.weight for c in mutate_weights(fives, replace, np.random.default_rng(3))])
    assert abs(fresh.mean()) < 0.2 and 1.8 < fresh.std() < 2.2  # old weight 5 forgotten


def test_weights_are_clamped_and_disabled_genes_mutate_too() -> None:
    g, _ = tracked(2, 1, [(0, 3, 0.1, True), (1, 3, 0.2, False), (2, 3, 0.3, True)])
    cfg = MutationConfig(weight_rate=1.0, weight_perturb_sigma=100.0, weight_max=0.5)
    new = mutate_weights(g.connections, cfg, np.random.default_rng(4))
    assert all(abs(c.weight) <= 0.5 for c in new)
    assert all(a.weight != b.weight for a, b in zip(g.connections, new, strict=True))
    assert [c.enabled for c in new] == [True, False, True]


def test_add_node_splits_edge_as_documented() -> None:
    g, tracker = tracked(2, 1, [(0, 3, 0.7, True), (1, 3, -1.3, False)])
    g = dataclasses.replace(g, hidden_activation="tanh")
    child = mutate(g, NODES_ONLY, tracker, np.random.default_rng(0))
    validate_genome(child)
    assert [(n.id, n.kind, n.activation) for n in child.hidden_nodes] == [(4, "hidden", "tanh")]
    by_pair = {(c.in_node, c.out_node): c for c in child.connections}
    assert set(by_pair) == {(0, 3), (1, 3), (0, 4), (4, 3)}  # disabled 1->3 is not split
    old = by_pair[(0, 3)]
    assert not old.enabled and old.weight == 0.7 and old.innovation == 0
    assert by_pair[(0, 4)].enabled and by_pair[(0, 4)].weight == 1.0
    assert by_pair[(4, 3)].enabled and by_pair[(4, 3)].weight == 0.7
    assert by_pair[(1, 3)] == g.connections[1]


def test_add_node_with_identity_hidden_keeps_the_function() -> None:
    tracker = InnovationTracker(3 + 1 + 2)
    g = minimal_genome(3, 2, tracker, np.random.default_rng(5), hidden_activation="identity")
    child = mutate(g, NODES_ONLY, tracker, np.random.default_rng(6))
    assert len(child.hidden_nodes) == len(g.connections)  # every enabled edge split
    x = np.random.default_rng(7).normal(size=(10, 3))
    np.testing.assert_allclose(
        FeedForwardNetwork.from_genome(child).activate(x),
        FeedForwardNetwork.from_genome(g).activate(x),
        rtol=1e-12,
    )


def test_node_rate_is_per_edge() -> None:
    tracker = InnovationTracker(40 + 1 + 5)
    rng = np.random.default_rng(8)
    g = minimal_genome(40, 5, tracker, rng)  # 205 enabled edges
    cfg = MutationConfig(weight_rate=0.0, node_rate=0.1, edge_rate=0.0)
    splits = [len(mutate(g, cfg, tracker, rng).hidden_nodes) for _ in range(20)]
    assert 16.0 < np.mean(splits) < 25.0  # expected 20.5


def test_add_edge_gives_each_target_one_acyclic_new_in_edge() -> None:
    # 2 inputs (0, 1), bias 2, output 3, hidden 4: 0 -> 4 -> 3
    g, tracker = tracked(2, 1, [(0, 4, 1.0, True), (4, 3, 1.0, True)])
    seen: set[tuple[int, int]] = set()
    for seed in range(40):
        child = mutate(g, EDGES_ONLY, tracker, np.random.default_rng(seed))
        validate_genome(child)
        new = sorted(set(pairs(child)) - {(0, 4), (4, 3)})
        assert sorted(b for _, b in new) == [3, 4]  # rate 1: exactly one new in-edge per target
        seen.update(new)
    # 3 -> 4 would close 4 -> 3 -> 4; every other missing pair is drawn sometimes
    assert seen == {(0, 3), (1, 3), (2, 3), (1, 4), (2, 4)}


def test_add_edge_never_duplicates_a_disabled_gene_or_closes_a_cycle() -> None:
    # disabled 5 -> 4 blocks 4 -> 5 (crossover could re-enable it) and a second 5 -> 4
    g, tracker = tracked(
        2, 1, [(0, 4, 1.0, True), (4, 3, 1.0, True), (0, 5, 1.0, True), (5, 4, 1.0, False)]
    )
    for seed in range(5):
        child = mutate(g, EDGES_ONLY, tracker, np.random.default_rng(seed))
        validate_genome(child)  # no cycle (disabled genes included), no repeated pair
        assert (4, 5) not in pairs(child) and pairs(child).count((5, 4)) == 1


def test_add_edge_random_graphs_stay_acyclic() -> None:
    tracker = InnovationTracker(4 + 1 + 3)
    rng = np.random.default_rng(9)
    g = minimal_genome(4, 3, tracker, rng)
    cfg = MutationConfig(node_rate=0.2, edge_rate=0.1)
    for _ in range(5):
        g = mutate(g, cfg, tracker, rng)
        tracker.new_generation()
        validate_genome(g)
        assert len(set(pairs(g))) == len(g.connections)
    assert len(g.hidden_nodes) >= 5  # the check above saw real structure


def test_edge_rate_is_per_target_node() -> None:
    # no edges: 30 inputs + bias -> 2 outputs; each output draws a new in-edge w.p. 0.25
    g, tracker = tracked(30, 2, [])
    cfg = MutationConfig(weight_rate=0.0, node_rate=0.0, edge_rate=0.25)
    rng = np.random.default_rng(10)
    added = [len(mutate(g, cfg, tracker, rng).connections) for _ in range(400)]
    assert 0.4 < np.mean(added) < 0.6  # expected 0.5, not ~16 as one coin per node pair


def test_swarm_rates_grow_networks_linearly_not_quadratically() -> None:
    # the paper's Swarm-Robot rates, mutation alone: one coin per node pair reached >14,000
    # connections in four generations; one trial per node stays near the node count
    tracker = InnovationTracker(6 + 1 + 2)
    rng = np.random.default_rng(3)
    g = minimal_genome(6, 2, tracker, rng)
    cfg = MutationConfig(node_rate=0.08, edge_rate=0.5)
    for _ in range(10):
        g = mutate(g, cfg, tracker, rng)
        tracker.new_generation()
    assert len(g.connections) < 1000


def test_same_split_in_one_generation_shares_node_and_innovations() -> None:
    tracker = InnovationTracker(2 + 1 + 1)
    a = minimal_genome(2, 1, tracker, np.random.default_rng(1))
    b = minimal_genome(2, 1, tracker, np.random.default_rng(2))
    ca = mutate(a, NODES_ONLY, tracker, np.random.default_rng(3))
    cb = mutate(b, NODES_ONLY, tracker, np.random.default_rng(4))
    assert [n.id for n in ca.hidden_nodes] == [n.id for n in cb.hidden_nodes] == [4, 5, 6]
    assert [(c.innovation, c.in_node, c.out_node) for c in ca.connections] == [
        (c.innovation, c.in_node, c.out_node) for c in cb.connections
    ]
    tracker.new_generation()
    c = mutate(minimal_genome(2, 1, tracker, np.random.default_rng(5)), NODES_ONLY, tracker,
               np.random.default_rng(6))
    assert [n.id for n in c.hidden_nodes] == [7, 8, 9]  # next generation: fresh nodes
    assert not {x.innovation for x in c.connections} & (
        {x.innovation for x in ca.connections} - {0, 1, 2}
    )


def test_same_new_edge_in_two_genomes_gets_same_innovation() -> None:
    g, tracker = tracked(2, 1, [(0, 4, 1.0, True), (4, 3, 1.0, True)])
    other = g.with_connections([dataclasses.replace(c, weight=-2.0) for c in g.connections])
    a = mutate(g, EDGES_ONLY, tracker, np.random.default_rng(0))
    tracker.new_generation()  # connection numbers are run-wide, not per generation
    b = mutate(other, EDGES_ONLY, tracker, np.random.default_rng(0))  # same picks
    assert {(c.innovation, c.in_node, c.out_node) for c in a.connections} == {
        (c.innovation, c.in_node, c.out_node) for c in b.connections
    }


def test_mutate_is_reproducible_and_leaves_parent_alone() -> None:
    def run() -> tuple[Genome, Genome]:
        tracker = InnovationTracker(3 + 1 + 2)
        rng = np.random.default_rng(12)
        parent = minimal_genome(3, 2, tracker, rng)
        cfg = MutationConfig(node_rate=0.5, edge_rate=0.5)
        return parent, mutate(parent, cfg, tracker, rng)

    (p1, c1), (p2, c2) = run(), run()
    assert c1 == c2 and c1 != p1
    assert p1 == p2 and not p1.hidden_nodes and c1.hidden_nodes


@pytest.mark.parametrize(
    ("key", "value"),
    [("weight_rate", 1.5), ("node_rate", -0.1), ("edge_rate", True), ("weight_max", 0.0),
     ("weight_perturb_sigma", float("inf"))],
)
def test_config_refuses_bad_values(key: str, value: float) -> None:
    with pytest.raises(ConfigError) as err:
        MutationConfig(**{key: value})
    assert err.value.key == key


def test_max_hidden_stops_add_node_and_nothing_else() -> None:
    tracker = InnovationTracker(6 + 1 + 2)
    rng = np.random.default_rng(4)
    g = minimal_genome(6, 2, tracker, rng)
    cfg = MutationConfig(node_rate=0.5, edge_rate=0.5, max_hidden=5)
    for _ in range(8):
        g = mutate(g, cfg, tracker, rng)
        tracker.new_generation()
        validate_genome(g)
    assert len(g.hidden_nodes) == 5  # reached the cap and stayed there
    with pytest.raises(ConfigError, match="max_hidden"):
        MutationConfig(max_hidden=-1)
