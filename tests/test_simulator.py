"""The reference simulator: episode events, multi-robot stepping, wire rounding, agreement
with the trainer's batched episodes."""

from __future__ import annotations

import math

import numpy as np
import pytest
from profiles_support import UGV_STRAIGHT

from mentor_core.controller.episodes import run_episodes
from mentor_core.evolution.genome import minimal_genome
from mentor_core.evolution.innovation import InnovationTracker
from mentor_core.evolution.network import FeedForwardNetwork
from mentor_core.runtime.planner import GenomePlanner
from mentor_core.runtime.simulator import (
    ReferenceSimulator,
    RobotSetup,
    decision_limit,
    run_reference_episode,
    scenario_for,
    start_fault,
    wire_decision,
    wire_pose,
    wire_ranges,
)
from mentor_core.sim.robots import RobotProfile, get_profile
from mentor_core.sim.scenarios import training_scenarios
from mentor_core.sim.world import World

UGV = get_profile("ugv")
SWARM = get_profile("swarm")


def _planner(profile: RobotProfile, seed: int = 3) -> GenomePlanner:
    tracker = InnovationTracker(profile.n_inputs + 3)
    genome = minimal_genome(profile.n_inputs, 2, tracker, np.random.default_rng(seed))
    return GenomePlanner(genome, profile)


def test_wire_values_are_what_ros_messages_carry() -> None:
    r = wire_ranges([0.1, 0.7, 0.6], SWARM)
    assert r[0] == float(np.float32(0.1)) and r[0] != 0.1
    assert math.isinf(r[1]) and r[2] == float(np.float32(0.6))
    x, y, th = wire_pose((1.0, 2.0, 0.3))
    assert (x, y) == (1.0, 2.0) and abs(th - 0.3) < 1e-12
    assert wire_decision(0.5, 1.5, 1.0) == (0.5, 1.5)
    dth, ds = wire_decision(0.1, 0.3, 0.7)
    assert dth == pytest.approx(0.1, abs=1e-15) and ds == pytest.approx(0.3, abs=1e-15)


def test_scenario_assignment_and_decision_limit() -> None:
    assert [scenario_for(e, 0, 1, 3) for e in range(4)] == [0, 1, 2, 0]
    assert [scenario_for(0, j, 2, 5) for j in range(2)] == [0, 1]
    assert [scenario_for(1, j, 2, 5, first=1) for j in range(2)] == [3, 4]
    assert decision_limit(33.9, 1.0) == 34 and decision_limit(0.0, 1.0) == 0
    with pytest.raises(ValueError):
        decision_limit(math.inf, 1.0)
    with pytest.raises(ValueError):
        scenario_for(0, 0, 1, 0)


def test_events_of_an_episode() -> None:
    world = World(10.0, np.array([[6.0, 0.0, 7.0, 10.0]]))
    sim = ReferenceSimulator(world, 1.0)
    events, rejected = sim.start(
        [
            RobotSetup("crash", UGV, (4.0, 2.0, 0.0), (9.0, 2.0), scenario=0),
            RobotSetup("goal", UGV, (1.0, 8.0, 0.0), (3.0, 8.0), scenario=1),
            RobotSetup("late", UGV, (1.0, 5.0, math.pi / 2), (5.0, 5.0), 2, time_budget=1.5),
            RobotSetup("there", UGV, (2.0, 2.0, 0.0), (2.5, 2.0), scenario=3),
        ]
    )
    assert rejected == []
    assert [(e.robot, e.kind) for e in events] == [
        ("crash", "started"), ("goal", "started"), ("late", "started"), ("there", "started"),
        ("there", "reached"),
    ]
    assert sim.active == ("crash", "goal", "late")
    decisions = {"crash": (0.0, 2.0), "goal": (0.0, 2.0), "late": (0.0, 0.1)}
    events = sim.step(decisions)
    assert [(e.robot, e.kind, e.scenario) for e in events] == [
        ("crash", "collided", 0), ("goal", "reached", 1)
    ]
    goal = sim.state("goal")
    assert goal.steps == 1 and 0.0 < goal.time_used < 1.0  # the arriving share of dt
    crash = sim.state("crash")
    assert crash.pose[0] <= 6.0 - 0.15 and crash.time_used == 1.0
    assert [e.kind for e in sim.step({"late": (0.0, 0.1)})] == ["timed_out"]
    late = sim.state("late")
    assert (late.steps, late.allowed, late.time_used) == (2, 2, 2.0)
    assert sim.done and sim.active == ()
    with pytest.raises(KeyError):
        sim.state("nobody")


