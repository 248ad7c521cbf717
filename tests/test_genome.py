"""Genome encoding: id layout, minimal genome, cycle test, validation."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from mentor_core.evolution.genome import (
    ConnectionGene,
    Genome,
    InvalidGenomeError,
    NodeGene,
    creates_cycle,
    genome_from_edges,
    minimal_genome,
    topological_order,
    validate_genome,
)
from mentor_core.evolution.innovation import InnovationTracker

# 2 inputs (0, 1), bias 2, outputs 3, 4; hidden from 5
N_IN, N_OUT = 2, 2


def _minimal(seed: int = 0, tracker: InnovationTracker | None = None) -> Genome:
    tracker = tracker or InnovationTracker(N_IN + 1 + N_OUT)
    return minimal_genome(N_IN, N_OUT, tracker, np.random.default_rng(seed))


def test_minimal_genome_layout() -> None:
    g = _minimal()
    assert [(n.id, n.kind) for n in g.nodes] == [
        (0, "input"), (1, "input"), (2, "bias"), (3, "output"), (4, "output"),
    ]
    assert {(c.in_node, c.out_node) for c in g.connections} == {
        (i, o) for i in (0, 1, 2) for o in (3, 4)
    }
    assert all(c.enabled for c in g.connections)
    assert [c.innovation for c in g.connections] == list(range(6))
    assert g.bias_id == 2 and list(g.output_ids) == [3, 4] and g.first_hidden_id == 5
    assert g.hidden_nodes == ()
    validate_genome(g)


def test_minimal_genomes_share_innovations_and_differ_in_weights() -> None:
    tracker = InnovationTracker(5)
    a, b = _minimal(1, tracker), _minimal(2, tracker)
    assert [(c.innovation, c.in_node, c.out_node) for c in a.connections] == [
        (c.innovation, c.in_node, c.out_node) for c in b.connections
    ]
    assert [c.weight for c in a.connections] != [c.weight for c in b.connections]
    assert _minimal(1) == a  # same seed, same genome


def test_minimal_weights_follow_weight_sigma() -> None:
    g = minimal_genome(40, 5, InnovationTracker(46), np.random.default_rng(3), weight_sigma=2.0)
    weights = np.array([c.weight for c in g.connections])
    assert weights.size == 41 * 5
    assert abs(weights.std() - 2.0) < 0.25
    assert abs(weights.mean()) < 0.3


def test_minimal_genome_rejects_tracker_that_would_reuse_ids() -> None:
    with pytest.raises(InvalidGenomeError, match="next_node_id"):
        minimal_genome(2, 2, InnovationTracker(3), np.random.default_rng(0))


def test_creates_cycle_counts_disabled_genes() -> None:
    conns = [ConnectionGene(0, 0, 5, 1.0), ConnectionGene(1, 5, 6, 1.0, enabled=False)]
    assert creates_cycle(conns, 6, 5)  # through the disabled gene
    assert creates_cycle(conns, 5, 5)  # self loop
    assert not creates_cycle(conns, 0, 6)
    assert not creates_cycle(conns, 6, 3)


def test_topological_order_and_cycle() -> None:
    assert topological_order([1, 2, 3], [(3, 1), (1, 2)]) == [3, 1, 2]
    with pytest.raises(InvalidGenomeError, match="cycle"):
        topological_order([1, 2], [(1, 2), (2, 1)])


def test_genome_from_edges_infers_hidden_nodes() -> None:
    g = genome_from_edges(2, 2, [(0, 5, 1.0), (5, 3, -1.0, False)], hidden_activation="tanh")
    assert [n.id for n in g.hidden_nodes] == [5]
    assert g.hidden_nodes[0].activation == "tanh"
    assert [c.enabled for c in g.connections] == [True, False]
    assert len(g.enabled_connections) == 1


def test_with_connections_resorts() -> None:
    g = _minimal()
    shuffled = tuple(reversed(g.connections))
    again = g.with_connections(shuffled, reversed(g.nodes))
    assert again == g


def test_genome_is_frozen() -> None:
    g = _minimal()
    with pytest.raises(dataclasses.FrozenInstanceError):
        g.n_inputs = 3  # type: ignore[misc]


def _base() -> Genome:
    return genome_from_edges(2, 2, [(0, 3, 0.5), (1, 5, 1.0), (5, 4, 2.0)])


def _replace_node(g: Genome, node_id: int, node: NodeGene) -> Genome:
    return dataclasses.replace(
        g, nodes=tuple(node if n.id == node_id else n for n in g.nodes)
    )


BAD_GENOMES = {
    "duplicate node ids": lambda g: dataclasses.replace(g, nodes=(*g.nodes, g.nodes[-1])),
    "not sorted by id": lambda g: dataclasses.replace(g, nodes=tuple(reversed(g.nodes))),
    "must be of kind 'bias'": lambda g: _replace_node(g, 2, NodeGene(2, "input", "identity")),
    "must be of kind 'output'": lambda g: dataclasses.replace(g, nodes=g.nodes[:3] + g.nodes[4:]),
    "unknown kind": lambda g: _replace_node(g, 5, NodeGene(5, "weird", "sigmoid")),  # type: ignore[arg-type]
    "outside the id layout": lambda g: _replace_node(g, 5, NodeGene(5, "output", "sigmoid")),
    "must use 'identity'": lambda g: _replace_node(g, 0, NodeGene(0, "input", "sigmoid")),
    "missing node 7": lambda g: g.with_connections((*g.connections, ConnectionGene(9, 0, 7, 1.0))),
    "ends in input node": lambda g: g.with_connections(
        (*g.connections, ConnectionGene(9, 3, 0, 1.0))
    ),
    "two connections 0 -> 3": lambda g: g.with_connections(
        (*g.connections, ConnectionGene(9, 0, 3, 1.0))
    ),
    "duplicate connection innovation": lambda g: dataclasses.replace(
        g, connections=(*g.connections, ConnectionGene(2, 0, 4, 1.0))
    ),
    "has weight nan": lambda g: g.with_connections(
        (*g.connections, ConnectionGene(9, 0, 4, float("nan")))
    ),
    "cycle": lambda g: g.with_connections(
        (*g.connections, ConnectionGene(9, 4, 5, 1.0, enabled=False))
    ),
    "n_outputs": lambda g: dataclasses.replace(g, n_outputs=0),
}


@pytest.mark.parametrize("fault", sorted(BAD_GENOMES))
def test_validate_genome_names_the_fault(fault: str) -> None:
    validate_genome(_base())
    with pytest.raises(InvalidGenomeError) as err:
        validate_genome(BAD_GENOMES[fault](_base()))
    assert fault in str(err.value)
    assert isinstance(err.value, ValueError)
