"""Planners with a context (``feedback_action``, ``memory_units``): what each decision reads
of the previous one, in the episode loop and in GenomePlanner alike, reset per episode and
goal; settings from the trainer config into the genome's metadata and back."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from memory_support import latch

from mentor_core.benchmark.contenders import hand_written
from mentor_core.benchmark.suite import reference_profile
from mentor_core.controller.episodes import run_episodes
from mentor_core.errors import ConfigError
from mentor_core.evolution.genome import Genome, minimal_genome
from mentor_core.evolution.innovation import InnovationTracker
from mentor_core.evolution.network import FeedForwardNetwork
from mentor_core.files.genome_file import load_genome_and_metadata, save_genome
from mentor_core.runtime.decision_gate import DecisionGate
from mentor_core.runtime.planner import GenomePlanner, planner_profile
from mentor_core.sim import observation
from mentor_core.sim.planner_settings import with_planner
from mentor_core.sim.robots import RobotProfile, get_profile
from mentor_core.sim.world import Scenario, World
from mentor_core.training.config import TrainerConfig
from mentor_core.training.trainer import make_problem

SWARM = get_profile("swarm")  # 3 sensors of 0.6 m, heading change in [-pi, pi], dt 1 s
SPAN = SWARM.step_max - SWARM.step_min  # ds = step_min + SPAN o_2
WORLD = World(4.0, np.array([[1.6, 1.4, 2.0, 2.6], [0.4, 3.0, 1.2, 3.3], [2.6, 0.5, 3.0, 0.9]]))
SCENARIOS = [
    Scenario(WORLD, (1.0, 2.0, 0.0), (3.4, 2.0)),
    Scenario(WORLD, (0.5, 0.5, 1.2), (3.5, 3.5)),
    Scenario(WORLD, (3.5, 3.5, -2.0), (0.5, 1.0)),
]
S = 1_000_000_000  # ns per s


def random_genome(profile: RobotProfile, seed: int) -> Genome:
    tracker = InnovationTracker(profile.n_inputs + 1 + profile.n_outputs)
    return minimal_genome(
        profile.n_inputs, profile.n_outputs, tracker, np.random.default_rng(seed),
        weight_sigma=2.0,
    )  # fmt: skip


def genome_policy(genome: Genome):  # type: ignore[no-untyped-def]
    network = FeedForwardNetwork.from_genome(genome)
    return lambda inputs, robots: network.activate(inputs)


def test_default_profiles_and_configs_have_no_context() -> None:
    assert (SWARM.feedback_action, SWARM.memory_units, SWARM.n_context) == (False, 0, 0)
    assert (SWARM.n_inputs, SWARM.n_outputs) == (6, 2)
    plain = make_problem(TrainerConfig.from_dict({"robot": "swarm"})).profile
    assert (plain.n_inputs, plain.n_outputs) == (6, 2)
    both = with_planner(SWARM, feedback_action=True, memory_units=3)
    assert (both.n_context, both.n_inputs, both.n_outputs) == (5, 11, 5)


def test_inputs_and_context_follow_the_documented_order() -> None:
    profile = with_planner(SWARM, input_encoding="paper", feedback_action=True, memory_units=2)
    first = observation.initial_context(2, profile)
    np.testing.assert_array_equal(first, [[0.5, 0.0, 0.0, 0.0]] * 2)  # no turn, least step
    ranges = np.array([[0.1, np.inf, 0.3], [0.2, 0.2, 0.2]])
    poses = np.array([[1.0, 1.0, 3.0], [2.0, 2.0, -1.0]])
    goals = np.array([[3.0, 3.0], [0.0, 2.0]])
    plain = observation.network_inputs(ranges, poses, goals, SWARM)
    got = observation.network_inputs(ranges, poses, goals, profile, first)
    np.testing.assert_array_equal(got[:, :6], plain)  # readings, dX, dY, theta as before
    np.testing.assert_array_equal(got[:, 6:], first)
    outputs = np.array([[1.3, -0.2, 0.25, 2.0], [0.7, 0.4, -1.0, 0.9]])
    np.testing.assert_array_equal(  # clipped to [0, 1], actions then memory
        observation.next_context(outputs, profile), [[1.0, 0.0, 0.25, 1.0], [0.7, 0.4, 0.0, 0.9]]
    )
    memory_only = with_planner(SWARM, memory_units=2)
    np.testing.assert_array_equal(observation.next_context(outputs, memory_only),
                                  [[0.25, 1.0], [0.0, 0.9]])  # fmt: skip
    # the memory outputs are no actions
    dtheta, ds = observation.actions_from_outputs(outputs, profile)
    np.testing.assert_array_equal(dtheta, [np.pi, np.pi * (2.0 * 0.7 - 1.0)])
    np.testing.assert_array_equal(ds, [0.01, 0.01 + SPAN * 0.4])
    with pytest.raises(ValueError, match="previous outputs"):
        observation.network_inputs(ranges, poses, goals, profile)
    with pytest.raises(ValueError, match=r"\(n, 4\) network outputs"):
        observation.actions_from_outputs(outputs[:, :2], profile)


def test_a_latch_turns_by_what_the_first_sensor_read_one_decision_before() -> None:
    profile = with_planner(SWARM, memory_units=1)
    planner = GenomePlanner(latch(profile), profile)
    rng = np.random.default_rng(4)
    previous = 0.0  # the memory input of the first decision
    for _ in range(30):
        ranges = rng.uniform(0.0, 0.6, 3)
        dtheta, ds = planner.decide(ranges, (1.0, 1.0, 0.0), (3.0, 3.0))
        assert dtheta == math.pi * (2.0 * previous - 1.0) and ds == 0.01 + SPAN * 0.5
        previous = ranges[0]
    # in the episode loop the same: the action at t reads U_0(t - 1) of the experience
    batch = run_episodes(SCENARIOS, profile, genome_policy(latch(profile)))
    assert batch.steps.min() >= 3
    for rows in batch.experience:
        seen, turns = rows[:, 0], rows[:, 3]
        expected = math.pi * (2.0 * np.concatenate([[0.0], seen[:-1]]) - 1.0)
        np.testing.assert_array_equal(turns, expected)


@pytest.mark.parametrize(("feedback", "units"), [(True, 0), (False, 2), (True, 3)])
def test_the_episode_loop_and_the_planner_decide_alike_and_reset_starts_blank(
    feedback: bool, units: int
) -> None:
    profile = with_planner(SWARM, input_encoding="egocentric", feedback_action=feedback,
                           memory_units=units)  # fmt: skip
    genome = random_genome(profile, seed=units + 7)
    batch = run_episodes(SCENARIOS, profile, genome_policy(genome))
    planner = GenomePlanner(genome, profile)
    k = profile.n_sensors
    for i, sc in enumerate(SCENARIOS):
        planner.reset()
        rows = batch.experience[i]
        poses = batch.trajectories[i]
        decided = [planner.decide(rows[t, :k], poses[t], sc.goal) for t in range(len(rows))]
        np.testing.assert_array_equal(decided, rows[:, k : k + 2])  # bit for bit
        planner.reset()
        again = [planner.decide(rows[t, :k], poses[t], sc.goal) for t in range(len(rows))]
        assert again == decided
    # the context matters: a planner reset before every decision decides otherwise
    rows, poses = batch.experience[1], batch.trajectories[1]
    blank = []
    for t in range(len(rows)):
        planner.reset()
        blank.append(planner.decide(rows[t, :k], poses[t], SCENARIOS[1].goal))
    assert not np.array_equal(blank, rows[:, k : k + 2])


def test_each_robot_carries_its_own_context() -> None:
    profile = with_planner(SWARM, feedback_action=True, memory_units=2)
    policy = genome_policy(random_genome(profile, seed=3))
    together = run_episodes(SCENARIOS, profile, policy)
    for i, sc in enumerate(SCENARIOS):
        alone = run_episodes([sc], profile, policy)
        np.testing.assert_array_equal(alone.experience[0], together.experience[i])
        steps = alone.trajectories.shape[1]
        np.testing.assert_array_equal(alone.trajectories[0], together.trajectories[i, :steps])


def test_a_planner_that_failed_to_decide_keeps_its_context() -> None:
    profile = with_planner(SWARM, memory_units=1)
    planner = GenomePlanner(latch(profile), profile)
    planner.decide([0.4, 0.6, 0.6], (1.0, 1.0, 0.0), (3.0, 3.0))
    with pytest.raises(ValueError, match="NaN"):
        planner.decide([math.nan, 0.6, 0.6], (1.0, 1.0, 0.0), (3.0, 3.0))
    dtheta, _ = planner.decide([0.1, 0.6, 0.6], (1.0, 1.0, 0.0), (3.0, 3.0))
    assert dtheta == math.pi * (2.0 * 0.4 - 1.0)


def test_the_settings_go_from_the_config_into_the_metadata_and_back(tmp_path: Path) -> None:
    config = TrainerConfig.from_dict({"robot": "swarm", "feedback_action": True,
                                      "memory_units": 2})  # fmt: skip
    assert TrainerConfig.from_dict(config.to_dict()) == config
    profile = make_problem(config).profile
    assert (profile.feedback_action, profile.memory_units) == (True, 2)
    assert (profile.n_inputs, profile.n_outputs) == (10, 4)
    genome = random_genome(profile, seed=1)
    path = tmp_path / "memory.json"
    save_genome(genome, path, metadata={"feedback_action": True, "memory_units": 2,
                                        "input_encoding": "egocentric"})  # fmt: skip
    planner = GenomePlanner.load(path, "swarm")
    assert planner.profile == profile
    # a genome saved before the keys existed has no context
    _, meta = load_genome_and_metadata(path)
    old = planner_profile(SWARM, {k: v for k, v in meta.items()
                                  if k not in ("feedback_action", "memory_units")})  # fmt: skip
    assert (old.feedback_action, old.memory_units) == (False, 0)
    # a genome whose outputs do not fit its metadata's settings: the one-line ConfigError
    save_genome(genome, path, metadata={"feedback_action": True, "memory_units": 1})
    with pytest.raises(ConfigError, match=r"needs 9 inputs and 3 outputs") as err:
        GenomePlanner.load(path, "swarm")
    assert str(path) in str(err.value) and "\n" not in str(err.value)


@pytest.mark.parametrize(
    ("changes", "key"),
    [
        ({"memory_units": -1}, "memory_units"),
        ({"memory_units": 9}, "memory_units"),
        ({"memory_units": True}, "memory_units"),
        ({"memory_units": 1.0}, "memory_units"),
        ({"feedback_action": "yes"}, "feedback_action"),
        ({"feedback_action": 1}, "feedback_action"),
    ],
)
def test_bad_settings_name_the_key(changes: dict[str, object], key: str, tmp_path: Path) -> None:
    with pytest.raises(ConfigError, match=key) as err:
        TrainerConfig.from_dict({"robot": "swarm", **changes}, "cfg.yaml")
    assert "cfg.yaml" in str(err.value) and "\n" not in str(err.value)
    path = tmp_path / "bad.json"
    save_genome(random_genome(SWARM, 0), path, metadata=changes)
    with pytest.raises(ConfigError, match=key) as err:
        GenomePlanner.load(path, "swarm")
    assert str(path) in str(err.value) and "\n" not in str(err.value)


def test_the_gate_marks_the_first_answer_of_each_goal_and_episode() -> None:
    gate = DecisionGate(stale_after=3.0, sync_tolerance=0.01)
    gate.on_goal((3.0, 3.0))
    gate.on_scan(1 * S, [0.3, 0.3, 0.3])
    gate.on_odometry(1 * S, (1.0, 1.0, 0.0))
    first = gate.take(1 * S)
    assert first is not None and first.new_goal and not first.new_episode
    assert gate.take(1 * S) is None  # a repeated observation (a lockstep resend): not again
    gate.on_goal((3.0, 3.0))  # the goal held, once more
    gate.on_scan(2 * S, [0.3, 0.3, 0.3])
    gate.on_odometry(2 * S, (1.0, 1.0, 0.0))
    second = gate.take(2 * S)
    assert second is not None and not second.new_goal
    gate.on_goal((1.0, 3.0))  # a new goal: answered again, with the same stamp
    third = gate.take(2 * S)
    assert third is not None and third.new_goal and not third.new_episode  # a goal only
    gate.on_event("started", 4 * S, (1.0, 3.0))  # a restarted episode, the goal held
    gate.on_scan(5 * S, [0.3, 0.3, 0.3])
    gate.on_odometry(5 * S, (1.0, 1.0, 0.0))
    fourth = gate.take(5 * S)
    assert fourth is not None and fourth.new_goal and fourth.new_episode
    gate.on_event("collided", 6 * S)  # the goal is done: the next one is new
    gate.on_goal((1.0, 3.0))
    gate.on_event("started", 7 * S)
    gate.on_scan(8 * S, [0.3, 0.3, 0.3])
    gate.on_odometry(8 * S, (1.0, 1.0, 0.0))
    fifth = gate.take(8 * S)
    assert fifth is not None and fifth.new_goal and fifth.new_episode


def test_baselines_ignore_the_context_and_answer_zero_memory() -> None:
    reference = reference_profile(SWARM)
    remembering = with_planner(reference, feedback_action=True, memory_units=2)
    for name in ("vfh", "bug", "oracle"):
        plain = run_episodes(SCENARIOS, reference, hand_written(name, reference).policy(SCENARIOS))
        policy = hand_written(name, remembering).policy(SCENARIOS)
        other = run_episodes(SCENARIOS, remembering, policy)
        np.testing.assert_array_equal(plain.trajectories, other.trajectories)
        np.testing.assert_array_equal(plain.reached, other.reached)
