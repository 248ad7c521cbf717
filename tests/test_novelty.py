"""Novelty search (mentor_core.objectives.novelty) and its place in training."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial import cKDTree

from mentor_core.evolution.config import EvolutionConfig
from mentor_core.evolution.mutation import mutated_genomes
from mentor_core.objectives.novelty import most_novel, sparseness
from mentor_core.training.config import TrainerConfig
from mentor_core.training.evaluators import InProcessEvaluator, PoolEvaluator
from mentor_core.training.trainer import _Run, make_problem, train


def test_sparseness_by_hand() -> None:
    # four points on a line, no archive, k = 2: the mean distance to the two nearest others
    behaviours = np.array([[0.0], [1.0], [3.0], [7.0]])
    assert sparseness(behaviours, np.zeros((0, 1)), 2).tolist() == [2.0, 1.5, 2.5, 5.0]
    # an archived point counts as a neighbour; a copy of a behaviour is at distance 0
    archive = np.array([[0.0], [6.0]])
    assert sparseness(behaviours, archive, 1).tolist() == [0.0, 1.0, 2.0, 1.0]


def test_sparseness_matches_a_kd_tree_query() -> None:
    rng = np.random.default_rng(3)
    behaviours, archive = rng.random((40, 6)), rng.random((25, 6))
    k = 15
    tree = cKDTree(np.concatenate([behaviours, archive]))
    distances, _ = tree.query(behaviours, k=k + 1)  # the first is the point itself
    assert np.allclose(sparseness(behaviours, archive, k), distances[:, 1:].mean(axis=1))


def test_sparseness_with_fewer_others_than_k_averages_those_there_are() -> None:
    behaviours = np.array([[0.0, 0.0], [3.0, 4.0]])
    assert sparseness(behaviours, np.zeros((0, 2)), 15).tolist() == [5.0, 5.0]
    assert sparseness(behaviours[:1], np.zeros((0, 2)), 15).tolist() == [0.0]


@pytest.mark.parametrize(
    ("behaviours", "archive", "k", "message"),
    [
        (np.zeros(3), np.zeros((0, 1)), 1, "behaviours: expected"),
        (np.zeros((3, 2)), np.zeros((1, 3)), 1, r"archive: expected a \(n, 2\)"),
        (np.full((3, 2), np.nan), np.zeros((0, 2)), 1, "finite"),
        (np.zeros((3, 2)), np.zeros((0, 2)), 0, "k: expected a positive int"),
    ],
)
def test_sparseness_refuses_bad_input(behaviours, archive, k, message) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(ValueError, match=message):
        sparseness(behaviours, archive, k)


def test_most_novel_takes_the_highest_first_and_the_lower_index_on_ties() -> None:
    assert most_novel([0.5, 2.0, 1.0, 2.0], 3).tolist() == [1, 3, 2]
    assert most_novel([1.0, 2.0], 0).tolist() == []
    assert most_novel([1.0, 2.0], 5).tolist() == [1, 0]
    with pytest.raises(ValueError, match="count"):
        most_novel([1.0], -1)


def _novelty_config(**changes: object) -> TrainerConfig:
    data = {"robot": "swarm", "framework": "dual", "generations": 4, "stage1_generations": 2,
            "n_scenarios": 3, "novelty_neighbours": 3, "novelty_archive_growth": 2,
            "evolution": {"population_size": 8}, **changes}  # fmt: skip
    return TrainerConfig.from_dict(data)


def test_the_behaviour_is_each_scenarios_final_position_on_every_backend() -> None:
    config = _novelty_config()
    problem = make_problem(config)
    genomes = mutated_genomes(
        5, problem.n_inputs, EvolutionConfig.paper("swarm").mutation, 3, np.random.default_rng(1)
    )
    serial = InProcessEvaluator(problem).evaluate(genomes)
    batch = problem.simulate(genomes)
    final = batch.trajectories[np.arange(15), batch.steps, :2] / problem.scenarios[0].world.size
    assert serial.behaviour.shape == (5, 6)
    assert np.array_equal(serial.behaviour, final.reshape(5, 6))
    with PoolEvaluator(problem, workers=2) as pool:
        assert np.array_equal(pool.evaluate(genomes).behaviour, serial.behaviour)


def test_the_run_ranks_novelty_against_the_population_and_a_growing_archive() -> None:
    config = _novelty_config()
    problem = make_problem(config)
    run = _Run(config, 1, problem)
    genomes = run.evolution.ask()
    evaluation = InProcessEvaluator(problem).evaluate(genomes)
    ranked = run.ranked_objectives(evaluation, "multi", genomes)
    expected = sparseness(evaluation.behaviour, np.zeros((0, 6)), 3)
    assert np.array_equal(ranked[:, :2], evaluation.objectives)
    assert np.array_equal(ranked[:, 2], expected)
    assert np.array_equal(run.archive, evaluation.behaviour[most_novel(expected, 2)])
    ranked = run.ranked_objectives(evaluation, "multi", genomes)  # the archive holds two
    assert np.array_equal(ranked[:, 2], sparseness(evaluation.behaviour, run.archive[:2], 3))
    assert len(run.archive) == 4
    # where F is ranked alone, novelty is neither computed nor archived
    ranked = run.ranked_objectives(evaluation, "single", genomes)
    assert np.isnan(ranked[:, 2]).all() and len(run.archive) == 4


def test_a_novelty_run_resumes_to_the_same_files_and_differs_from_one_without(
    tmp_path: Path,
) -> None:
    config = _novelty_config()
    train(config, tmp_path / "whole", seed=2)
    train(config, tmp_path / "broken", seed=2, stop_after=1)
    state = json.loads((tmp_path / "broken" / "checkpoint.json").read_text())
    assert np.asarray(state["novelty_archive"]).shape == (2, 6)
    whole_state = json.loads((tmp_path / "whole" / "checkpoint.json").read_text())
    assert np.asarray(whole_state["novelty_archive"]).shape == (4, 6)  # stage 1's 2 generations
    train(config, tmp_path / "broken", seed=2, resume=True)
    for name in ("best_genome.json", "population.json", "pareto.json", "checkpoint.json"):
        whole = (tmp_path / "whole" / name).read_text()
        broken = (tmp_path / "broken" / name).read_text()
        if name == "checkpoint.json":  # but for the wall-clock seconds of the history
            whole, broken = (json.loads(t) for t in (whole, broken))
            whole.pop("history"), broken.pop("history")
        assert whole == broken, name
    plain = _novelty_config(novelty_neighbours=None)
    train(plain, tmp_path / "plain", seed=2)
    assert (tmp_path / "plain" / "pareto.json").read_bytes() != (
        tmp_path / "whole" / "pareto.json"
    ).read_bytes()
    plain_state = json.loads((tmp_path / "plain" / "checkpoint.json").read_text())
    assert "novelty_archive" not in plain_state
