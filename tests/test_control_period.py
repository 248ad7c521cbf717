"""A planner's control period (``control_period``; the robot file's 1 s in the paper): the same
decisions in less time, within what the robot can drive, the same in training, in files and
in the benchmark."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from mentor_core.controller.episodes import run_episodes
from mentor_core.errors import ConfigError
from mentor_core.runtime.planner import planner_profile
from mentor_core.sim.planner_settings import with_planner
from mentor_core.sim.robots import RobotProfile, get_profile
from mentor_core.sim.world import Scenario, World
from mentor_core.training.config import TrainerConfig
from mentor_core.training.trainer import train

QUARTER = math.pi / 4


def ugv_planner(period: float | None) -> RobotProfile:
    return with_planner(get_profile("ugv"), input_encoding="egocentric",
                        heading_change_max=QUARTER, step_max=0.5, step_min=0.02,
                        clearance_margin=0.2, control_period=period)  # fmt: skip


def test_a_shorter_period_is_a_faster_planner_within_the_robot() -> None:
    robot = get_profile("ugv")
    slow, fast = ugv_planner(None), ugv_planner(0.5)
    assert slow.control_period == robot.control_period == 1.0
    assert fast.control_period == 0.5
    # rated twice as fast: a budget from the rated speed holds the same decisions
    assert fast.rated_speed == pytest.approx(2.0 * slow.rated_speed)
    for goal in ((4.0, 1.0), (11.0, 11.0)):  # under the cap, and cut by it
        decisions = [p.time_budget((1.0, 1.0), goal) / p.control_period for p in (slow, fast)]
        assert decisions[1] == pytest.approx(decisions[0]) or decisions[1] > decisions[0]
    assert fast.time_budget((1.0, 1.0), (4.0, 1.0)) == pytest.approx(
        0.5 * slow.time_budget((1.0, 1.0), (4.0, 1.0)))
    # 0.5 m and 45 deg in 0.25 s are the robot's top pace (2 m/s) and turn rate (180 deg/s)
    assert ugv_planner(0.25).control_period == 0.25


@pytest.mark.parametrize(
    ("settings", "message"),
    [({"step_max": 0.5, "control_period": 0.2}, "too short for steps of up to 0.5 m"),
     ({"step_max": 0.5, "control_period": 0.5}, "too short for turns of up to 180 deg"),
     ({"control_period": 2.0}, r"must be a number in \(0, 1.0\] s"),
     ({"control_period": 0.0}, "must be a number"),
     ({"control_period": "fast"}, "must be a number")],
)
def test_a_period_the_robot_cannot_drive_is_refused(settings: dict[str, object], message: str
                                                    ) -> None:
    with pytest.raises(ConfigError, match=message) as err:
        with_planner(get_profile("ugv"), **settings, source="c.yaml")  # type: ignore[arg-type]
    assert "control_period" in str(err.value) and "c.yaml" in str(err.value)


def test_the_same_decisions_take_half_the_time() -> None:
    """A policy that only reads its inputs drives the same poses at either period; the
    budget's seconds hold twice the decisions at 0.5 s."""
    world = World(12.0, np.array([[5.0, 2.0, 5.3, 10.0]]))
    scenarios = [Scenario(world, (1.0, 1.0 + 2 * i, 0.3 * i), (10.0, 10.0 - i)) for i in range(4)]

    def policy(inputs: np.ndarray, robots: np.ndarray) -> np.ndarray:
        # steer by the goal's bearing (egocentric sin, cos), slow near the nearest reading
        turn = 0.5 + 0.5 * np.arctan2(inputs[:, 9], inputs[:, 8]) / math.pi
        return np.column_stack([turn, np.clip(inputs[:, :8].min(axis=1) / 2.0, 0.0, 1.0)])

    slow = run_episodes(scenarios, ugv_planner(None), policy, time_budgets=30.0)
    fast = run_episodes(scenarios, ugv_planner(0.5), policy, time_budgets=15.0)
    assert np.array_equal(slow.trajectories, fast.trajectories)
    assert np.array_equal(slow.steps, fast.steps)
    assert np.array_equal(slow.reached, fast.reached) and np.array_equal(slow.collided,
                                                                          fast.collided)
    np.testing.assert_allclose(fast.time_used, 0.5 * slow.time_used)
    assert not slow.reached.all()  # some run out of their 30 decisions ...
    longer = run_episodes(scenarios, ugv_planner(0.5), policy, time_budgets=30.0)
    assert (longer.steps > slow.steps).any()  # ... and drive on in the fast planner's 30 s


def _run(tmp: Path, extra: dict[str, object]) -> tuple[dict[str, object], dict[str, object]]:
    config = TrainerConfig.from_dict({
        "robot": "ugv", "generations": 2, "stage1_generations": 1, "n_scenarios": 3,
        "input_encoding": "egocentric", "heading_change_max_deg": 45, "step_max": 0.5,
        "evolution": {"population_size": 6}, **extra})  # fmt: skip
    train(config, tmp, seed=3)
    saved = json.loads((tmp / "best_genome.json").read_text())
    metadata = saved.pop("metadata")
    return saved, metadata


def test_training_at_half_the_period_in_half_the_time_trains_the_same_genome(
    tmp_path: Path,
) -> None:
    genome, metadata = _run(tmp_path / "a", {"time_budget": 20.0})
    fast_genome, fast_metadata = _run(tmp_path / "b", {"time_budget": 10.0,
                                                       "control_period": 0.5})
    assert fast_genome == genome
    assert fast_metadata["objectives"] == metadata["objectives"]
    assert "control_period" not in metadata  # written as before when not set
    assert fast_metadata["control_period"] == 0.5
    robot = get_profile("ugv")
    assert planner_profile(robot, fast_metadata).control_period == 0.5
    assert planner_profile(robot, metadata).control_period == robot.control_period
    with pytest.raises(ConfigError, match="control_period"):
        planner_profile(robot, {**fast_metadata, "control_period": 0.1}, "g.json")
