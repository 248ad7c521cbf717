"""The rotation shim (the stage ``rotation_shim``; trained with: ``rotation_shim_deg``; not in the
paper): a robot turns on the spot onto a new goal before its network drives, the same in the
engine, on the robot and in files."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from mentor_core.controller.deployment import Deployment, trained_stages
from mentor_core.controller.episodes import run_episodes
from mentor_core.controller.rotation_shim import RotationShim, goal_bearing, rotation_shim
from mentor_core.controller.stage import Stage
from mentor_core.controller.turn_gain import TurnGain
from mentor_core.errors import ConfigError
from mentor_core.evolution.genome import genome_from_edges
from mentor_core.evolution.network import FeedForwardNetwork
from mentor_core.runtime.planner import GenomePlanner, deployed_genome, planner_profile
from mentor_core.sim.episode import EpisodeBatch
from mentor_core.sim.observation import network_inputs
from mentor_core.sim.planner_settings import with_planner
from mentor_core.sim.robots import RobotProfile, get_profile
from mentor_core.sim.world import Scenario, World
from mentor_core.training.config import TrainerConfig
from mentor_core.training.trainer import make_problem, train

QUARTER = math.pi / 4


def shimmed(encoding: str = "egocentric") -> RobotProfile:
    """The planner's profile the shim is tested with (the shim itself is a stage)."""
    return with_planner(get_profile("ugv"), input_encoding=encoding, heading_change_max=QUARTER,
                        step_max=0.5, step_min=0.02)  # fmt: skip


def test_the_bearing_is_the_same_in_both_encodings() -> None:
    rng = np.random.default_rng(0)
    poses = np.column_stack([rng.uniform(0, 12, (50, 2)), rng.uniform(-4, 4, 50)])
    goals = rng.uniform(0, 12, (50, 2))
    readings = np.full((50, 8), 2.0)
    d = goals - poses[:, :2]
    expected = np.arctan2(d[:, 1], d[:, 0]) - poses[:, 2]
    expected = np.arctan2(np.sin(expected), np.cos(expected))
    for encoding in ("egocentric", "paper"):
        profile = shimmed(encoding)
        inputs = network_inputs(readings, poses, goals, profile)
        np.testing.assert_allclose(goal_bearing(inputs, profile), expected, atol=1e-9)


def test_it_turns_onto_the_goal_then_hands_over_for_good() -> None:
    profile = shimmed()
    k = profile.n_sensors
    inputs = np.zeros((3, profile.n_inputs))
    bearings = np.array([2.0, -0.6, 0.3])  # rad: far left, right, within the threshold
    inputs[:, k], inputs[:, k + 1] = np.cos(bearings), np.sin(bearings)
    network = np.full((3, 2), 0.9)
    out, aligned = rotation_shim(network, inputs, np.zeros(3, dtype=bool), profile, 0.35)
    # the first two turn by their bearing, clipped to the limit, with the smallest step
    np.testing.assert_allclose(out[:2], [[1.0, 0.0], [0.5 - 0.6 / (2 * QUARTER), 0.0]])
    np.testing.assert_array_equal(out[2], network[2])
    assert aligned.tolist() == [False, False, True]
    # once aligned, a wide bearing (going round an obstacle) is the network's to handle
    out, aligned = rotation_shim(network, inputs, np.ones(3, dtype=bool), profile, 0.35)
    np.testing.assert_array_equal(out, network)
    assert aligned.all()
    # with a threshold of half a turn every bearing is within it: nothing changes
    out, aligned = rotation_shim(network, inputs, np.zeros(3, dtype=bool), profile, math.pi)
    np.testing.assert_array_equal(out, network)
    assert aligned.all()


def test_the_stage_remembers_each_robot_until_it_is_reset() -> None:
    profile = shimmed()
    k = profile.n_sensors
    inputs = np.zeros((3, profile.n_inputs))
    bearings = np.array([2.0, -0.6, 0.3])
    inputs[:, k], inputs[:, k + 1] = np.cos(bearings), np.sin(bearings)
    network = np.full((3, 2), 0.9)
    stage = RotationShim(threshold_deg=math.degrees(0.35))
    assert stage.threshold == pytest.approx(0.35)
    run = stage.start(3, profile, None)
    robots = np.arange(3)
    out = run.outputs(robots, network, inputs)
    expected, _ = rotation_shim(network, inputs, np.zeros(3, dtype=bool), profile, 0.35)
    np.testing.assert_array_equal(out, expected)
    # robot 2 turned onto its goal: a wide bearing later is its network's
    wide = inputs.copy()
    wide[2, k], wide[2, k + 1] = math.cos(2.5), math.sin(2.5)
    np.testing.assert_array_equal(run.outputs(robots[2:], network[2:], wide[2:]), network[2:])
    run.reset(robots[2:])  # a new goal for robot 2 only
    assert run.outputs(robots[2:], network[2:], wide[2:])[0, 1] == 0.0
    np.testing.assert_array_equal(  # robot 0 still holds
        run.outputs(robots[:1], network[:1], inputs[:1]), expected[:1])
    assert stage.record() == {"rotation_shim": pytest.approx(0.35)}


