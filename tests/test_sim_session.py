"""The simulator node's run without ROS: episodes, lockstep and real-time stepping, resends
and timeouts, the reset, outcomes and the recording (:class:`SimSession`)."""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from mentor_core.files.bags import read_episode_bag
from mentor_core.runtime.lockstep import HOLD
from mentor_core.runtime.recording import recorded_episodes
from mentor_core.runtime.scenario_plan import ScenarioSource
from mentor_core.runtime.sim_session import Outcome, SessionConfig, SimSession, Tick
from mentor_core.runtime.simulator import ReferenceSimulator, wire_ranges
from mentor_core.sim.robots import get_profile
from mentor_core.sim.world import Scenario, World

SWARM = get_profile("swarm")
S = 1_000_000_000
WORLD = World(4.0, np.array([[2.0, 0.0, 2.5, 1.5], [0.0, 3.0, 1.0, 4.0]]), name="test")
SCENARIOS = (
    Scenario(WORLD, (1.5, 0.5, 0.0), (3.5, 3.5)),
    Scenario(WORLD, (3.0, 2.5, math.pi), (0.5, 1.5)),
)
SOURCE = ScenarioSource(WORLD, SCENARIOS, "test world")
STEP = (0.0, 0.05)  # (dtheta, ds): straight ahead, 5 cm


class Port:
    """Everything a session outputs, in order."""

    def __init__(self) -> None:
        self.calls: list[tuple[Any, ...]] = []

    def clock(self, time_ns: int) -> None:
        self.calls.append(("clock", time_ns))

    def goal(self, robot: str, goal: tuple[float, float], time_ns: int) -> None:
        self.calls.append(("goal", robot, tuple(goal), time_ns))

    def event(
        self, robot: str, kind: str, scenario: int, time_ns: int, goal: Any
    ) -> None:
        self.calls.append(("event", robot, kind, scenario, time_ns, goal))

    def observation(
        self, robot: str, ranges: Any, pose: Any, twist: Any, time_ns: int
    ) -> None:
        self.calls.append(("observation", robot, time_ns, tuple(pose), tuple(twist)))

    def odometry(self, robot: str, pose: Any, twist: Any, time_ns: int) -> None:
        self.calls.append(("odometry", robot, time_ns, tuple(pose), tuple(twist)))

    def info(self, text: str) -> None:
        self.calls.append(("info", text))

    def error(self, text: str) -> None:
        self.calls.append(("error", text))

    def take(self, *kinds: str) -> list[tuple[Any, ...]]:
        """The calls of ``kinds`` (all: none given) since the last take."""
        out = [c for c in self.calls if not kinds or c[0] in kinds]
        self.calls.clear()
        return out


class Wall:
    """A wall clock the test moves."""

    def __init__(self) -> None:
        self.now = 0.0

    def __call__(self) -> float:
        return self.now


def _session(
    port: Port, wall: Wall | None = None, robots: tuple[str, ...] = ("robot_0",), **kw: Any
) -> SimSession:
    config = SessionConfig(robots=tuple((n, SWARM) for n in robots), **kw)
    return SimSession(SOURCE, config, port, wall or Wall())


def test_lockstep_episodes_step_on_every_answer() -> None:
    port = Port()
    s = _session(port, time_limit=2.0, episodes=2)
    assert s.dt == SWARM.control_period == 1.0 and s.lockstep and s.episode == -1
    assert s.tick() == Tick("start")
    goal = SCENARIOS[0].goal
    assert port.take() == [
        ("clock", 0),
        ("goal", "robot_0", goal, 0),
        ("event", "robot_0", "started", 0, 0, goal),
        ("info", "episode 0: robot_0 scenario 0"),
    ]
    assert not s.accepts("robot_0")  # the observation goes out at the next tick
    assert not s.command("robot_0", STEP)
    assert s.tick() == Tick("observe")
    assert port.take() == [("observation", "robot_0", 0, SCENARIOS[0].start, HOLD)]
    assert s.accepts("robot_0") and not s.accepts("robot_1")
    assert s.command("robot_0", STEP)
    calls = port.take()
    assert [c[:3] for c in calls] == [("clock", 1 * S), ("observation", "robot_0", 1 * S)]
    assert calls[1][3][0] == pytest.approx(1.55) and calls[1][4] == (0.05, 0.0)
    assert s.command("robot_0", STEP)  # the answer to the new observation: the last step
    calls = port.take()
    assert [c[:3] for c in calls] == [
        ("clock", 2 * S), ("event", "robot_0", "timed_out"), ("info", "robot_0: timed_out "
        "after 2 decisions (2.00 s), scenario 0"), ("odometry", "robot_0", 2 * S),
    ]
    assert calls[-1][4] == HOLD and s.episodes_done == 1 and s.time_ns == 2 * S
    assert s.outcomes == [
        Outcome(0, "robot_0", "timed_out", 0, 2, 2.0, calls[-1][3]),
    ]
    # the next episode starts one control period later, with the next scenario
    assert s.tick() == Tick("start") and s.time_ns == 3 * S and s.episode == 1
    assert port.take("event") == [
        ("event", "robot_0", "started", 1, 3 * S, SCENARIOS[1].goal)
    ]
    # a reset ends the robot still driving (timed out); here that is the last episode
    assert s.reset() == (True, "episode 1 ended; all episodes are done")
    assert [c[:3] for c in port.take("event", "odometry")] == [
        ("event", "robot_0", "timed_out"), ("odometry", "robot_0", 3 * S)
    ]
    assert s.finished and s.episodes_done == 2 and s.active == ()
    assert s.reset() == (False, "all 2 episodes are done")
    assert s.tick() == Tick("idle") and port.take() == []


