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
from mentor_core.runtime.sim_session import (
    ContinuousConfig,
    Outcome,
    SessionConfig,
    SimSession,
    Tick,
)
from mentor_core.runtime.simulator import ReferenceSimulator, wire_ranges
from mentor_core.runtime.wiring import Wiring
from mentor_core.sim.lidar import LidarSpec
from mentor_core.sim.robots import get_profile
from mentor_core.sim.transforms import Transform2D
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

    def lidar(self, robot: str, ranges: Any, time_ns: int) -> None:
        self.calls.append(("lidar", robot, time_ns, len(ranges)))

    def warning(self, text: str) -> None:
        self.calls.append(("warning", text))

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


# -------------------------------------------------------------------- issue 16: goals, frames,
# lidar, continuous mode


def test_a_users_goal_is_the_one_the_robot_is_judged_against() -> None:
    """Failed before: the simulator judged "reached" against its own scenario goal."""
    port = Port()
    s = _session(port, auto_advance=False)
    s.tick()
    s.tick()
    port.take()
    user = (1.7, 1.0)  # behind the robot's start (1.5, 0.5), far from the scenario's goal
    assert s.give_goal(["robot_0"], "map", user) == user
    calls = port.take()
    assert ("goal", "robot_0", user, 0) in calls
    assert ("info", "robot_0: new goal (1.700, 1.000)") in calls
    s.command("robot_0", (math.pi / 2, 0.08))  # a quarter turn left, 8 cm: nearer the goal
    for _ in range(20):
        if s.outcomes:
            break
        s.command("robot_0", (0.0, 0.08))
    (out,) = s.outcomes
    assert out.event == "reached"
    assert math.hypot(out.pose[0] - user[0], out.pose[1] - user[1]) <= SWARM.goal_radius


def test_goals_outside_the_arena_or_in_unknown_frames_are_refused() -> None:
    port = Port()
    s = _session(port, auto_advance=False)
    s.tick()
    s.tick()
    port.take()
    assert s.give_goal(["robot_0"], "map", (2.0, 30.0)) is None
    assert port.take() == [("warning", "goal (2.000, 30.000) in map lies outside the known "
                                       "area [0, 4] x [0, 4] m; refused")]
    assert s.give_goal(["robot_0"], "world", (1.0, 1.0)) is None
    assert "no transform from frame 'world'" in port.take()[0][1]
    # a goal relative to the robot: 0.5 m ahead of it
    goal = s.give_goal(["robot_0"], "robot_0/base_link", (0.5, 0.0))
    assert goal == pytest.approx((2.0, 0.5))


def test_odometry_in_an_odom_frame_apart_from_map() -> None:
    port = Port()
    offset = Transform2D(1.0, -0.5, 0.3)
    s = _session(port, wiring=Wiring(map_to_odom=offset), auto_advance=False)
    s.tick()
    s.tick()
    (obs,) = port.take("observation")
    assert obs[3] == pytest.approx(offset.inverse().apply_pose(SCENARIOS[0].start))
    assert s.frames().lookup("map", "robot_0/base_link").as_tuple() == pytest.approx(
        SCENARIOS[0].start
    )
    # a goal given in odom is the same point in map
    goal_odom = offset.inverse().apply_point((3.0, 3.0))
    assert s.give_goal(["robot_0"], "odom", goal_odom) == pytest.approx((3.0, 3.0))


def test_robots_can_wait_for_a_goal_and_start_with_it(tmp_path: Path) -> None:
    port = Port()
    bag = tmp_path / "rec"
    s = _session(port, wait_for_goals=True, episodes=1, record=str(bag))
    assert s.tick() == Tick("start")
    calls = port.take()
    assert not [c for c in calls if c[0] in ("goal", "event")]  # no goal, no started event
    assert s.tick() == Tick("observe")
    assert [c[0] for c in port.take()] == ["odometry"]  # visible, owes no answer
    assert not s.accepts("robot_0") and s.tick() == Tick("idle")
    user = (1.5, 1.2)
    s.give_goal(["robot_0"], "map", user)
    assert s.tick() == Tick("observe")  # it starts at the next step boundary
    calls = port.take()
    assert [c[0] for c in calls[:3]] == ["goal", "event", "observation"]
    assert calls[1][2:] == ("started", 0, 0, user)
    s.command("robot_0", (math.pi / 2, 0.05))
    while not s.finished:
        s.command("robot_0", (0.0, 0.08))
    assert s.outcomes[0].event == "reached"
    (run,) = recorded_episodes(read_episode_bag(bag), bag)
    assert run.setup.goal == user and run.setup.start == SCENARIOS[0].start
    assert run.setup.time_budget == SWARM.time_budget(SCENARIOS[0].start[:2], user)


def test_the_lidar_scan_goes_out_before_each_observation() -> None:
    port = Port()
    wiring = Wiring(lidar=LidarSpec(90, range_max=3.0))
    s = _session(port, wiring=wiring, auto_advance=False)
    s.tick()
    port.take()
    s.tick()
    assert port.take() == [("lidar", "robot_0", 0, 90),
                           ("observation", "robot_0", 0, SCENARIOS[0].start, HOLD)]


def test_continuous_mode_holds_each_command_until_it_times_out() -> None:
    port = Port()
    cont = ContinuousConfig(physics_step=0.1, scan_period=0.2, odom_period=0.1,
                            command_timeout=0.35)
    s = _session(port, continuous=cont, real_time_factor=1.0, auto_advance=False)
    assert not s.lockstep and s.continuous
    assert s.tick() == Tick("start")
    assert [c[0] for c in port.take()][-1] == "observation"
    assert s.command("robot_0", (0.0, 0.05), received=(0.5, 0.0))  # 0.5 m/s ahead
    xs, warnings = [], []
    for _ in range(8):
        assert s.tick() == Tick("step")
        s.step()
        calls = port.take()
        warnings += [c for c in calls if c[0] == "warning"]
        kinds = [c for c in calls if c[0] in ("observation", "odometry")]
        assert len(kinds) == 1  # a scan with odometry every 0.2 s, odometry alone between
        xs.append(kinds[0][3][0])
    steps = np.diff([SCENARIOS[0].start[0], *xs])
    # held for 0.35 s of sim time (the command came at t = 0): 4 steps of 5 cm, then it stops
    np.testing.assert_allclose(steps[:4], 0.05, atol=1e-12)
    np.testing.assert_allclose(steps[4:], 0.0, atol=0)
    assert warnings == [("warning", "robot_0: no cmd_vel for the command timeout; stopping")]
    assert s.time_ns == 800_000_000
