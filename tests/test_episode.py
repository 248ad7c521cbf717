"""Episodes: termination, time accounting, trajectories, experience points, several worlds,
the controller's stages."""

from __future__ import annotations

import numpy as np
import pytest
from profiles_support import single_rays

from mentor_core.controller.collision_guard import CollisionGuardStage
from mentor_core.controller.episodes import run_episodes
from mentor_core.controller.rotation_shim import RotationShim
from mentor_core.controller.stage import Stage
from mentor_core.controller.turn_gain import TurnGain
from mentor_core.controller.view_corridor import ViewCorridor
from mentor_core.sim.planner_settings import with_planner
from mentor_core.sim.robots import get_profile
from mentor_core.sim.world import Scenario, World

UGV = get_profile("ugv")  # dt 1 s, goal radius 1 m, ds in [0.1, 2] m, budget 2 d / (1 m/s)
WORLD = World(size=12.0, obstacles=np.array([[6.0, 1.0, 7.0, 3.0]]))
SCENARIOS = [
    Scenario(WORLD, (1.0, 6.0, 0.0), (9.0, 6.0)),   # 0: straight run, 8 m
    Scenario(WORLD, (4.0, 2.0, 0.0), (10.0, 2.0)),  # 1: box in the way
    Scenario(WORLD, (1.0, 10.0, 0.0), (1.0, 2.0)),  # 2: goal behind the left shoulder
]


def straight(inputs: np.ndarray, robots: np.ndarray) -> np.ndarray:
    """Full speed, no turn (outputs 0.5 -> dtheta 0, 1.0 -> ds = step_max)."""
    return np.tile([0.5, 1.0], (len(robots), 1))


def test_outcomes_time_and_trajectories() -> None:
    batch = run_episodes(SCENARIOS, UGV, straight)
    np.testing.assert_array_equal(batch.reached, [True, False, False])
    np.testing.assert_array_equal(batch.collided, [False, True, True])
    np.testing.assert_array_equal(batch.timed_out, [False, False, False])
    np.testing.assert_allclose(batch.time_budget, [16.0, 12.0, 16.0])
    # 0 reaches x = 8 (1 m short of the goal) 0.5 s into its 4th decision
    assert batch.steps[0] == 4
    assert batch.time_used[0] == pytest.approx(3.5, abs=2.0 / 32)
    assert batch.final_distance[0] <= UGV.goal_radius
    np.testing.assert_allclose(batch.time_remaining, [16.0 - batch.time_used[0], 0.0, 0.0])
    # 1 stops short of the box face at x = 6
    assert 5.85 - 2.0 / 32 <= batch.trajectories[1, -1, 0] <= 5.85
    assert batch.trajectories.shape == (3, batch.steps.max() + 1, 3)
    np.testing.assert_array_equal(batch.trajectories[:, 0], [s.start for s in SCENARIOS])
    for i, k in enumerate(batch.steps):  # padded with the final pose
        assert (batch.trajectories[i, k:] == batch.trajectories[i, -1]).all()


def test_experience_points_chain_and_carry_the_actions() -> None:
    batch = run_episodes(SCENARIOS, UGV, straight)
    k = UGV.n_sensors
    for i, points in enumerate(batch.experience):
        assert points.shape == (batch.steps[i], 2 * k + 2)
        np.testing.assert_array_equal(points[1:, :k], points[:-1, k + 2:])  # U(t+1) -> U(t)
        np.testing.assert_allclose(points[:, k:k + 2], np.tile([0.0, 2.0], (len(points), 1)))
        assert (points[:, :k] <= UGV.sensor_range).all() and np.isfinite(points).all()
    # all robots' points in one array, robot by robot: the per-robot arrays read in place
    rows, at = batch.packed_experience()
    assert at.tolist() == [0, *np.cumsum(batch.steps).tolist()]
    for i, points in enumerate(batch.experience):
        assert np.shares_memory(points, rows)
        np.testing.assert_array_equal(rows[at[i] : at[i + 1]], points)


def test_time_out_and_policy_sees_only_active_robots() -> None:
    seen: list[np.ndarray] = []

    def spin(inputs: np.ndarray, robots: np.ndarray) -> np.ndarray:
        assert inputs.shape == (len(robots), UGV.n_inputs)
        seen.append(robots.copy())
        return np.tile([1.0, 0.0], (len(robots), 1))  # half turn, 0.1 m: circles in place

    batch = run_episodes(SCENARIOS[:1] * 3, UGV, spin, time_budgets=[2.0, 5.0, 0.5])
    np.testing.assert_array_equal(batch.steps, [2, 5, 1])
    np.testing.assert_array_equal(batch.timed_out, [True] * 3)
    np.testing.assert_allclose(batch.time_used, [2.0, 5.0, 1.0])
    assert [r.tolist() for r in seen] == [[0, 1, 2], [0, 1], [1], [1], [1]]
    capped = run_episodes(SCENARIOS[:1] * 2, UGV, spin, max_steps=3)
    np.testing.assert_array_equal(capped.steps, [3, 3])


