"""The predictive guard (mentor_core.controller.predictive_guard, issue 59, E097): a reading
that closes faster than the robot's own motion explains is a moving obstacle, predicted
nearer; a wall the robot drives at is not."""

from __future__ import annotations

import numpy as np

from mentor_core.controller.deployment import load_deployment
from mentor_core.controller.predictive_guard import PredictiveGuard
from mentor_core.sim.robots import get_profile

ONE = np.zeros(1, dtype=np.int64)


def _readings(front: float) -> np.ndarray:
    r = np.full((1, 8), np.inf)
    r[0, :2] = front
    return r


def test_an_obstacle_coming_closer_is_predicted_nearer() -> None:
    profile = get_profile("ugv")  # period 1 s, rated 1 m/s
    run = PredictiveGuard(horizon=1.0).start(1, profile, None)
    goal = np.array([[10.0, 0.0]])
    run.readings(ONE, _readings(3.0), np.array([[0.0, 0.0, 0.0]]), goal)
    # the robot stood still; the front readings fell by 1 m in a period: 1 m/s towards it,
    # so a period on they read 2 - 1 = 1 m
    run.readings(ONE, _readings(2.0), np.array([[0.0, 0.0, 0.0]]), goal)
    predicted = run.predicted[0]  # type: ignore[attr-defined]
    assert np.allclose(predicted[:2], 1.0)
    assert np.isinf(predicted[2:]).all()


def test_a_wall_driven_at_is_not_moving() -> None:
    profile = get_profile("ugv")
    run = PredictiveGuard().start(1, profile, None)
    goal = np.array([[10.0, 0.0]])
    run.readings(ONE, _readings(3.0), np.array([[0.0, 0.0, 0.0]]), goal)
    run.readings(ONE, _readings(2.5), np.array([[0.5, 0.0, 0.0]]), goal)  # drove 0.5 m
    assert np.isinf(run.predicted[0]).all()  # type: ignore[attr-defined]


def test_it_is_a_plugin_stage_in_place_of_the_guard() -> None:
    settings = ["stages.collision_guard=null", 'stages.predictive_guard={plugin: '
                '"mentor_core.controller.predictive_guard:PredictiveGuard", horizon: 3}']
    stages = load_deployment("shipped", "ugv", settings)[0].build()
    assert [s.name for s in stages] == ["rotation_shim", "predictive_guard"]
    assert load_deployment("shipped", "ugv")[0].build()[-1].name == "collision_guard"
