"""The Bug-like turn commitment (sim/commitment.py) and its trainer config key."""

from __future__ import annotations

import math

import numpy as np
import pytest

from mentor_core.sim.commitment import TurnCommitment
from mentor_core.sim.robots import get_profile, with_planner
from mentor_core.training.config import TrainerConfig
from mentor_core.training.trainer import make_problem

UGV = with_planner(
    get_profile("ugv"), heading_change_max=math.radians(45), step_max=0.5, step_min=0.02,
    clearance_margin=0.2,
)  # fmt: skip


def test_a_blocked_robot_keeps_turning_to_its_previous_side() -> None:
    k = UGV.n_sensors
    wall = np.full((2, k + 3), 0.1)  # everything 0.1 m away: every turn's step is the smallest
    rule = TurnCommitment(UGV, 2)
    robots = np.array([0, 1])
    # the first decision: nothing to keep, both as the network says
    first = rule(np.array([[0.9, 0.5], [0.2, 0.5]]), wall, robots)
    assert first[:, 0].tolist() == [0.9, 0.2]
    # then the network turns the other way: mirrored back to each robot's own side
    again = rule(np.array([[0.3, 0.5], [0.7, 0.5]]), wall, robots)
    assert again[:, 0] == pytest.approx([0.7, 0.3], abs=1e-15)
    assert again[:, 1].tolist() == [0.5, 0.5]  # the step output is the network's


def test_a_free_robot_turns_as_the_network_says() -> None:
    k = UGV.n_sensors
    free = np.full((1, k + 3), UGV.sensor_range)
    rule = TurnCommitment(UGV, 1)
    rule(np.array([[0.9, 0.5]]), free, np.array([0]))
    assert rule(np.array([[0.1, 0.5]]), free, np.array([0]))[0, 0] == 0.1


def test_config_key_turns_it_on_in_training() -> None:
    base = {"robot": "swarm", "n_scenarios": 3, "generations": 2, "stage1_generations": 1}
    assert not make_problem(TrainerConfig.from_dict(base)).turn_commitment
    assert make_problem(TrainerConfig.from_dict({**base, "turn_commitment": True})).turn_commitment
