"""Recurrent connection genes: a one-step delay, the same in every evaluator and on the robot."""

from __future__ import annotations

import itertools
import json
import math
from pathlib import Path

import numpy as np
import pytest

from mentor_core.errors import FileFormatError
from mentor_core.evolution.batch_network import BatchNetwork
from mentor_core.evolution.crossover import crossover
from mentor_core.evolution.genome import (
    ConnectionGene,
    Genome,
    InvalidGenomeError,
    genome_from_edges,
    minimal_genome,
    validate_genome,
)
from mentor_core.evolution.genome_codec import genome_from_dict, genome_to_dict
from mentor_core.evolution.innovation import InnovationTracker
from mentor_core.evolution.mutation import MutationConfig, mutate, mutated_genomes
from mentor_core.evolution.network import FeedForwardNetwork
from mentor_core.runtime.planner import GenomePlanner
from mentor_core.sim.planner_settings import with_planner
from mentor_core.sim.robots import get_profile
from mentor_core.training.config import TrainerConfig
from mentor_core.training.evaluators import InProcessEvaluator, PoolEvaluator
from mentor_core.training.run_files import load_population
from mentor_core.training.trainer import make_problem, train

RECURRENT = MutationConfig(node_rate=0.2, edge_rate=0.3, recurrent_rate=0.3)


def delay_line() -> Genome:
    """One input, one identity output that reads the input of the decision before (x 2)."""
    return genome_from_edges(1, 1, [], output_activation="identity", recurrent=[(0, 2, 2.0)])


def running_sum() -> Genome:
    """o(t) = x(t) + o(t - 1): a self-loop on the identity output."""
    return genome_from_edges(
        1, 1, [(0, 2, 1.0)], output_activation="identity", recurrent=[(2, 2, 1.0)]
    )


def random_recurrent(n: int, n_inputs: int = 3, seed: int = 0) -> list[Genome]:
    genomes = mutated_genomes(n, n_inputs, RECURRENT, 5, np.random.default_rng(seed))
    assert sum(g.is_recurrent for g in genomes) > n // 2
    return genomes


def test_a_recurrent_edge_reads_the_value_of_the_decision_before() -> None:
    network = FeedForwardNetwork.from_genome(delay_line())
    assert network.recurrent
    memory = network.new_memory(2)  # two robots, each its own past
    seen = [network.activate(np.array([[x], [-x]]), memory)[:, 0] for x in (1.0, 3.0, 5.0)]
    np.testing.assert_array_equal(seen, [[0.0, 0.0], [2.0, -2.0], [6.0, -6.0]])


def test_a_self_loop_integrates_and_a_blank_memory_restarts_it() -> None:
    network = FeedForwardNetwork.from_genome(running_sum())
    memory = network.new_memory()
    sums = [float(network.activate(np.array([x]), memory)[0]) for x in (1.0, 2.0, 4.0)]
    assert sums == [1.0, 3.0, 7.0]
    assert float(network.activate(np.array([1.0]), network.new_memory())[0]) == 1.0


def test_a_feed_forward_network_needs_no_memory_and_a_recurrent_one_says_so() -> None:
    plain = FeedForwardNetwork.from_genome(genome_from_edges(1, 1, [(0, 2, 1.0)]))
    assert not plain.recurrent and plain.memory_width == 0
    network = FeedForwardNetwork.from_genome(running_sum())
    with pytest.raises(ValueError, match="needs a memory"):
        network.activate(np.array([[1.0]]))
    with pytest.raises(ValueError, match="needs a memory"):
        network.activate(np.array([[1.0], [2.0]]), network.new_memory(1))
    batch = BatchNetwork.from_genomes([running_sum()])
    with pytest.raises(ValueError, match="need memory"):
        batch.activate(np.array([[1.0]]), np.array([0]))
    with pytest.raises(ValueError, match="slots must lie"):
        batch.activate(np.array([[1.0]]), np.array([0]), memory=batch.new_memory(1), slots=[1])


@pytest.mark.parametrize("backend", ["numba", "numpy"])
def test_the_batch_program_and_the_planner_network_agree_bit_for_bit_over_decisions(
    backend: str,
) -> None:
    genomes = [*random_recurrent(16), genome_from_edges(3, 2, [(0, 4, 0.5)])]  # one plain
    batch = BatchNetwork.from_genomes(genomes)
    networks = [FeedForwardNetwork.from_genome(g) for g in genomes]
    per_genome = 3
    owners = np.repeat(np.arange(len(genomes)), per_genome)
    memory = batch.new_memory(owners.size)
    own = [n.new_memory(per_genome) for n in networks]
    rng = np.random.default_rng(1)
    for _ in range(6):
        x = rng.normal(size=(owners.size, 3))
        active = rng.permutation(owners.size)[: owners.size - 5]  # some robots have stopped
        out = batch.activate(x[active], owners[active], memory=memory, slots=active,
                             backend=backend)  # type: ignore[arg-type]  # fmt: skip
        for k, robot in enumerate(active):
            g, j = owners[robot], robot % per_genome
            mine = own[g][j : j + 1]
            expected = networks[g].activate(x[robot : robot + 1], mine)
            own[g][j : j + 1] = mine
            np.testing.assert_array_equal(out[k], expected[0])


