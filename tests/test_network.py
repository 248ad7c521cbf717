"""Feed-forward phenotype: batch evaluation against a naive per-sample, per-node reference."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from mentor_core.evolution.genome import (
    ConnectionGene,
    Genome,
    InvalidGenomeError,
    NodeGene,
    genome_from_edges,
    minimal_genome,
)
from mentor_core.evolution.innovation import InnovationTracker
from mentor_core.evolution.mutation import MutationConfig, mutate
from mentor_core.evolution.network import FeedForwardNetwork, weighted_sum


def _naive_activation(name: str, x: float) -> float:
    if name == "sigmoid":
        return 1.0 / (1.0 + math.exp(-4.9 * x)) if x > -100.0 else 0.0
    if name == "tanh":
        return math.tanh(x)
    if name == "relu":
        return max(x, 0.0)
    assert name == "identity"
    return x


def naive_outputs(genome: Genome, sample: np.ndarray) -> list[float]:
    """Reference: recursive, memoised evaluation of one sample, one node at a time."""
    kinds = {n.id: n for n in genome.nodes}
    incoming: dict[int, list[tuple[int, float]]] = {}
    for c in genome.connections:
        if c.enabled:
            incoming.setdefault(c.out_node, []).append((c.in_node, c.weight))
    memo: dict[int, float] = {i: float(sample[i]) for i in genome.input_ids}
    memo[genome.bias_id] = 1.0

    def value(node: int) -> float:
        if node not in memo:
            total = 0.0
            for src, weight in incoming.get(node, []):
                total += weight * value(src)
            memo[node] = _naive_activation(kinds[node].activation, total)
        return memo[node]

    return [value(o) for o in genome.output_ids]


def evolved_genome(seed: int, n_inputs: int = 6, n_outputs: int = 3) -> Genome:
    """A genome with hidden nodes, disabled genes and skip edges, grown by mutation."""
    rng = np.random.default_rng(seed)
    tracker = InnovationTracker(n_inputs + 1 + n_outputs)
    g = minimal_genome(n_inputs, n_outputs, tracker, rng, hidden_activation="tanh")
    cfg = MutationConfig(node_rate=0.15, edge_rate=0.05)
    for _ in range(4):
        g = mutate(g, cfg, tracker, rng)
        tracker.new_generation()
    assert g.hidden_nodes and any(not c.enabled for c in g.connections)
    return g


def test_linear_network_matches_hand_computation() -> None:
    """y = 2 x0 - 3 x1 + 0.5 (bias) with identity output."""
    g = genome_from_edges(
        2, 1, [(0, 3, 2.0), (1, 3, -3.0), (2, 3, 0.5)], output_activation="identity"
    )
    net = FeedForwardNetwork.from_genome(g)
    x = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [2.0, -1.0]])
    expected = np.array([[0.5], [2.5], [-2.5], [7.5]])
    np.testing.assert_allclose(net.activate(x), expected, rtol=0, atol=1e-15)


def test_hidden_node_and_neat_sigmoid_by_hand() -> None:
    """out = sigmoid(0.5 * relu(2 x0 - x1) + 0.25), NEAT sigmoid 1 / (1 + exp(-4.9 z))."""
    g = genome_from_edges(
        2,
        1,
        [(0, 4, 2.0), (1, 4, -1.0), (4, 3, 0.5), (2, 3, 0.25)],
        hidden_activation="relu",
        output_activation="sigmoid",
    )
    out = FeedForwardNetwork.from_genome(g).activate(np.array([[1.0, 1.0], [0.0, 3.0]]))
    z0 = 0.5 * 1.0 + 0.25  # relu(2 - 1) = 1
    z1 = 0.25  # relu(-3) = 0
    expected = [[1.0 / (1.0 + math.exp(-4.9 * z0))], [1.0 / (1.0 + math.exp(-4.9 * z1))]]
    np.testing.assert_allclose(out, expected, rtol=1e-14)


def test_disabled_connections_are_ignored() -> None:
    edges: list[tuple[int, int, float] | tuple[int, int, float, bool]] = [
        (0, 4, 1.5), (4, 3, -2.0), (1, 3, 0.7), (2, 3, 0.1),
    ]
    plain = genome_from_edges(2, 1, edges, hidden_activation="tanh")
    with_disabled = genome_from_edges(
        2, 1, [*edges, (0, 3, 100.0, False), (1, 4, -50.0, False)], hidden_activation="tanh"
    )
    x = np.random.default_rng(0).normal(size=(20, 2))
    a = FeedForwardNetwork.from_genome(plain).activate(x)
    b = FeedForwardNetwork.from_genome(with_disabled).activate(x)
    np.testing.assert_array_equal(a, b)


def test_output_without_incoming_edges_is_activation_of_zero() -> None:
    g = genome_from_edges(2, 2, [(0, 3, 1.0)], output_activation="sigmoid")
    out = FeedForwardNetwork.from_genome(g).activate(np.array([[3.0, 4.0]]))
    assert out[0, 1] == 0.5


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_batch_matches_naive_reference_on_evolved_genome(seed: int) -> None:
    g = evolved_genome(seed)
    x = np.random.default_rng(100 + seed).normal(scale=2.0, size=(64, g.n_inputs))
    out = FeedForwardNetwork.from_genome(g).activate(x)
    assert out.shape == (64, g.n_outputs)
    expected = np.array([naive_outputs(g, row) for row in x])
    np.testing.assert_allclose(out, expected, rtol=0, atol=1e-12)


def test_batch_equals_single_rows() -> None:
    """Batch of N rows gives the N single-row results, bit for bit.

    Each weighted sum has a fixed order (gene order, one rounded product and one rounded sum
    per term, never BLAS), so a row's outputs do not depend on the batch around it.
    """
    g = evolved_genome(3)
    net = FeedForwardNetwork.from_genome(g)
    x = np.random.default_rng(7).normal(size=(33, g.n_inputs))
    batch = net.activate(x)
    singles = np.stack([net.activate(row) for row in x])
    assert singles.shape == batch.shape
    np.testing.assert_array_equal(batch, singles)
    for n in (1, 2, 5, 17):
        np.testing.assert_array_equal(net.activate(x[:n]), batch[:n])
    np.testing.assert_array_equal(net.activate(x[::-1]), batch[::-1])


def test_weighted_sum_is_sequential_in_gene_order_without_fma() -> None:
    """Terms 1, 1e16, 1e16 * -1 in gene order sum to 0 (another order: 1); round(w v) + s,
    not fma(w, v, s) (which would give 2**-60 on the second genome)."""
    cancel = genome_from_edges(
        3, 1, [(0, 4, 1.0), (1, 4, 1.0), (2, 4, -1.0)], output_activation="identity"
    )
    x = np.array([[1.0, 1e16, 1e16]] * 3)
    np.testing.assert_array_equal(FeedForwardNetwork.from_genome(cancel).activate(x), 0.0)
    fma = genome_from_edges(2, 1, [(0, 3, -1.0), (1, 3, 1.0 + 2.0**-30)],
                            output_activation="identity")
    y = np.array([[1.0 + 2.0**-29, 1.0 + 2.0**-30]])
    assert FeedForwardNetwork.from_genome(fma).activate(y)[0, 0] == 0.0
    sums = weighted_sum(np.array([2.0, -3.0]), np.array([[1.0, 0.5], [4.0, -1.0]]))
    np.testing.assert_array_equal(sums, [2.0 - 12.0, 1.0 + 3.0])
    np.testing.assert_array_equal(weighted_sum(np.zeros(0), np.zeros((0, 3))), np.zeros(3))


def test_one_dimensional_input_gives_one_dimensional_output() -> None:
    g = evolved_genome(4)
    net = FeedForwardNetwork.from_genome(g)
    x = np.linspace(-1.0, 1.0, g.n_inputs)
    out = net.activate(x)
    assert out.shape == (g.n_outputs,)
    np.testing.assert_allclose(out, naive_outputs(g, x), rtol=0, atol=1e-12)


def test_inputs_of_other_dtypes_and_input_untouched() -> None:
    g = evolved_genome(5)
    net = FeedForwardNetwork.from_genome(g)
    x32 = np.arange(2 * g.n_inputs, dtype=np.float32).reshape(2, g.n_inputs) / 10
    before = x32.copy()
    out = net.activate(x32)
    assert out.dtype == np.float64
    np.testing.assert_array_equal(x32, before)
    np.testing.assert_allclose(out, net.activate(x32.astype(np.float64)), rtol=0, atol=0)
    zeros = np.zeros((1, g.n_inputs))
    np.testing.assert_array_equal(net.activate([[0] * g.n_inputs]), net.activate(zeros))


def test_extreme_inputs_stay_finite_without_warnings() -> None:
    g = genome_from_edges(1, 1, [(0, 2, 1.0)], output_activation="sigmoid")
    net = FeedForwardNetwork.from_genome(g)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        out = net.activate(np.array([[-1e6], [1e6], [0.0]]))
    np.testing.assert_array_equal(out, [[0.0], [1.0], [0.5]])


@pytest.mark.parametrize("shape", [(3, 5), (3, 7), (5,), (2, 3, 6)])
def test_wrong_input_shape_is_refused(shape: tuple[int, ...]) -> None:
    net = FeedForwardNetwork.from_genome(evolved_genome(0))  # 6 inputs
    with pytest.raises(ValueError, match="shape"):
        net.activate(np.zeros(shape))


def test_cycle_is_refused_with_clear_error() -> None:
    base = genome_from_edges(2, 1, [(0, 4, 1.0), (4, 5, 1.0), (5, 3, 1.0)])
    cyclic = base.with_connections((*base.connections, ConnectionGene(9, 5, 4, 1.0)))
    with pytest.raises(InvalidGenomeError, match="cycle"):
        FeedForwardNetwork.from_genome(cyclic)


def test_unknown_activation_and_missing_node_are_refused() -> None:
    base = genome_from_edges(2, 1, [(0, 4, 1.0), (4, 3, 1.0)])
    odd = base.with_connections(
        base.connections, [*base.nodes[:-1], NodeGene(4, "hidden", "softsign")]
    )
    with pytest.raises(InvalidGenomeError, match="softsign"):
        FeedForwardNetwork.from_genome(odd)
    dangling = base.with_connections((*base.connections, ConnectionGene(9, 7, 3, 1.0)))
    with pytest.raises(InvalidGenomeError, match="missing node"):
        FeedForwardNetwork.from_genome(dangling)
