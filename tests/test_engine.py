"""Batched stepper: free motion, stopping before a collision, stopping at the goal."""

from __future__ import annotations

import numpy as np
import pytest

from mentor_core.sim.collision import robot_collides, sample_counts
from mentor_core.sim.engine import BatchEngine
from mentor_core.sim.kinematics import arc_samples, unicycle_arc
from mentor_core.sim.robots import get_profile
from mentor_core.sim.sensors import sensor_readings
from mentor_core.sim.world import World

UGV = get_profile("ugv")  # goal radius 1 m
WORLD = World(size=12.0, obstacles=np.array([[6.0, 1.0, 7.0, 3.0]]))
STARTS = np.array([
    [2.0, 10.0, 0.0],   # 0: open space, goal far away
    [4.0, 2.0, 0.0],    # 1: box face 1.85 m ahead of the front
    [2.0, 6.0, 0.0],    # 2: goal 2.5 m ahead
    [9.0, 9.0, 1.0],    # 3: inactive
])
GOALS = np.array([[11.0, 11.0], [11.0, 2.0], [4.5, 6.0], [0.5, 0.5]])


def _engine() -> BatchEngine:
    engine = BatchEngine(WORLD, UGV)
    engine.reset(STARTS, GOALS)
    return engine


def test_one_step_of_every_kind() -> None:
    engine = _engine()
    dth = np.array([0.3, 0.0, 0.0, 1.0])
    ds = np.array([1.5, 2.0, 2.0, 2.0])
    result = engine.step(dth, ds, np.array([True, True, True, False]))
    np.testing.assert_array_equal(result.collided, [False, True, False, False])
    np.testing.assert_array_equal(result.reached, [False, False, True, False])
    # free robot: exactly the arc's end; inactive robot: untouched
    np.testing.assert_array_equal(engine.poses[0], unicycle_arc(STARTS[:1], dth[:1], ds[:1])[0])
    np.testing.assert_array_equal(engine.poses[3], STARTS[3])
    assert result.fraction[0] == 1.0 and result.fraction[3] == 0.0
    # collided robot: stopped at the last free sample; the next one collides
    n = int(sample_counts(0.0, 2.0, UGV))
    samples = arc_samples(STARTS[1:2], 0.0, 2.0, n)[0]
    stop = int(np.flatnonzero((samples == engine.poses[1]).all(axis=1))[0])
    assert not robot_collides(samples[stop:stop + 1], UGV, WORLD)[0]
    assert robot_collides(samples[stop + 1:stop + 2], UGV, WORLD)[0]
    assert result.fraction[1] == pytest.approx(stop / n)
    # reached robot: the first sample within the goal radius (1.5 m on from x = 2)
    assert engine.goal_distance()[2] <= UGV.goal_radius
    assert engine.goal_distance()[2] > UGV.goal_radius - 2.0 / n - 1e-12
    assert 0.0 < result.fraction[2] < 1.0
    assert result.fraction[2] * 2.0 == pytest.approx(engine.poses[2, 0] - 2.0)


def test_observe_matches_sensor_readings() -> None:
    engine = _engine()
    np.testing.assert_array_equal(engine.observe(), sensor_readings(STARTS, UGV, WORLD))
    np.testing.assert_array_equal(engine.observe([2, 0]),
                                  sensor_readings(STARTS[[2, 0]], UGV, WORLD))


def test_backends_give_the_same_steps() -> None:
    results = []
    for backend in ("numpy", "auto"):
        engine = BatchEngine(WORLD, UGV, backend=backend)  # type: ignore[arg-type]
        engine.reset(STARTS, GOALS)
        step_rng = np.random.default_rng(1)
        for _ in range(5):
            engine.step(step_rng.uniform(-np.pi, np.pi, 4), step_rng.uniform(0.1, 2.0, 4),
                        np.ones(4, dtype=bool))
        results.append(engine.poses.copy())
    np.testing.assert_array_equal(*results)


def test_poses_are_read_only_and_bad_input_raises() -> None:
    engine = _engine()
    with pytest.raises(ValueError):
        engine.poses[0, 0] = 1.0
    with pytest.raises(ValueError, match="shape"):
        engine.step(np.zeros(3), np.zeros(4), np.ones(4, dtype=bool))
    with pytest.raises(ValueError, match="finite"):
        engine.step(np.full(4, np.nan), np.ones(4), np.ones(4, dtype=bool))
    with pytest.raises(ValueError):
        engine.reset(np.zeros((2, 3)), np.zeros((3, 2)))
