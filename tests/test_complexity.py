"""Complexity criterion: FLOPs of one forward pass relative to the minimal network."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from mentor_core.evolution.genome import (
    Genome,
    InvalidGenomeError,
    NodeGene,
    genome_from_edges,
    minimal_genome,
)
from mentor_core.evolution.innovation import InnovationTracker
from mentor_core.evolution.mutation import MutationConfig, mutate
from mentor_core.objectives.complexity import flops, flops_ratio, minimal_flops


def minimal(
    n_inputs: int, n_outputs: int, output_activation: str = "sigmoid"
) -> tuple[Genome, InnovationTracker]:
    tracker = InnovationTracker(n_inputs + 1 + n_outputs)
    rng = np.random.default_rng(0)
    g = minimal_genome(n_inputs, n_outputs, tracker, rng, output_activation=output_activation)
    return g, tracker


@pytest.mark.parametrize(
    ("n_inputs", "n_outputs", "activation"),
    [(1, 1, "sigmoid"), (11, 2, "sigmoid"), (4, 3, "tanh"), (2, 2, "identity"), (0, 1, "relu")],
)
def test_minimal_network_ratio_is_one(n_inputs: int, n_outputs: int, activation: str) -> None:
    g, _ = minimal(n_inputs, n_outputs, output_activation=activation)
    assert flops(g) == minimal_flops(g)
    assert flops_ratio(g) == 1.0


def test_paper_ugv_minimal_cost() -> None:
    """11 inputs + bias fully wired to 2 sigmoid outputs: 24 edges x 2 + 2 x 4 = 56 FLOPs."""
    g, _ = minimal(11, 2)
    assert flops(g) == 56


def test_hand_example_matches_cost_model() -> None:
    """Edges 0 -> 4 -> 3, 1 -> 3, bias -> 3 enabled, 0 -> 3 disabled; tanh hidden, sigmoid out.

    flops = 2 x 4 enabled edges + tanh 6 + sigmoid 4 = 18; minimal = 2 x 3 edges + 4 = 10.
    """
    g = genome_from_edges(
        2,
        1,
        [(0, 4, 1.0), (4, 3, 1.0), (1, 3, 1.0), (2, 3, 1.0), (0, 3, 1.0, False)],
        hidden_activation="tanh",
        output_activation="sigmoid",
    )
    assert flops(g) == 18
    assert minimal_flops(g) == 10
    assert flops_ratio(g) == pytest.approx(1.8)


def test_dead_end_hidden_node_is_counted() -> None:
    """The architecture's cost: a node that reaches no output still counts."""
    live = genome_from_edges(1, 1, [(0, 2, 1.0), (1, 2, 1.0)], hidden_activation="relu")
    dead = genome_from_edges(
        1, 1, [(0, 2, 1.0), (1, 2, 1.0), (0, 3, 1.0)], hidden_activation="relu"
    )
    assert flops(dead) == flops(live) + 2 + 1


def test_ratio_grows_with_hidden_nodes_and_edges() -> None:
    g, tracker = minimal(3, 2)
    split = mutate(g, MutationConfig(weight_rate=0.0, node_rate=1.0, edge_rate=0.0), tracker,
                   np.random.default_rng(1))
    # each split: one gene disabled, two enabled (+1 edge), one sigmoid hidden node
    n_splits = len(split.hidden_nodes)
    assert n_splits == len(g.connections)
    assert flops(split) == flops(g) + n_splits * (2 + 4)
    wired = mutate(split, MutationConfig(weight_rate=0.0, node_rate=0.0, edge_rate=1.0), tracker,
                   np.random.default_rng(2))
    added = len(wired.connections) - len(split.connections)
    assert added > 0
    assert flops(wired) == flops(split) + 2 * added
    assert 1.0 == flops_ratio(g) < flops_ratio(split) < flops_ratio(wired)


def test_disabling_an_edge_lowers_cost_and_sparse_genome_is_below_one() -> None:
    g, _ = minimal(3, 2)
    off = g.with_connections(
        [dataclasses.replace(c, enabled=k != 0) for k, c in enumerate(g.connections)]
    )
    assert flops(off) == flops(g) - 2
    assert flops_ratio(off) < 1.0


def test_unknown_activation_has_no_cost() -> None:
    g = genome_from_edges(1, 1, [(0, 3, 1.0), (3, 2, 1.0)])
    odd = g.with_connections(g.connections, [*g.nodes[:-1], NodeGene(3, "hidden", "swish")])
    with pytest.raises(InvalidGenomeError, match="swish"):
        flops(odd)
