"""Bag-based regression: the committed episodes of the reference genomes (bags/regression/,
recorded from the real nodes by scripts/record_regression_bags.py) are reproduced today.

* open loop: every recorded scan, odometry and goal, fed to the planner's computation
  (:class:`mentor_core.runtime.planner.GenomePlanner`), gives the recorded cmd_vel, exactly;
* closed loop: re-simulating each recorded scenario with the genome in the loop
  (:func:`mentor_core.runtime.simulator.run_reference_episode`) reproduces the recorded odometry
  within 1e-6 m (in fact exactly), the recorded scans, and the same outcome.

No ROS graph is needed: the bags are read with rosbags.
"""

from __future__ import annotations

import json
import shutil
from functools import cache
from pathlib import Path

import numpy as np
import pytest
import yaml

from mentor_core.errors import FileFormatError
from mentor_core.evolution.genome import ConnectionGene, Genome
from mentor_core.files.bags import EpisodeLog, GoalRecord, read_episode_bag, read_scenario_bag
from mentor_core.files.genome_file import save_genome
from mentor_core.runtime.planner import GenomePlanner
from mentor_core.runtime.recording import RecordedRun, recorded_episodes, recording_world
from mentor_core.runtime.simulator import run_reference_episode

ROOT = Path(__file__).resolve().parents[1]
REGRESSION = ROOT / "bags" / "regression"
ROBOTS = ("ugv", "swarm")
TOLERANCE = 1e-6  # m
MAX_TOTAL_BYTES = 400 * 1024


@cache
def _log(robot: str) -> EpisodeLog:
    return read_episode_bag(REGRESSION / f"{robot}_episodes")


@cache
def _runs(robot: str) -> tuple[RecordedRun, ...]:
    return tuple(recorded_episodes(_log(robot), REGRESSION / f"{robot}_episodes"))


def _planner(robot: str) -> GenomePlanner:
    return GenomePlanner.load(REGRESSION / f"{robot}_reference_genome.json", robot)


def _goal_at(goals: tuple[GoalRecord, ...], stamp_ns: int) -> tuple[float, float]:
    return [g for g in goals if g.stamp_ns <= stamp_ns][-1].goal


def test_the_bags_are_small_complete_jazzy_bags() -> None:
    files = [f for f in REGRESSION.rglob("*") if f.is_file()]
    assert sum(f.stat().st_size for f in files) < MAX_TOTAL_BYTES
    for robot in ROBOTS:
        meta = yaml.safe_load((REGRESSION / f"{robot}_episodes" / "metadata.yaml").read_text())
        info = meta["rosbag2_bagfile_information"]
        assert info["storage_identifier"] == "mcap" and info["version"] == 9
        topics = {t["topic_metadata"]["name"] for t in info["topics_with_message_count"]}
        assert {"/mentor/metadata", "/mentor/obstacles", "/robot_0/scan", "/robot_0/odom",
                "/robot_0/cmd_vel", "/robot_0/goal", "/robot_0/events"} <= topics
        log = _log(robot)
        assert log.profile_name == robot
        assert log.metadata["genome"] == f"bags/regression/{robot}_reference_genome.json"
        # the episodes were recorded from the scenario bag beside them, in the same world
        world, scenarios, profile, _ = read_scenario_bag(REGRESSION / f"{robot}_scenarios")
        assert profile == robot and world == recording_world(log) == log.world
        runs = _runs(robot)
        assert [r.setup.start for r in runs] == [s.start for s in scenarios]
        # every ending is covered
        assert {r.outcome for r in runs} == {"reached", "collided", "timed_out"}


@pytest.mark.parametrize("robot", ROBOTS)
def test_open_loop_recorded_inputs_give_the_recorded_commands(robot: str) -> None:
    planner = _planner(robot)
    goals = _log(robot).robots[0].goals
    checked = 0
    for run in _runs(robot):
        odom = {o.stamp_ns: o.pose for o in run.odometry}
        commands = {c.stamp_ns: (c.linear_x, c.angular_z) for c in run.commands}
        assert len(commands) == len(run.scans) > 0
        for scan in run.scans:
            got = planner.command(scan.ranges, odom[scan.stamp_ns], _goal_at(goals, scan.stamp_ns))
            assert got == commands[scan.stamp_ns]
            checked += 1
    assert checked >= 10


@pytest.mark.parametrize("robot", ROBOTS)
def test_closed_loop_resimulation_reproduces_odometry_and_outcome(robot: str) -> None:
    planner = _planner(robot)
    world = recording_world(_log(robot))
    for run in _runs(robot):
        ref = run_reference_episode(world, [run.setup], {"robot_0": planner.decide})["robot_0"]
        assert ref.outcome == run.outcome
        recorded = np.array([o.pose for o in run.odometry])
        assert recorded.shape == ref.poses.shape
        assert np.abs(recorded[:, :2] - ref.poses[:, :2]).max() <= TOLERANCE
        heading = np.remainder(recorded[:, 2] - ref.poses[:, 2] + np.pi, 2 * np.pi) - np.pi
        assert np.abs(heading).max() <= 1e-9
        np.testing.assert_array_equal(np.array([s.ranges for s in run.scans]), ref.ranges)


def test_a_changed_planner_is_caught(tmp_path: Path) -> None:
    """The open-loop check has teeth: one weight nudged by 1e-3 changes recorded commands."""
    planner = _planner("ugv")
    g = planner.genome
    first = g.connections[0]
    nudged = ConnectionGene(first.innovation, first.in_node, first.out_node,
                            first.weight + 1e-3, first.enabled)
    changed = Genome(g.n_inputs, g.n_outputs, g.nodes, (nudged, *g.connections[1:]))
    save_genome(changed, tmp_path / "changed.json")
    other = GenomePlanner.load(tmp_path / "changed.json", "ugv")
    goals = _log("ugv").robots[0].goals
    differ = 0
    for run in _runs("ugv"):
        odom = {o.stamp_ns: o.pose for o in run.odometry}
        for scan, cmd in zip(run.scans, run.commands, strict=True):
            got = other.command(scan.ranges, odom[scan.stamp_ns], _goal_at(goals, scan.stamp_ns))
            differ += got != (cmd.linear_x, cmd.angular_z)
    assert differ > 0


def test_damaged_regression_bags_are_refused(tmp_path: Path) -> None:
    source = REGRESSION / "swarm_episodes"
    cut = tmp_path / "cut"
    shutil.copytree(source, cut)
    (mcap,) = cut.glob("*.mcap")
    mcap.write_bytes(mcap.read_bytes()[: mcap.stat().st_size // 3])
    with pytest.raises(FileFormatError, match=f"^{cut}: unreadable bag"):
        read_episode_bag(cut)
    # a scenario bag is not an episode bag
    with pytest.raises(FileFormatError, match="not a mentor-episode-bag"):
        read_episode_bag(REGRESSION / "swarm_scenarios")
    # an episode bag without the simulator's recording metadata cannot be re-simulated
    log = _log("swarm")
    foreign = EpisodeLog(log.profile_name, log.robots, {"note": json.dumps("hand-made")})
    with pytest.raises(FileFormatError, match="not a simulator recording"):
        recorded_episodes(foreign, "hand-made")
