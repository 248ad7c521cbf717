"""Rules on a planner's turns, experiment E024 (benchmarks/experiments/): the Bug-like turn
commitment (controller/turn_commitment.py, the stage ``turn_commitment``), turns relative to
the goal (sim/goal_frame.py), their trainer config keys."""

from __future__ import annotations

import math

import numpy as np
import pytest

from mentor_core.controller.turn_commitment import TurnCommitment
from mentor_core.errors import ConfigError
from mentor_core.sim.goal_frame import goal_frame_turns
from mentor_core.sim.planner_settings import with_planner
from mentor_core.sim.robots import get_profile
from mentor_core.training.config import TrainerConfig
from mentor_core.training.trainer import make_problem

UGV = with_planner(
    get_profile("ugv"), heading_change_max=math.radians(45), step_max=0.5, step_min=0.02,
    clearance_margin=0.2,
)  # fmt: skip


def test_a_blocked_robot_keeps_turning_to_its_previous_side() -> None:
    k = UGV.n_sensors
    wall = np.full((2, k + 3), 0.1)  # everything 0.1 m away: every turn's step is the smallest
    rule = TurnCommitment().start(2, UGV, None)
    robots = np.array([0, 1])
    # the first decision: nothing to keep, both as the network says
    first = rule.outputs(robots, np.array([[0.9, 0.5], [0.2, 0.5]]), wall)
    assert first[:, 0].tolist() == [0.9, 0.2]
    # then the network turns the other way: mirrored back to each robot's own side
    again = rule.outputs(robots, np.array([[0.3, 0.5], [0.7, 0.5]]), wall)
    assert again[:, 0] == pytest.approx([0.7, 0.3], abs=1e-15)
    assert again[:, 1].tolist() == [0.5, 0.5]  # the step output is the network's
    # a new episode for robot 0 only: it has nothing to keep, robot 1 still keeps its side
    rule.reset(np.array([0]))
    fresh = rule.outputs(robots, np.array([[0.3, 0.5], [0.7, 0.5]]), wall)
    assert fresh[:, 0] == pytest.approx([0.3, 0.3], abs=1e-15)


def test_a_free_robot_turns_as_the_network_says() -> None:
    k = UGV.n_sensors
    free = np.full((1, k + 3), UGV.sensor_range)
    rule = TurnCommitment().start(1, UGV, None)
    rule.outputs(np.array([0]), np.array([[0.9, 0.5]]), free)
    assert rule.outputs(np.array([0]), np.array([[0.1, 0.5]]), free)[0, 0] == 0.1


def test_config_key_turns_it_on_in_training() -> None:
    base = {"robot": "swarm", "n_scenarios": 3, "generations": 2, "stage1_generations": 1}
    assert make_problem(TrainerConfig.from_dict(base)).stages == ()
    on = make_problem(TrainerConfig.from_dict({**base, "turn_commitment": True}))
    assert on.stages == (TurnCommitment(),)


def _goal_inputs(bearings_deg: list[float]) -> np.ndarray:
    b = np.radians(bearings_deg)
    readings = np.full((len(b), UGV.n_sensors), UGV.sensor_range)
    return np.column_stack([readings, np.cos(b), np.sin(b), np.full(len(b), 0.5)])


def test_goal_frame_turns_name_a_heading_relative_to_the_goal() -> None:
    ugv = with_planner(UGV, input_encoding="egocentric")
    # o_1 = 0.5 heads for the goal (30 deg left: turn 30 deg; 120 deg left: the 45 deg limit);
    # 0.75 is 90 deg left of the goal; past +-180 deg the way round is the short one
    inputs = _goal_inputs([30.0, 120.0, 0.0, 170.0])
    outputs = np.array([[0.5, 0.2], [0.5, 0.2], [0.75, 0.2], [20 / 360 + 0.5, 0.2]])
    turned = goal_frame_turns(outputs, inputs, ugv)
    dtheta = np.degrees(ugv.heading_change_max * (2.0 * turned[:, 0] - 1.0))
    assert dtheta == pytest.approx([30.0, 45.0, 45.0, -45.0], abs=1e-9)
    assert turned[:, 1].tolist() == [0.2] * 4  # the step output is the network's
    with pytest.raises(ValueError, match="egocentric"):
        goal_frame_turns(outputs, inputs, with_planner(UGV, input_encoding="paper"))


def test_config_key_turn_frame_needs_the_egocentric_inputs() -> None:
    base = {"robot": "swarm", "n_scenarios": 3, "generations": 2, "stage1_generations": 1}
    goal = TrainerConfig.from_dict({**base, "turn_frame": "goal"})
    assert make_problem(goal).turn_frame == "goal"
    with pytest.raises(ConfigError, match=r"turn_frame.*egocentric"):
        make_problem(
            TrainerConfig.from_dict({**base, "turn_frame": "goal", "input_encoding": "paper"})
        )