def test_lockstep_resends_then_holds_the_silent_robot_still() -> None:
    port, wall = Port(), Wall()
    s = _session(port, wall, answer_timeout=1.0, resend_period=0.1)
    s.tick()
    s.tick()
    port.take()
    wall.now = 0.05
    assert s.tick() == Tick("wait", ("robot_0",))
    wall.now = 0.15
    assert s.tick() == Tick("resend", ("robot_0",), 0.15)
    wall.now = 1.5
    assert s.tick() == Tick("timeout", ("robot_0",))
    assert port.take() == []  # the node says so first, then steps
    s.step()
    calls = port.take()
    assert [c[:3] for c in calls] == [("clock", 1 * S), ("observation", "robot_0", 1 * S)]
    assert calls[1][3] == SCENARIOS[0].start  # held still


def test_lockstep_waits_for_every_driving_robot() -> None:
    port = Port()
    s = _session(port, robots=("a", "b"), auto_advance=False)
    s.tick()
    s.tick()
    assert s.active == ("a", "b")
    port.take()
    assert s.command("b", STEP) and port.take() == [] and s.time_ns == 0
    assert not s.command("b", STEP)  # b has answered this observation
    assert s.command("a", HOLD) and s.time_ns == 1 * S
    assert [c[1] for c in port.take("observation")] == ["a", "b"]


def test_real_time_steps_with_the_latest_commands() -> None:
    port = Port()
    s = _session(port, real_time_factor=10.0, time_limit=2.0, episodes=1)
    assert not s.lockstep
    assert s.tick() == Tick("start")  # the first observation goes out at once
    assert [c[0] for c in port.take()] == ["clock", "goal", "event", "info", "observation"]
    assert s.tick() == Tick("step", ("robot_0",))  # nothing sent yet: it would hold still
    assert s.command("robot_0", (0.0, 0.01)) and s.command("robot_0", STEP)  # the later counts
    assert not s.command("robot_1", STEP)
    assert s.tick() == Tick("step")
    s.step()
    assert port.take("observation")[0][4] == (0.05, 0.0)
    assert s.tick() == Tick("step", ("robot_0",))
    s.step()
    assert s.finished and s.tick() == Tick("idle")
    assert [o.steps for o in s.outcomes] == [2]


def test_skipped_scenarios_and_robots_that_cannot_start() -> None:
    port = Port()
    bad = Scenario(WORLD, (1.98, 0.5, 0.0), (3.5, 3.5))  # centre outside, body in the box
    source = ScenarioSource(WORLD, (bad, SCENARIOS[1]), "overlap")
    config = SessionConfig(robots=(("robot_0", SWARM),), auto_advance=False)
    s = SimSession(source, config, port, Wall())
    (line,) = s.rejections
    assert "scenario 0 skipped for robot_0 (swarm)" in line
    assert port.take() == [("error", f"overlap: {line}")]
    s.tick()
    assert ("info", "episode 0: robot_0 scenario 1") in port.take()
    # two robots given the same start: the second cannot start
    clash = ScenarioSource(WORLD, (SCENARIOS[0],), "one scenario")
    config = SessionConfig(robots=(("a", SWARM), ("b", SWARM)), auto_advance=False)
    s = SimSession(clash, config, port, Wall())
    s.tick()
    assert len(s.rejections) == 1 and "episode 0: b cannot start scenario 0" in s.rejections[0]
    assert s.active == ("a",) and ("error", s.rejections[0]) in port.take()


def test_recording_holds_what_was_output_and_received(tmp_path: Path) -> None:
    port = Port()
    bag = tmp_path / "rec"
    s = _session(
        port, time_limit=2.0, episodes=1, record=str(bag), record_metadata={"note": 1}
    )
    assert s.recorder is not None
    s.tick()
    s.tick()
    s.command("robot_0", STEP, received=(0.05, 0.0))
    s.command("robot_0", HOLD)  # refused as invalid: holds still, not recorded
    assert s.finished and bag.is_dir()
    assert ("info", f"recorded 1 episodes: {bag}") in port.take()
    log = read_episode_bag(bag)
    assert log.metadata["note"] == 1
    (run,) = recorded_episodes(log, bag)
    assert run.outcome == "timed_out" and len(run.scans) == 2 and len(run.odometry) == 3
    assert [(c.stamp_ns, c.linear_x, c.angular_z) for c in run.commands] == [(0, 0.05, 0.0)]
    sim = ReferenceSimulator(WORLD, 1.0)
    sim.start(s.plan.setups(0))
    want = wire_ranges(sim.observe("robot_0"), SWARM)
    assert run.scans[0].ranges == tuple(want)
    s.save_recording()  # once only
    assert port.take() == []


def test_a_recording_that_cannot_be_written_is_an_error_line(tmp_path: Path) -> None:
    port = Port()
    blocker = tmp_path / "file"
    blocker.write_text("not a bag")
    s = _session(port, time_limit=1.0, episodes=1, record=str(blocker))
    s.tick()
    s.tick()
    s.command("robot_0", STEP)
    assert s.finished
    errors = port.take("error")
    assert len(errors) == 1 and "recording not written" in errors[0][1]


def test_robots_must_share_a_control_period() -> None:
    slow = dataclasses.replace(SWARM, control_period=2.0)
    config = SessionConfig(robots=(("a", SWARM), ("b", slow)))
    with pytest.raises(ValueError, match="different periods"):
        SimSession(SOURCE, config, Port(), Wall())
