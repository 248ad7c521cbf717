"""Batched population phenotype: numba kernel == numpy fallback == per-genome
``FeedForwardNetwork.activate``, bit for bit, whatever the batch; and the trainer's episodes
with the batched policy equal those with one network call per genome."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from test_operator_properties import RunSpec, grow, run_specs

from mentor_core.controller.episodes import run_episodes
from mentor_core.evolution import batch_network
from mentor_core.evolution.batch_network import Backend, BatchNetwork
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
from mentor_core.evolution.network import ACTIVATION_NAMES, FeedForwardNetwork
from mentor_core.sim.robots import get_profile
from mentor_core.sim.scenarios import training_scenarios
from mentor_core.training.problem import NavigationProblem

BACKENDS: tuple[Backend, ...] = ("numba", "numpy")
needs_numba = pytest.mark.skipif(not batch_network.HAVE_NUMBA, reason="numba not importable")


def with_mixed_activations(g: Genome, rng: np.random.Generator) -> Genome:
    """``g`` with every hidden and output node given a random activation."""
    nodes = [
        n if n.kind in ("input", "bias")
        else NodeGene(n.id, n.kind, str(rng.choice(ACTIVATION_NAMES)))
        for n in g.nodes
    ]
    return g.with_connections(g.connections, nodes)


def population(
    seed: int, n: int = 12, n_inputs: int = 5, n_outputs: int = 2, rounds: int = 6
) -> list[Genome]:
    """Genomes of one run grown by mutation (hidden nodes, disabled genes, skip edges, varied
    depth), with mixed activations; one stays minimal (no hidden node)."""
    rng = np.random.default_rng(seed)
    tracker = InnovationTracker(n_inputs + 1 + n_outputs)
    cfg = MutationConfig(node_rate=0.2, edge_rate=0.1, weight_max=8.0)
    genomes = []
    for k in range(n):
        g = minimal_genome(n_inputs, n_outputs, tracker, rng)
        for _ in range(0 if k == 0 else 1 + k % rounds):
            g = mutate(g, cfg, tracker, rng)
        genomes.append(with_mixed_activations(g, rng))
    tracker.new_generation()
    assert any(not c.enabled for g in genomes for c in g.connections)
    return genomes


def per_genome(genomes: list[Genome], x: np.ndarray, owners: np.ndarray) -> np.ndarray:
    """Reference: each row through its own genome's FeedForwardNetwork, one row at a time."""
    nets = [FeedForwardNetwork.from_genome(g) for g in genomes]
    return np.stack([nets[int(o)].activate(row) for row, o in zip(x, owners, strict=True)])


def inputs_for(rng: np.random.Generator, m: int, n_inputs: int) -> np.ndarray:
    """Ordinary, saturating and exactly-zero inputs."""
    x = rng.normal(0.0, 2.0, size=(m, n_inputs))
    x[::5] *= 40.0
    x[::7] = 0.0
    return x


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_batched_equals_per_genome_activate_bit_for_bit(backend: Backend, seed: int) -> None:
    genomes = population(seed)
    rng = np.random.default_rng(50 + seed)
    owners = rng.integers(0, len(genomes), 300)
    x = inputs_for(rng, 300, genomes[0].n_inputs)
    out = BatchNetwork.from_genomes(genomes).activate(x, owners, backend=backend)
    assert out.shape == (300, genomes[0].n_outputs) and out.dtype == np.float64
    np.testing.assert_array_equal(out, per_genome(genomes, x, owners))


@needs_numba
@pytest.mark.parametrize("seed", [3, 4])
def test_numba_equals_numpy_fallback(seed: int) -> None:
    genomes = population(seed, n=20, rounds=8)
    net = BatchNetwork.from_genomes(genomes)
    rng = np.random.default_rng(seed)
    owners = np.repeat(np.arange(len(genomes)), 25)
    x = inputs_for(rng, owners.size, genomes[0].n_inputs)
    a = net.activate(x, owners, backend="numba")
    np.testing.assert_array_equal(a, net.activate(x, owners, backend="numpy"))
    np.testing.assert_array_equal(a, net.activate(x, owners))  # auto picks numba


@pytest.mark.parametrize("backend", BACKENDS)
def test_a_robot_gets_the_same_bits_whatever_shares_its_batch(backend: Backend) -> None:
    """Subsets, permutations, single rows, repeated rows: each row's outputs never change."""
    genomes = population(5, n=15)
    net = BatchNetwork.from_genomes(genomes)
    rng = np.random.default_rng(9)
    owners = rng.integers(0, len(genomes), 200)
    x = inputs_for(rng, 200, genomes[0].n_inputs)
    full = net.activate(x, owners, backend=backend)
    for size in (1, 2, 3, 8, 31, 117):
        pick = rng.choice(200, size=size, replace=size > 100)
        part = net.activate(x[pick], owners[pick], backend=backend)
        np.testing.assert_array_equal(part, full[pick])
    # a program of a subset of the genomes (as a pool worker compiles) agrees too
    keep = [3, 7, 11]
    rows = np.flatnonzero(np.isin(owners, keep))
    sub = BatchNetwork.from_genomes([genomes[k] for k in keep])
    local = np.searchsorted(keep, owners[rows])
    out = sub.activate(x[rows], local, backend=backend)
    np.testing.assert_array_equal(out, full[rows])