def test_recurrent_genes_are_checked_and_kept_in_files() -> None:
    genome = running_sum()
    doc = genome_to_dict(genome)
    assert doc["connections"][1]["recurrent"] is True
    assert "recurrent" not in doc["connections"][0]  # forward genes are written as before
    assert genome_from_dict(json.loads(json.dumps(doc))) == genome
    doc["connections"][1]["recurrent"] = "yes"
    with pytest.raises(FileFormatError, match=r"connections\[1\].recurrent"):
        genome_from_dict(doc, "g.json")
    # a forward and a recurrent edge of one pair are two genes; a cycle needs forward edges
    both = genome_from_edges(1, 1, [(0, 2, 1.0)], recurrent=[(0, 2, 1.0)])
    assert [c.recurrent for c in both.connections] == [False, True]
    loop = genome_from_edges(1, 1, [(0, 3, 1.0), (3, 2, 1.0)], recurrent=[(2, 3, 0.5)])
    validate_genome(loop)
    with pytest.raises(InvalidGenomeError, match="cycle"):
        genome_from_edges(1, 1, [(0, 3, 1.0), (3, 2, 1.0), (2, 3, 0.5)])
    with pytest.raises(InvalidGenomeError, match="starts at the bias"):
        genome_from_edges(1, 1, [], recurrent=[(1, 2, 1.0)])
    with pytest.raises(InvalidGenomeError, match="two recurrent connections"):
        genome_from_edges(1, 1, [], recurrent=[(0, 2, 1.0), (0, 2, 2.0)])


def test_the_mutation_grows_recurrent_genes_only_when_asked() -> None:
    tracker = InnovationTracker(next_node_id=6)
    rng = np.random.default_rng(0)
    plain = MutationConfig(node_rate=0.3, edge_rate=0.5)
    g = minimal_genome(3, 2, tracker, rng)
    for _ in range(10):
        g = mutate(g, plain, tracker, rng)
    assert not any(c.recurrent for c in g.connections)
    every = MutationConfig(node_rate=0.0, edge_rate=0.0, recurrent_rate=1.0)
    a, b = (mutate(minimal_genome(3, 2, tracker, rng), every, tracker, rng) for _ in range(2))
    for child in (a, b):
        delayed = [c for c in child.connections if c.recurrent]
        assert sorted(c.out_node for c in delayed) == [4, 5]  # one per output
        assert all(c.in_node != 3 for c in delayed)  # never from the bias
    forward = {c.innovation for c in a.connections if not c.recurrent}
    for c in (c for c in a.connections + b.connections if c.recurrent):
        assert c.innovation == tracker.connection(c.in_node, c.out_node, recurrent=True)
        assert c.innovation not in forward


def test_add_node_keeps_the_delay_of_a_recurrent_edge() -> None:
    tracker = InnovationTracker(next_node_id=3)
    genome = genome_from_edges(1, 1, [], output_activation="identity", recurrent=[(0, 2, 2.0)])
    tracker.connection(0, 2, recurrent=True)
    split = mutate(genome, MutationConfig(weight_rate=0.0, node_rate=1.0, edge_rate=0.0),
                   tracker, np.random.default_rng(0))  # fmt: skip
    new = {(c.in_node, c.out_node): c for c in split.connections if c.enabled}
    assert new[(0, 3)].recurrent and not new[(3, 2)].recurrent
    validate_genome(split)


def test_crossover_keeps_recurrent_genes_that_point_backwards() -> None:
    genomes = random_recurrent(12, seed=4)
    rng = np.random.default_rng(2)
    kept = 0
    for a, b in itertools.pairwise(genomes):
        child = crossover(a, b, True, rng)
        validate_genome(child)
        delayed = {c.innovation for c in a.connections if c.recurrent}
        kept += len(delayed & {c.innovation for c in child.connections})
        assert delayed <= {c.innovation for c in child.connections}  # a is better: all its genes
    assert kept > 0


def test_the_innovation_record_keeps_recurrent_numbers_apart() -> None:
    tracker = InnovationTracker(next_node_id=6)
    forward = tracker.connection(0, 4)
    delayed = tracker.connection(0, 4, recurrent=True)
    assert forward != delayed and tracker.connection(0, 4, recurrent=True) == delayed
    state = json.loads(json.dumps(tracker.to_state()))
    again = InnovationTracker.from_state(state)
    assert again.connection(0, 4, recurrent=True) == delayed
    assert again.next_innovation == tracker.next_innovation
    assert "recurrent" not in InnovationTracker(next_node_id=6).to_state()
    state["recurrent"][0][2] = forward
    with pytest.raises(FileFormatError, match="repeat"):
        InnovationTracker.from_state(state, "checkpoint.json")


