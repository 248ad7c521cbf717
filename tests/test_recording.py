"""Recording simulator episodes into an episode bag and splitting them back into episodes."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from mentor_core.errors import FileFormatError
from mentor_core.files.bags import EpisodeLog, read_episode_bag
from mentor_core.runtime.recording import (
    EpisodeRecorder,
    episode_setups,
    recorded_episodes,
    recording_world,
    world_from_json,
    world_to_json,
)
from mentor_core.runtime.simulator import ReferenceSimulator, RobotSetup
from mentor_core.sim.robots import get_profile
from mentor_core.sim.world import World

SWARM = get_profile("swarm")
S = 1_000_000_000


def _record(world: World, episodes: list[list[RobotSetup]]) -> EpisodeRecorder:
    """Drive every robot straight ahead, recording as the simulator node does."""
    names = sorted({s.name for ep in episodes for s in ep})
    rec = EpisodeRecorder(world, 1.0, names)
    sim = ReferenceSimulator(world, 1.0)
    t = 0
    for e, setups in enumerate(episodes):
        if e:
            t += S
        events, _ = sim.start(setups)
        rec.begin_episode(e, t, setups)
        for s in setups:
            rec.goal(s.name, t, s.goal)
        for ev in events:
            rec.event(ev.robot, t, ev.kind, ev.scenario)
        while not sim.done:
            for name in sim.active:
                rec.scan(name, t, sim.observe(name))
                rec.odometry(name, t, sim.pose(name), (0.0, 0.0))
                rec.command(name, t, 0.08, 0.0)
            active = sim.active
            events = sim.step({n: (0.0, 0.08) for n in active})
            t += S
            for ev in events:
                rec.event(ev.robot, t, ev.kind, ev.scenario)
                rec.odometry(ev.robot, t, sim.pose(ev.robot), (0.0, 0.0))
    return rec


def test_recording_round_trip_and_split(tmp_path: Path) -> None:
    world = World(4.0, np.array([[3.0, 0.0, 4.0, 1.0]]), name="w")
    episodes = [
        [
            RobotSetup("a", SWARM, (0.5, 0.5, 0.0), (3.9, 3.9), scenario=0, time_budget=3.0),
            RobotSetup("b", SWARM, (2.5, 0.5, 0.0), (0.5, 3.5), scenario=1),  # hits the box
        ],
        [RobotSetup("a", SWARM, (1.0, 2.0, 0.0), (1.5, 2.0), scenario=2)],
    ]
    rec = _record(world, episodes)
    assert rec.n_episodes == 2
    rec.save(tmp_path / "bag", SWARM, {"genome": "g.json"})
    log = read_episode_bag(tmp_path / "bag")
    assert log.world == world and recording_world(log) == world
    assert log.metadata["genome"] == "g.json"
    setups = episode_setups(log)
    # exact starts and goals; a budget left to the profile is written down resolved
    assert [[(x.name, x.start, x.goal, x.scenario) for x in ep] for ep in setups] == [
        [(x.name, x.start, x.goal, x.scenario) for x in ep] for ep in episodes
    ]
    assert setups[0][0].time_budget == 3.0
    assert setups[1][0].time_budget == SWARM.time_budget((1.0, 2.0), (1.5, 2.0))
    runs = recorded_episodes(log)
    assert [(r.episode, r.setup.name, r.outcome) for r in runs] == [
        (0, "a", "timed_out"), (1, "a", "reached"), (0, "b", "collided")
    ]
    a0, a1, b0 = runs
    assert len(a0.scans) == 3 and len(a0.odometry) == 4 and len(a0.commands) == 3
    assert a0.odometry[-1].pose[0] == pytest.approx(0.5 + 3 * 0.08)
    assert a1.odometry[0].pose[:2] == (1.0, 2.0)
    assert all(r.stamp_ns >= a1.odometry[0].stamp_ns for r in a1.scans)
    assert b0.odometry[-1].pose[0] + SWARM.length / 2 <= 3.0


def test_world_json_round_trip_and_bad_metadata() -> None:
    world = World(4.0, np.array([[1.0 / 3.0, 0.1, 2.0, 0.7]]), name="x")
    assert world_from_json(world_to_json(world)) == world
    with pytest.raises(FileFormatError, match="bad world"):
        world_from_json({"size": -1, "obstacles": []})
    log = EpisodeLog("swarm", (), {"recorder": "other"})
    with pytest.raises(FileFormatError, match="not a simulator recording"):
        episode_setups(log, "x.bag")
    log = EpisodeLog("swarm", (), {"recorder": "mentor-sim-recording", "version": 1,
                                    "episodes": [{"robots": [{"name": "a"}]}]})
    with pytest.raises(FileFormatError, match="bad episode metadata"):
        episode_setups(log, "x.bag")