def test_a_robot_facing_away_turns_on_the_spot_first_and_drives_shorter() -> None:
    # a network with no connections outputs (0.5, 0.5): straight on, a middling step
    profile = shimmed()
    genome = genome_from_edges(profile.n_inputs, 2, [])
    empty = World(12.0, np.zeros((0, 4)))
    away = Scenario(empty, (4.0, 6.0, math.pi), (10.0, 6.0))  # the goal straight behind

    def run(stages: tuple[Stage, ...]) -> EpisodeBatch:
        return run_episodes([away], profile,
                            FeedForwardNetwork.from_genome(genome).episode_policy(1),
                            time_budgets=[50.0], stages=stages)  # fmt: skip

    with_shim, without = run((RotationShim(threshold_deg=45),)), run(())
    path = with_shim.trajectories[0]
    # four quarter turns on the spot (steps of step_min), facing the goal, then straight
    turns = np.angle(np.exp(1j * np.diff(path[:5, 2])))  # either way round: it is behind
    np.testing.assert_allclose(np.abs(turns), QUARTER, atol=1e-9)
    assert abs(np.angle(np.exp(1j * path[4, 2]))) < 1e-9  # facing the goal
    assert np.all(np.hypot(*np.diff(path[:5, :2], axis=0).T) <= profile.step_min + 1e-9)
    assert with_shim.reached[0] and not without.reached[0]  # it never turns round


@pytest.mark.parametrize("gain", [1.0, 0.6])
def test_the_planner_on_the_robot_shims_as_the_engine_did(gain: float) -> None:
    """Bit for bit, also with a gain on the network's turn in front of the shim
    (the stage ``turn_gain``, a deployment option)."""
    config = TrainerConfig.from_dict({"robot": "swarm", "n_scenarios": 6, "rotation_shim_deg": 30})
    problem = make_problem(config)
    assert problem.stages == (RotationShim(threshold_deg=30),)
    problem.stages = (TurnGain(gain=gain), *problem.stages)
    rng = np.random.default_rng(2)
    n_in = problem.n_inputs
    edges = [(i, n_in + 1 + o, float(rng.normal())) for i in range(n_in) for o in range(2)]
    genome = genome_from_edges(n_in, 2, edges)
    batch = problem.simulate([genome])
    k = problem.profile.n_sensors
    planner = GenomePlanner(genome, problem.profile, stages=problem.stages)
    turned = 0
    for s, sc in enumerate(problem.scenarios):
        planner.reset()
        rows, poses = batch.experience[s], batch.trajectories[s]
        decided = [planner.decide(rows[t, :k], poses[t], sc.goal) for t in range(len(rows))]
        np.testing.assert_array_equal(decided, rows[:, k : k + 2])  # bit for bit
        turned += int(rows[0, k + 1] == problem.profile.step_min)
    assert turned  # some scenario started with a turn on the spot


def test_the_threshold_goes_into_the_metadata_and_back(tmp_path: Path) -> None:
    config = TrainerConfig.from_dict({"robot": "swarm", "generations": 2, "stage1_generations": 1,
                                      "n_scenarios": 2, "rotation_shim_deg": 45,
                                      "evolution": {"population_size": 6}})  # fmt: skip
    train(config, tmp_path, seed=0)
    path = tmp_path / "best_genome.json"
    metadata = json.loads(path.read_text())["metadata"]
    assert metadata["rotation_shim"] == pytest.approx(QUARTER)
    (shim,) = trained_stages(metadata)
    assert isinstance(shim, RotationShim) and shim.threshold == pytest.approx(QUARTER)
    # the planner runs behind it as trained, under any deployment that names no other shim
    assert [s.name for s in GenomePlanner.load(path, "swarm").stages] == ["rotation_shim"]
    _, deployed = deployed_genome(
        path, "swarm", Deployment(stages={"rotation_shim": {"threshold_deg": 20}}))
    assert deployed.stages == (RotationShim(threshold_deg=20),)
    # a genome saved without it, as every genome before it existed: no shim
    del metadata["rotation_shim"]
    assert trained_stages(metadata) == ()
    planner_profile(get_profile("swarm"), metadata)  # the profile never held it
    with pytest.raises(ConfigError, match=r"g\.json: rotation_shim"):
        trained_stages({**metadata, "rotation_shim": 4.0}, "g.json")
    with pytest.raises(ConfigError, match=r"g\.json: rotation_shim"):
        trained_stages({**metadata, "rotation_shim": "wide"}, "g.json")
    for bad in (0, 200, "wide"):
        with pytest.raises(ConfigError, match="rotation_shim_deg"):
            TrainerConfig.from_dict({"robot": "swarm", "rotation_shim_deg": bad})