def test_the_planner_on_the_robot_decides_as_the_trainer_simulated() -> None:
    config = TrainerConfig.from_dict({"robot": "swarm", "n_scenarios": 4})
    problem = make_problem(config)
    genomes = random_recurrent(6, problem.n_inputs, seed=5)
    batch = problem.simulate(genomes)  # the batch program, every robot with its memory
    k, n_scen = problem.profile.n_sensors, len(problem.scenarios)
    differs = False
    for g, genome in enumerate(genomes):
        planner = GenomePlanner(genome, problem.profile)
        for s, sc in enumerate(problem.scenarios):
            planner.reset()
            rows, poses = batch.experience[g * n_scen + s], batch.trajectories[g * n_scen + s]
            decided = [planner.decide(rows[t, :k], poses[t], sc.goal) for t in range(len(rows))]
            np.testing.assert_array_equal(decided, rows[:, k : k + 2])  # bit for bit
            if genome.is_recurrent and len(rows) > 1:
                planner.reset()
                planner.decide(rows[0, :k], poses[0], sc.goal)
                planner.reset()  # forgets the first decision: the second is a first one
                blank = planner.decide(rows[1, :k], poses[1], sc.goal)
                differs |= blank != tuple(rows[1, k : k + 2])
    assert differs  # the memory matters for some genome


def test_a_planner_that_failed_to_decide_keeps_its_memory() -> None:
    profile = with_planner(get_profile("swarm"))
    genome = genome_from_edges(profile.n_inputs, 2, [], output_activation="identity",
                               recurrent=[(0, profile.n_inputs + 1, 1.0)])  # fmt: skip
    planner = GenomePlanner(genome, profile)
    planner.decide([0.4, 0.6, 0.6], (1.0, 1.0, 0.0), (3.0, 3.0))
    with pytest.raises(ValueError, match="NaN"):
        planner.decide([math.nan, 0.6, 0.6], (1.0, 1.0, 0.0), (3.0, 3.0))
    after = planner.decide([0.1, 0.6, 0.6], (1.0, 1.0, 0.0), (3.0, 3.0))
    planner.reset()
    planner.decide([0.4, 0.6, 0.6], (1.0, 1.0, 0.0), (3.0, 3.0))
    assert planner.decide([0.1, 0.6, 0.6], (1.0, 1.0, 0.0), (3.0, 3.0)) == after


def test_pool_evaluation_of_recurrent_genomes_is_bit_identical_to_in_process() -> None:
    problem = make_problem(TrainerConfig.from_dict({"robot": "swarm", "n_scenarios": 3}))
    genomes = random_recurrent(8, problem.n_inputs, seed=6)
    serial = InProcessEvaluator(problem).evaluate(genomes)
    with PoolEvaluator(problem, workers=2) as pool:
        parallel = pool.evaluate(genomes)
    assert np.array_equal(serial.objectives, parallel.objectives)
    assert np.array_equal(serial.success_rate, parallel.success_rate)


def test_a_recurrent_run_resumes_to_the_same_files(tmp_path: Path) -> None:
    data = {"robot": "swarm", "framework": "dual", "generations": 4, "stage1_generations": 2,
            "n_scenarios": 3,
            "evolution": {"population_size": 8, "mutation": {"recurrent_rate": 0.5}}}  # fmt: skip
    config = TrainerConfig.from_dict(data)
    train(config, tmp_path / "whole", seed=2)
    train(config, tmp_path / "broken", seed=2, stop_after=2)
    train(config, tmp_path / "broken", seed=2, resume=True)
    whole, broken = tmp_path / "whole", tmp_path / "broken"
    for name in ("best_genome.json", "population.json", "pareto.json"):
        assert (whole / name).read_bytes() == (broken / name).read_bytes()
    members = load_population(tmp_path / "whole" / "population.json")
    assert any(genome.is_recurrent for genome, _ in members)


def test_a_gene_with_a_non_bool_recurrent_flag_is_refused() -> None:
    genome = running_sum()
    bad = ConnectionGene(9, 0, 2, 1.0, True, 1)  # type: ignore[arg-type]
    with pytest.raises(InvalidGenomeError, match="recurrent must be a bool"):
        validate_genome(genome.with_connections([*genome.connections, bad]))


def test_the_topology_figure_draws_recurrent_genes_without_moving_columns() -> None:
    from mentor_core.report.figures import node_layers, topology

    forward, delayed = [(0, 3, 1.0), (3, 2, 1.0)], [(2, 3, 0.5), (3, 3, 1.0)]
    genome = genome_from_edges(1, 1, forward, recurrent=delayed)
    assert node_layers(genome) == {0: 0, 1: 0, 2: 2, 3: 1}
    fig = topology(genome)
    labels = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert "recurrent" in labels