def test_rejections_and_bad_decisions() -> None:
    world = World(5.0, np.array([[2.0, 2.0, 3.0, 3.0]]))
    sim = ReferenceSimulator(world, 1.0)
    events, rejected = sim.start(
        [
            RobotSetup("a", SWARM, (1.0, 1.0, 0.0), (4.0, 4.0)),
            RobotSetup("b", SWARM, (1.02, 1.0, 0.0), (4.0, 1.0)),  # overlaps a
            RobotSetup("c", UGV, (2.0, 1.9, 0.0), (4.0, 1.0), scenario=7),  # body in the box
        ]
    )
    assert [e.robot for e in events] == ["a"]
    assert [(r.robot, r.scenario) for r in rejected] == [("b", -1), ("c", 7)]
    assert "overlaps" in rejected[1].reason
    assert start_fault(world, RobotSetup("c", UGV, (2.0, 1.9, 0.0), (4.0, 1.0)))
    assert not start_fault(world, RobotSetup("c", SWARM, (2.0, 1.9, 0.0), (4.0, 1.0)))
    with pytest.raises(ValueError, match="no decision"):
        sim.step({})
    with pytest.raises(ValueError, match="not finite"):
        sim.step({"a": (math.nan, 0.01)})
    assert sim.state("a").steps == 0  # nothing moved
    with pytest.raises(ValueError, match="decides every"):
        ReferenceSimulator(world, 0.5).start([RobotSetup("a", SWARM, (1.0, 1.0, 0.0), (4.0, 4.0))])
    with pytest.raises(ValueError, match="unique"):
        sim.start([RobotSetup("a", SWARM, (1.0, 1.0, 0.0), (4.0, 4.0))] * 2)


def test_robots_see_and_hit_each_other() -> None:
    sim = ReferenceSimulator(World(10.0), 1.0)
    sim.start(
        [
            RobotSetup("a", UGV_STRAIGHT, (3.0, 5.0, 0.0), (9.0, 9.0)),
            RobotSetup("b", SWARM, (5.0, 5.0, math.pi / 2), (5.0, 9.0)),
        ]
    )
    # a's front pair (x = 3.15, y = 5 -+ 0.0375) sees b's side face at x = 4.97
    np.testing.assert_allclose(sim.observe("a")[:2], [1.82, 1.82], atol=1e-12)
    # robots move in name order: a runs into b where b stands, then b moves on
    events = sim.step({"a": (0.0, 2.0), "b": (0.0, 0.05)})
    assert [(e.robot, e.kind) for e in events] == [("a", "collided")]
    assert sim.pose("a")[0] + 0.15 <= 4.97
    np.testing.assert_allclose(sim.pose("b"), (5.0, 5.05, math.pi / 2), atol=1e-12)
    assert sim.active == ("b",)


@pytest.mark.parametrize("robot", ["ugv", "swarm"])
def test_reference_episode_agrees_with_the_trainers_episodes(robot: str) -> None:
    """Same genome, same scenarios: pymunk reference with wire rounding vs the batched
    engine in float64, alone in the world: same outcomes, trajectories within 1e-6 m."""
    profile = get_profile(robot)
    planner = _planner(profile)
    scenarios = training_scenarios(profile, 0, n=4)
    net = FeedForwardNetwork.from_genome(planner.genome)
    batch = run_episodes(scenarios, profile, lambda x, _r: net.activate(x), backend="numpy")
    for i, sc in enumerate(scenarios):
        setup = RobotSetup("r", profile, sc.start, sc.goal, i)
        trace = run_reference_episode(sc.world, [setup], {"r": planner.decide})["r"]
        steps = int(batch.steps[i])
        assert trace.steps == steps
        outcome = "reached" if batch.reached[i] else "collided" if batch.collided[i] else (
            "timed_out"
        )
        assert trace.outcome == outcome
        assert trace.time_used == pytest.approx(batch.time_used[i], abs=1e-6)
        np.testing.assert_allclose(
            trace.poses[:, :2], batch.trajectories[i, : steps + 1, :2], atol=1e-6
        )
        assert trace.ranges.shape == (steps, profile.n_sensors)
        assert trace.decisions.shape == (steps, 2)


def test_reference_episode_is_deterministic() -> None:
    planner = _planner(UGV, seed=5)
    sc = training_scenarios(UGV, 1, n=1)[0]
    setups = [RobotSetup("r", UGV, sc.start, sc.goal, 0)]
    first = run_reference_episode(sc.world, setups, {"r": planner.decide})["r"]
    second = run_reference_episode(sc.world, setups, {"r": planner.decide})["r"]
    np.testing.assert_array_equal(first.poses, second.poses)
    np.testing.assert_array_equal(first.decisions, second.decisions)
    assert run_reference_episode(sc.world, [], {}) == {}