def test_the_program_has_the_genomes_levels() -> None:
    """Depths differ between genomes; each genome's nodes are grouped by level."""
    deep = genome_from_edges(
        2, 1, [(0, 4, 1.0), (4, 5, 1.0), (5, 6, 1.0), (6, 3, 1.0), (1, 3, 0.5)]
    )
    flat = genome_from_edges(2, 1, [(0, 3, 1.0), (2, 3, -1.0)])
    net = BatchNetwork.from_genomes([deep, flat])
    assert net.n_levels == 4
    np.testing.assert_array_equal(net.n_rows, [3 + 4, 3 + 1])
    np.testing.assert_array_equal(net.level_ptr, [[0, 1, 2, 3, 4], [4, 5, 5, 5, 5]])
    np.testing.assert_array_equal(net.output_rows, [[6], [3]])
    x = np.array([[0.3, -1.2], [2.0, 0.5]])
    for owners in ([0, 1], [1, 0], [0, 0], [1, 1]):
        own = np.array(owners)
        np.testing.assert_array_equal(
            net.activate(x, own), per_genome([deep, flat], x, own)
        )


@pytest.mark.parametrize("backend", BACKENDS)
def test_disabled_genes_are_ignored(backend: Backend) -> None:
    edges: list[tuple[int, int, float] | tuple[int, int, float, bool]] = [
        (0, 4, 1.5), (4, 3, -2.0), (1, 3, 0.7), (2, 3, 0.1), (1, 5, 0.9), (5, 3, 0.4),
    ]
    plain = genome_from_edges(2, 1, edges, hidden_activation="tanh")
    noisy = genome_from_edges(
        2, 1, [*edges, (0, 3, 100.0, False), (1, 4, -50.0, False), (5, 4, 9.0, False)],
        hidden_activation="tanh",
    )
    # and a whole disabled branch: a hidden node reachable only over disabled genes
    dead_branch = genome_from_edges(
        2, 1, [*edges, (0, 6, 3.0, False), (6, 3, 7.0, False)], hidden_activation="tanh"
    )
    x = np.random.default_rng(0).normal(size=(40, 2))
    owners = np.arange(40) % 3
    out = BatchNetwork.from_genomes([plain, noisy, dead_branch]).activate(
        x, owners, backend=backend
    )
    alone = BatchNetwork.from_genomes([plain]).activate(
        x, np.zeros(40, dtype=int), backend=backend
    )
    np.testing.assert_array_equal(out, alone)


@pytest.mark.parametrize("backend", BACKENDS)
def test_summation_order_is_sequential_without_fused_multiply_add(backend: Backend) -> None:
    """Three terms 1, 1e16, -1e16 summed in gene order give 0 (any other order: 1), and
    round(w v) + s differs from fma(w, v, s) on the second pair (2**-60 with an FMA)."""
    cancel = genome_from_edges(3, 1, [(0, 4, 1.0), (1, 4, 1.0), (2, 4, 1.0)],
                               output_activation="identity")
    x = np.array([[1.0, 1e16, -1e16]])
    fma = genome_from_edges(3, 1, [(0, 4, -1.0), (1, 4, 1.0 + 2.0**-30)],
                            output_activation="identity")
    y = np.array([[1.0 + 2.0**-29, 1.0 + 2.0**-30, 0.0]])
    net = BatchNetwork.from_genomes([cancel, fma])
    out = net.activate(np.vstack([x, y]), np.array([0, 1]), backend=backend)
    assert out[0, 0] == 0.0 and out[1, 0] == 0.0
    assert FeedForwardNetwork.from_genome(cancel).activate(x)[0, 0] == 0.0
    assert FeedForwardNetwork.from_genome(fma).activate(y)[0, 0] == 0.0


@pytest.mark.parametrize("backend", BACKENDS)
def test_every_activation_at_its_edges(backend: Backend) -> None:
    """Each activation on values around 0 (signed zeros, tiny, huge): the network's bits."""
    sums = np.array([0.0, -0.0, 1e-300, -1e-300, 5e-324, 1e-9, -1e-9, 0.1, -0.1, 3.0, -3.0,
                     40.0, -40.0, 200.0, -200.0, 1e6, -1e6, 1e300, -1e300])
    genomes = [genome_from_edges(1, 1, [(0, 2, 1.0)], output_activation=name)
               for name in ACTIVATION_NAMES]
    owners = np.repeat(np.arange(len(genomes)), sums.size)
    x = np.tile(sums, len(genomes))[:, np.newaxis]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        out = BatchNetwork.from_genomes(genomes).activate(x, owners, backend=backend)
    expected = per_genome(genomes, x, owners)
    np.testing.assert_array_equal(out, expected)
    assert np.array_equal(np.signbit(out), np.signbit(expected))