def test_deterministic_and_backends_agree() -> None:
    rng = np.random.default_rng(0)
    weights = rng.normal(size=(UGV.n_inputs, 2))

    def linear(inputs: np.ndarray, robots: np.ndarray) -> np.ndarray:
        return 1.0 / (1.0 + np.exp(-inputs @ weights))

    runs = [run_episodes(SCENARIOS * 4, UGV, linear, backend=b) for b in ("auto", "numpy")]
    runs.append(run_episodes(SCENARIOS * 4, UGV, linear))
    for other in runs[1:]:
        np.testing.assert_array_equal(runs[0].trajectories, other.trajectories)
        np.testing.assert_array_equal(runs[0].time_used, other.time_used)


#: stages that each change a decision, two of them remembering per robot
LAYERS: tuple[Stage, ...] = (ViewCorridor(margin=0.5), TurnGain(gain=0.8),
                             RotationShim(threshold_deg=30), CollisionGuardStage())  # fmt: skip


@pytest.mark.parametrize("stages", [(), LAYERS], ids=["network", "stages"])
def test_several_worlds_give_what_each_world_gives_alone(stages: tuple[Stage, ...]) -> None:
    """Also behind stages that remember per robot: each world's are fresh, and each robot's
    state its own."""
    rng = np.random.default_rng(1)
    weights = rng.normal(size=(UGV.n_inputs, 2))
    seen: list[np.ndarray] = []

    def linear(inputs: np.ndarray, robots: np.ndarray) -> np.ndarray:
        seen.append(robots)
        total = np.zeros((len(robots), 2))
        for j in range(inputs.shape[1]):  # row by row: BLAS may round by batch shape
            total += inputs[:, j, None] * weights[j]
        return 1.0 / (1.0 + np.exp(-total))

    other = World(size=12.0, obstacles=np.array([[2.0, 2.0, 3.0, 9.0]]))
    elsewhere = [
        Scenario(other, (1.0, 6.0, 0.0), (9.0, 6.0)),  # the wall x in [2, 3] is in the way
        Scenario(other, SCENARIOS[2].start, SCENARIOS[2].goal),
    ]
    mixed = [SCENARIOS[0], elsewhere[0], SCENARIOS[1], SCENARIOS[2], elsewhere[1]]
    budgets = [30.0, 20.0, 10.0, 5.0, 40.0]
    batch = run_episodes(mixed, UGV, linear, time_budgets=budgets, stages=stages)
    assert {int(i) for chunk in seen for i in chunk} == set(range(5))  # the caller's indices
    for i, sc in enumerate(mixed):  # robot i alone, in its own world, with its own budget
        alone = run_episodes([sc], UGV, linear, time_budgets=[budgets[i]], stages=stages)
        for name in ("reached", "collided", "timed_out", "time_used", "final_distance", "steps"):
            assert getattr(batch, name)[i] == getattr(alone, name)[0], name
        t = alone.trajectories[0]
        np.testing.assert_array_equal(batch.trajectories[i, : len(t)], t)
        np.testing.assert_array_equal(batch.trajectories[i, len(t) :], t[-1:].repeat(
            batch.trajectories.shape[1] - len(t), axis=0))
        np.testing.assert_array_equal(batch.experience[i], alone.experience[0])
    rows, at = batch.packed_experience()  # several worlds: packed in robot order, copied
    for i, points in enumerate(batch.experience):
        np.testing.assert_array_equal(rows[at[i] : at[i + 1]], points)
    with pytest.raises(ValueError):
        run_episodes([], UGV, straight)


def test_a_clearance_margin_stops_a_robot_a_margin_short_of_the_wall_it_sees() -> None:
    # full 2 m steps straight at the box face x = 6 from x = 4 (scenario 1, front edge at
    # 4.15): without a margin the robot hits the face (test above); with a 0.1 m margin its
    # first step is the 1.85 m its front pair sees along its heading less the margin, and then
    # it stands (step_min 0) a margin short of the face until its decisions run out (single
    # rays: the shipped front beams also see the face straight ahead, at 1.85 m)
    guarded = with_planner(single_rays(UGV), step_min=0.0, clearance_margin=0.1)
    batch = run_episodes([SCENARIOS[1]], guarded, straight, max_steps=6)
    assert not batch.collided[0] and batch.timed_out[0]
    np.testing.assert_allclose(batch.trajectories[0, 1:, 0] + UGV.length / 2, 5.9)
    ds = np.concatenate(batch.experience)[:, UGV.n_sensors + 1]
    np.testing.assert_allclose(ds, [1.75, 0, 0, 0, 0, 0], atol=1e-12)


def test_start_inside_the_goal_radius_is_reached_without_a_decision() -> None:
    batch = run_episodes([Scenario(WORLD, (3.0, 6.0, 0.0), (3.5, 6.0))], UGV, straight)
    assert batch.reached[0] and batch.steps[0] == 0 and batch.time_used[0] == 0.0
    assert batch.experience[0].shape == (0, 2 * UGV.n_sensors + 2)
