"""The planner's decision pipeline (the trainer's own functions) and its decision gate."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from mentor_core.errors import ConfigError, FileFormatError
from mentor_core.evolution.genome import minimal_genome
from mentor_core.evolution.innovation import InnovationTracker
from mentor_core.evolution.network import FeedForwardNetwork
from mentor_core.files.genome_file import save_genome
from mentor_core.runtime.decision_gate import DecisionGate
from mentor_core.runtime.planner import GenomePlanner
from mentor_core.sim.observation import actions_from_outputs, network_inputs, twist_from_action
from mentor_core.sim.robots import get_profile

UGV = get_profile("ugv")
SWARM = get_profile("swarm")
S = 1_000_000_000  # ns per s


@pytest.fixture
def swarm_genome_file(tmp_path: Path) -> Path:
    tracker = InnovationTracker(SWARM.n_inputs + 3)
    genome = minimal_genome(SWARM.n_inputs, 2, tracker, np.random.default_rng(1))
    path = tmp_path / "swarm.json"
    save_genome(genome, path)
    return path


def test_decisions_are_the_trainers(swarm_genome_file: Path) -> None:
    planner = GenomePlanner.load(swarm_genome_file, "swarm")
    net = FeedForwardNetwork.from_genome(planner.genome)
    rng = np.random.default_rng(0)
    for _ in range(20):
        ranges = np.where(rng.random(3) < 0.3, np.inf, rng.uniform(0.0, 0.6, 3))
        pose = (rng.uniform(0, 4), rng.uniform(0, 4), rng.uniform(-math.pi, math.pi))
        goal = (rng.uniform(0, 4), rng.uniform(0, 4))
        inputs = network_inputs(ranges[None], np.array([pose]), np.array([goal]), SWARM)
        dtheta, ds = actions_from_outputs(net.activate(inputs), SWARM)
        assert planner.decide(ranges, pose, goal) == (float(dtheta[0]), float(ds[0]))
        wz, vx = twist_from_action(dtheta[0], ds[0], 1.0)
        assert planner.command(ranges, pose, goal) == (float(vx), float(wz))
        assert -math.pi <= dtheta[0] <= math.pi and 0.01 <= ds[0] <= 0.08


def test_a_genome_trained_with_a_clearance_margin_keeps_it(tmp_path: Path) -> None:
    tracker = InnovationTracker(UGV.n_inputs + 3)
    genome = minimal_genome(UGV.n_inputs, 2, tracker, np.random.default_rng(2))
    planner_settings = {"step_max": 0.5, "step_min": 0.02, "clearance_margin": 0.1}
    save_genome(genome, tmp_path / "ugv.json", metadata=planner_settings)
    planner = GenomePlanner.load(tmp_path / "ugv.json", "ugv")
    assert planner.profile.clearance_margin == 0.1 and planner.profile.step_min == 0.02
    ranges = np.array([0.15, 0.15, 4.0, 4.0, 4.0, 4.0, 4.0, 4.0])  # a wall just ahead
    pose, goal = (1.0, 1.0, 0.0), (5.0, 1.0)
    inputs = network_inputs(ranges[None], np.array([pose]), np.array([goal]), planner.profile)
    outputs = planner.network.activate(inputs)
    dtheta, ds = actions_from_outputs(outputs, planner.profile, ranges[None])
    assert planner.decide(ranges, pose, goal) == (float(dtheta[0]), float(ds[0]))
    assert ds[0] <= max(0.02, 0.15 - 0.1)


def test_bad_inputs_are_refused(swarm_genome_file: Path) -> None:
    planner = GenomePlanner.load(swarm_genome_file, "swarm")
    with pytest.raises(ValueError, match="NaN"):
        planner.decide([math.nan, 0.1, 0.1], (1.0, 1.0, 0.0), (2.0, 2.0))
    with pytest.raises(ValueError):
        planner.decide([0.1, 0.1], (1.0, 1.0, 0.0), (2.0, 2.0))


def test_corrupt_genome_unknown_profile_and_misfit(
    swarm_genome_file: Path, tmp_path: Path
) -> None:
    bad = tmp_path / "bad.json"
    bad.write_text(swarm_genome_file.read_text()[:100])
    with pytest.raises(FileFormatError, match=r"bad\.json"):
        GenomePlanner.load(bad, "swarm")
    with pytest.raises(ConfigError, match="unknown robot 'tank'"):
        GenomePlanner.load(swarm_genome_file, "tank")
    with pytest.raises(ConfigError, match="needs 11 inputs"):
        GenomePlanner.load(swarm_genome_file, "ugv")
    for err in (FileFormatError, ConfigError):
        assert issubclass(err, ValueError)
    data = json.loads(swarm_genome_file.read_text())
    data["connections"][0]["weight"] = "heavy"
    bad.write_text(json.dumps(data))
    with pytest.raises(FileFormatError):
        GenomePlanner.load(bad, "swarm")


def test_gate_answers_each_synchronised_observation_once() -> None:
    gate = DecisionGate(stale_after=3.0, sync_tolerance=0.0)
    gate.on_scan(0, [0.1, 0.2, 0.3])
    gate.on_odometry(0, (1.0, 1.0, 0.0))
    assert gate.take(0) is None  # no goal yet
    gate.on_goal((2.0, 2.0))
    obs = gate.take(0)
    assert obs is not None and obs.stamp_ns == 0 and obs.goal == (2.0, 2.0)
    np.testing.assert_array_equal(obs.ranges, [0.1, 0.2, 0.3])
    assert gate.take(0) is None  # answered once
    gate.on_scan(0, [0.1, 0.2, 0.3])  # the simulator repeats an unanswered observation
    assert gate.take(0) is None
    gate.on_scan(1 * S, [0.2, 0.2, 0.3])
    assert gate.take(0) is None  # odometry of the new stamp not there yet
    gate.on_odometry(1 * S, (1.1, 1.0, 0.0))
    obs = gate.take(1 * S)
    assert obs is not None and obs.pose == (1.1, 1.0, 0.0)
    # a simulator that restarts: the clock jumps back, the planner follows
    gate.on_scan(0, [0.3, 0.3, 0.3])
    gate.on_odometry(0, (0.5, 0.5, 0.0))
    assert gate.take(2 * S) is not None


def test_gate_pairs_the_scan_with_the_pose_at_its_stamp() -> None:
    """The scan is the clock: the pose between the odometry before and after its stamp, or
    the nearest within sync_tolerance (issue 56, point 1)."""
    gate = DecisionGate(stale_after=3.0, sync_tolerance=0.05)
    gate.on_goal((0.0, 0.0))
    gate.on_scan(1_000_000_000, [1.0] * 8)
    gate.on_odometry(1_040_000_000, (1.0, 1.0, 0.0))
    obs = gate.take(0)  # the odometry 0.04 s after the scan, within the tolerance
    assert obs is not None and obs.stamp_ns == 1_000_000_000 and obs.pose == (1.0, 1.0, 0.0)
    gate.on_odometry(1_240_000_000, (1.2, 1.0, 0.4))
    gate.on_scan(1_190_000_000, [1.0] * 8)  # three quarters of the way between the two
    obs = gate.take(0)
    assert obs is not None
    np.testing.assert_allclose(obs.pose, (1.15, 1.0, 0.3), atol=1e-12)
    gate.on_scan(1_300_000_000, [1.0] * 8)  # 0.06 s past the newest odometry: it waits
    assert gate.take(0) is None
    gate.on_odometry(1_340_000_000, (1.3, 1.0, 0.4))
    obs = gate.take(0)
    assert obs is not None and obs.stamp_ns == 1_300_000_000
    np.testing.assert_allclose(obs.pose, (1.26, 1.0, 0.4), atol=1e-12)


def test_a_lidar_at_5_hz_and_odometry_at_30_hz_are_paired_at_every_scan() -> None:
    """At the rates of Gazebo's TurtleBot3 the latest scan and the latest odometry lie within
    0.05 s of each other at a third of the ticks; paired by stamp, every scan is answered."""
    gate = DecisionGate(stale_after=3.0, sync_tolerance=0.1)
    gate.on_goal((9.0, 0.0))
    answered = 0
    events = sorted([(k * S // 5 + 7_000_000, "scan") for k in range(25)]
                    + [(k * S // 30, "odom") for k in range(150)])  # fmt: skip
    for t, kind in events:
        if kind == "odom":
            gate.on_odometry(t, (t / S, 0.0, 0.0), received_ns=t)
        else:
            gate.on_scan(t, [1.0] * 3, received_ns=t)
        obs = gate.take(t)
        if obs is not None:
            answered += 1
            # the pose at the scan's stamp, or the newest before it (one odometry interval)
            assert 0.0 <= obs.stamp_ns / S - obs.pose[0] <= 1 / 30 + 1e-9
    assert answered == 25


def test_a_refused_scan_leaves_nothing_to_answer_and_a_stopped_stream_is_stale_at_once() -> None:
    gate = DecisionGate(stale_after=1.5, sync_tolerance=0.1)
    gate.on_goal((5.0, 0.0))
    for k in range(10):  # scans at 5 Hz, odometry at 50 Hz
        for j in range(10):
            t = k * S // 5 + j * S // 50
            gate.on_odometry(t, (0.0, 0.0, 0.0), received_ns=t)
        gate.on_scan(k * S // 5, [1.0] * 3, received_ns=k * S // 5)
        assert gate.take(k * S // 5) is not None
    last = 9 * S // 5 + 9 * S // 50
    assert gate.stale(last + S // 100) is None
    # the odometry stops: stale 2.5 of its intervals (0.02 s) on, at the 0.2 s floor
    assert gate.stale(last + 190_000_000) is None
    why = gate.stale(last + 210_000_000)
    assert why is not None and why.startswith("no odometry for 0.210 s")
    assert gate.watchdog(last + 210_000_000) == why
    gate.refuse_scan(received_ns=2 * S)
    gate.on_odometry(2 * S, (0.0, 0.0, 0.0), received_ns=2 * S)
    assert gate.take(2 * S) is None  # nothing decided on the scan before the refused one


def test_watchdog_reports_missing_and_stale_data() -> None:
    gate = DecisionGate(stale_after=3.0, sync_tolerance=0.0)
    assert gate.watchdog(10 * S) is None  # no goal: nothing is driven, nothing to stop
    assert gate.watchdog(100 * S) is None
    gate.on_goal((1.0, 1.0))  # a goal: the watchdog counts from its last quiet call
    assert gate.watchdog(103 * S) is None
    assert gate.watchdog(104 * S) == "no scan, odometry received"
    gate = DecisionGate(stale_after=3.0, sync_tolerance=0.0)
    gate.on_goal((1.0, 1.0))
    assert gate.watchdog(10 * S) is None  # counts from its first call
    gate.on_scan(0, [1.0] * 3)
    gate.on_odometry(0, (0.0, 0.0, 0.0))
    assert gate.take(14 * S) is not None
    assert gate.watchdog(17 * S) is None
    msg = gate.watchdog(18 * S)
    assert msg is not None and msg.startswith("no new scan and odometry for 4.000 s")
    gate.on_scan(10 * S, [1.0] * 3)  # odometry stopped at 5 s
    gate.on_odometry(5 * S, (0.0, 0.0, 0.0))
    assert (gate.watchdog(18 * S) or "").startswith("no odometry within 0.000 s of the scan's "
                                                     "stamp 10.000 s (odometry from 0.000 to")


def _gate_after_one_episode() -> DecisionGate:
    """A gate that answered one observation, then saw the episode end (reached at 1 s)."""
    gate = DecisionGate(stale_after=3.0, sync_tolerance=0.0)
    gate.on_goal((1.0, 1.0))
    gate.on_scan(0, [1.0] * 3)
    gate.on_odometry(0, (0.0, 0.0, 0.0))
    assert gate.take(0) is not None
    gate.on_event("reached", 1 * S)
    return gate


def test_watchdog_is_quiet_between_episodes() -> None:
    gate = _gate_after_one_episode()
    assert gate.idle and gate.watchdog(100 * S) is None
    gate.on_event("started", 100 * S, goal=(2.0, 2.0))  # the next: the watchdog counts afresh
    assert not gate.idle
    assert gate.watchdog(103 * S) is None
    assert gate.watchdog(104 * S) is not None
    with pytest.raises(ValueError):
        DecisionGate(stale_after=0.0, sync_tolerance=0.0)
    with pytest.raises(ValueError):
        DecisionGate(stale_after=1.0, sync_tolerance=-1.0)


def test_between_episodes_nothing_is_answered_and_the_new_goal_comes_with_started() -> None:
    gate = _gate_after_one_episode()
    # the next episode's observation arrives before its started event: it waits
    gate.on_scan(2 * S, [0.5] * 3)
    gate.on_odometry(2 * S, (3.0, 3.0, 0.0))
    assert gate.take(2 * S) is None
    gate.on_event("started", 2 * S, goal=(4.0, 0.5))
    obs = gate.take(2 * S)
    assert obs is not None and obs.goal == (4.0, 0.5) and obs.stamp_ns == 2 * S
    # a goal topic message with the same goal later changes nothing
    gate.on_goal((4.0, 0.5))
    assert gate.take(2 * S) is None


def test_the_last_scan_of_an_ended_episode_is_not_answered_with_the_next_goal() -> None:
    """The simulator ends an episode, publishes its final odometry and starts the next: the
    scan held from the episode that ended is no question for the next goal (failed when the
    scan first became the clock: two answers too many in three episodes, test_ros_e2e)."""
    gate = DecisionGate(stale_after=3.0, sync_tolerance=0.1)
    gate.on_goal((1.0, 1.0))
    gate.on_scan(38 * S, [1.0] * 3)
    gate.on_odometry(38 * S, (0.0, 0.0, 0.0))
    assert gate.take(38 * S) is not None
    gate.on_event("timed_out", 38 * S)
    gate.on_odometry(39 * S, (0.1, 0.0, 0.0))  # the final pose
    gate.on_event("started", 39 * S, goal=(4.0, 0.5))
    assert gate.take(39 * S) is None
    gate.on_scan(40 * S, [1.0] * 3)
    assert gate.take(40 * S) is None  # the final pose lies 1 s back: no pose at 40 s yet
    gate.on_odometry(40 * S, (3.0, 3.0, 0.0))
    obs = gate.take(40 * S)
    assert obs is not None and obs.pose == (3.0, 3.0, 0.0) and obs.goal == (4.0, 0.5)


def test_a_new_goal_is_a_new_question_and_the_same_goal_is_not() -> None:
    gate = DecisionGate(stale_after=3.0, sync_tolerance=0.0)
    gate.on_scan(0, [0.1, 0.2, 0.3])
    gate.on_odometry(0, (1.0, 1.0, 0.0))
    assert gate.on_goal((2.0, 2.0)) and gate.take(0) is not None
    assert not gate.on_goal((2.0, 2.0 + 1e-12))  # the same goal through another frame
    assert gate.take(0) is None
    assert gate.on_goal((3.0, 1.0))  # another goal: the same observation is answered again
    obs = gate.take(0)
    assert obs is not None and obs.goal == (3.0, 1.0) and gate.take(0) is None


def test_the_goal_is_done_when_ended_or_the_episode_ends() -> None:
    gate = DecisionGate(stale_after=3.0, sync_tolerance=0.0)
    gate.on_goal((2.0, 2.0))
    gate.on_scan(0, [0.1, 0.2, 0.3])
    gate.on_odometry(0, (1.0, 1.0, 0.0))
    gate.end_goal()
    assert gate.goal is None and gate.take(0) is None  # nothing is answered without a goal
    assert gate.on_goal((2.0, 2.0))  # the same goal again is a new one
    gate.on_event("collided", 0)
    assert gate.goal is None  # an end event ends the goal too