@pytest.mark.parametrize("backend", BACKENDS)
def test_no_inputs_and_outputs_without_edges(backend: Backend) -> None:
    """Zero inputs (bias only); an output without incoming edges gives f(0)."""
    g = genome_from_edges(0, 2, [(0, 1, 0.75)], output_activation="sigmoid")
    owners = np.zeros(3, dtype=int)
    out = BatchNetwork.from_genomes([g]).activate(np.zeros((3, 0)), owners, backend=backend)
    assert out.shape == (3, 2)
    np.testing.assert_array_equal(out, per_genome([g], np.zeros((3, 0)), owners))
    assert (out[:, 1] == 0.5).all()


@settings(max_examples=40, deadline=None)
@given(spec=run_specs, seed=st.integers(0, 2**32 - 1))
def test_grown_populations_batched_equals_per_genome(spec: RunSpec, seed: int) -> None:
    """Populations grown by crossover and mutation (as in the operator property tests)."""
    pop, _ = grow(spec)
    rng = np.random.default_rng(seed)
    pop = [with_mixed_activations(g, rng) for g in pop]
    owners = rng.integers(0, len(pop), 23)
    x = inputs_for(rng, 23, pop[0].n_inputs)
    net = BatchNetwork.from_genomes(pop)
    expected = per_genome(pop, x, owners)
    for backend in BACKENDS if batch_network.HAVE_NUMBA else ("numpy",):
        np.testing.assert_array_equal(net.activate(x, owners, backend=backend), expected)


def test_bad_arguments_are_refused() -> None:
    genomes = population(0, n=3)
    net = BatchNetwork.from_genomes(genomes)
    x = np.zeros((4, 5))
    with pytest.raises(ValueError, match="at least one genome"):
        BatchNetwork.from_genomes([])
    other = genome_from_edges(4, 2, [(0, 5, 1.0)])
    with pytest.raises(ValueError, match="same inputs and outputs"):
        BatchNetwork.from_genomes([genomes[0], other])
    with pytest.raises(ValueError, match="shape"):
        net.activate(np.zeros((4, 6)), np.zeros(4))
    with pytest.raises(ValueError, match="shape"):
        net.activate(x, np.zeros(3))
    with pytest.raises(ValueError, match="owners"):
        net.activate(x, np.array([0, 1, 2, 3]))
    with pytest.raises(ValueError, match="owners"):
        net.activate(x, np.array([0, -1, 0, 0]))
    with pytest.raises(ValueError, match="backend"):
        net.activate(x, np.zeros(4), backend="cuda")
    assert net.activate(np.zeros((0, 5)), np.zeros(0)).shape == (0, 2)


def test_invalid_genomes_are_refused_like_the_network() -> None:
    base = genome_from_edges(2, 1, [(0, 4, 1.0), (4, 5, 1.0), (5, 3, 1.0)])
    cyclic = base.with_connections((*base.connections, ConnectionGene(9, 5, 4, 1.0)))
    with pytest.raises(InvalidGenomeError, match="cycle"):
        BatchNetwork.from_genomes([base, cyclic])
    odd = base.with_connections(
        base.connections, [*base.nodes[:-1], NodeGene(5, "hidden", "softsign")]
    )
    with pytest.raises(InvalidGenomeError, match="softsign"):
        BatchNetwork.from_genomes([odd])


def test_simulate_equals_one_network_call_per_genome() -> None:
    """NavigationProblem.simulate (batched policy) reproduces, bit for bit, the episodes of the
    former policy: each genome's robots through that genome's own FeedForwardNetwork."""
    profile = get_profile("swarm")
    scenarios = training_scenarios(profile, 0, 4)
    rng = np.random.default_rng(3)
    tracker = InnovationTracker(profile.n_inputs + 3)
    cfg = MutationConfig(node_rate=0.3, edge_rate=0.1)
    genomes = []
    for k in range(6):
        g = minimal_genome(profile.n_inputs, 2, tracker, rng)
        for _ in range(k):
            g = mutate(g, cfg, tracker, rng)
        genomes.append(g)
    genomes[1] = with_mixed_activations(genomes[1], rng)
    n_scen = len(scenarios)
    nets = [FeedForwardNetwork.from_genome(g) for g in genomes]

    def policy(inputs: np.ndarray, robots: np.ndarray) -> np.ndarray:
        owners = robots // n_scen
        out = np.empty((len(robots), 2))
        for g in np.unique(owners):
            rows = owners == g
            out[rows] = nets[int(g)].activate(inputs[rows])
        return out

    expected = run_episodes(list(scenarios) * len(genomes), profile, policy)
    got = NavigationProblem(profile, scenarios).simulate(genomes)
    assert int(got.steps.sum()) > len(genomes) * n_scen  # more than one decision each
    np.testing.assert_array_equal(got.trajectories, expected.trajectories)
    np.testing.assert_array_equal(got.steps, expected.steps)
    for a, b in zip(got.experience, expected.experience, strict=True):
        np.testing.assert_array_equal(a, b)
    with pytest.raises(ValueError, match="at least one genome"):
        NavigationProblem(profile, scenarios).simulate([])
