"""Range readings as proximities (``RobotProfile.proximity_scale``, not in the paper): the
network reads ``exp(-r / lambda)`` for each reading ``r``, the config and the genome's metadata
carry ``lambda``, and the planner on the robot decides as the trainer's episodes did."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from mentor_core.benchmark.control import readings
from mentor_core.errors import ConfigError
from mentor_core.evolution.genome import genome_from_edges
from mentor_core.runtime.planner import GenomePlanner, planner_profile
from mentor_core.sim.observation import network_inputs, range_inputs, ranges_from_inputs
from mentor_core.sim.planner_settings import with_planner
from mentor_core.sim.robots import get_profile
from mentor_core.training.config import TrainerConfig
from mentor_core.training.trainer import make_problem, train

UGV = get_profile("ugv")  # 8 sensors of 4 m
NEAR = with_planner(UGV, proximity_scale=1.0)


def test_a_reading_becomes_its_proximity() -> None:
    r = np.array([[0.0, 0.5, 1.0, 2.0, 3.0, 4.0, 9.0, math.inf]])
    np.testing.assert_array_equal(range_inputs(r, UGV), np.minimum(r, 4.0))  # the paper's
    expected = np.exp(-np.minimum(r, 4.0))
    np.testing.assert_allclose(range_inputs(r, NEAR), expected, rtol=0, atol=1e-15)
    # 1 at contact, 1/e at the scale, the same small value for the range and nothing seen
    assert range_inputs(r, NEAR)[0, 0] == 1.0
    assert range_inputs(r, NEAR)[0, 2] == pytest.approx(1.0 / math.e)
    assert range_inputs(r, NEAR)[0, 5] == range_inputs(r, NEAR)[0, 7] == math.exp(-4.0)
    # a tree 3 m away moves an input a twentieth of what one at 0.5 m does
    assert range_inputs(r, NEAR)[0, 4] < range_inputs(r, NEAR)[0, 1] / 10
    with pytest.raises(ValueError, match="NaN"):
        range_inputs([[math.nan] * 8], NEAR)


def test_the_inputs_carry_the_proximities_and_give_the_readings_back() -> None:
    r = np.array([[0.3, 1.0, 2.5, 4.0, math.inf, 0.0, 3.9, 1.7]])
    pose, goal = np.array([[1.0, 2.0, 0.3]]), np.array([[5.0, 6.0]])
    plain = network_inputs(r, pose, goal, UGV)
    near = network_inputs(r, pose, goal, NEAR)
    np.testing.assert_array_equal(near[:, 8:], plain[:, 8:])  # the goal inputs as before
    np.testing.assert_array_equal(near[:, :8], range_inputs(r, NEAR))
    # a baseline's rule reads the readings the network saw, in m, either way
    np.testing.assert_allclose(readings(near, NEAR), np.minimum(r, 4.0), atol=1e-12)
    np.testing.assert_array_equal(ranges_from_inputs(plain, UGV), np.minimum(r, 4.0))


def test_the_scale_goes_from_the_config_into_the_metadata_and_back(tmp_path: Path) -> None:
    config = TrainerConfig.from_dict({"robot": "ugv", "generations": 2, "stage1_generations": 1,
                                      "n_scenarios": 2, "proximity_scale": 1.0,
                                      "evolution": {"population_size": 6}})  # fmt: skip
    assert TrainerConfig.from_dict(config.to_dict()) == config
    assert make_problem(config).profile.proximity_scale == 1.0
    train(config, tmp_path, seed=0)
    metadata = json.loads((tmp_path / "best_genome.json").read_text())["metadata"]
    assert metadata["proximity_scale"] == 1.0
    assert planner_profile(UGV, metadata).proximity_scale == 1.0
    # a genome saved without it, as every genome before it existed: readings in m
    del metadata["proximity_scale"]
    assert planner_profile(UGV, metadata).proximity_scale is None
    with pytest.raises(ConfigError, match="proximity_scale"):
        planner_profile(UGV, {**metadata, "proximity_scale": -1.0}, "g.json")
    for bad in (0, -0.5, "far"):
        with pytest.raises(ConfigError, match="proximity_scale"):
            TrainerConfig.from_dict({"robot": "ugv", "proximity_scale": bad})


def test_the_planner_on_the_robot_decides_as_the_trainer_did() -> None:
    config = TrainerConfig.from_dict({"robot": "ugv", "n_scenarios": 3, "proximity_scale": 1.0,
                                      "input_encoding": "egocentric"})  # fmt: skip
    problem = make_problem(config)
    rng = np.random.default_rng(3)
    n_in = problem.n_inputs
    edges = [(i, n_in + 1 + o, float(rng.normal(0.0, 3.0))) for i in range(n_in) for o in range(2)]
    genome = genome_from_edges(n_in, 2, edges)
    batch = problem.simulate([genome])
    k = problem.profile.n_sensors
    planner = GenomePlanner(genome, problem.profile)
    for s, sc in enumerate(problem.scenarios):
        planner.reset()
        rows, poses = batch.experience[s], batch.trajectories[s]
        decided = [planner.decide(rows[t, :k], poses[t], sc.goal) for t in range(len(rows))]
        np.testing.assert_array_equal(decided, rows[:, k : k + 2])  # bit for bit
