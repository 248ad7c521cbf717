"""The one input/output function: network inputs, actions, twists and experience points."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from mentor_core.errors import ConfigError
from mentor_core.sim.observation import (
    action_from_twist,
    actions_from_outputs,
    clearance_limit,
    clip_ranges,
    egocentric_goal,
    experience_point,
    network_inputs,
    signal_gradient,
    twist_from_action,
)
from mentor_core.sim.planner_settings import with_planner
from mentor_core.sim.robots import get_profile

SWARM = get_profile("swarm")
UGV = get_profile("ugv")


def test_ranges_are_clipped_and_inf_becomes_range_max() -> None:
    out = clip_ranges([[0.1, math.inf, 0.9]], SWARM)
    np.testing.assert_array_equal(out, [[0.1, 0.6, 0.6]])


@pytest.mark.parametrize(
    ("ranges", "match"),
    [([[0.1, math.nan, 0.2]], "NaN"), ([[0.1, -0.01, 0.2]], "negative"), ([[0.1, 0.2]], "3")],
)
def test_bad_ranges_raise(ranges: list[list[float]], match: str) -> None:
    with pytest.raises(ValueError, match=match):
        network_inputs(ranges, [(0, 0, 0)], [(1, 1)], SWARM)


def test_network_inputs_layout_and_values() -> None:
    ranges = [[0.2, math.inf, 0.3], [0.6, 0.5, 0.4]]
    poses = [(1.0, 1.0, 3 * math.pi / 2), (2.0, 2.0, -math.pi)]
    goals = [(1.0, 3.0), (2.1, 2.0)]
    x = network_inputs(ranges, poses, goals, SWARM)
    assert x.shape == (2, SWARM.n_inputs)
    np.testing.assert_allclose(x[:, :3], [[0.2, 0.6, 0.3], [0.6, 0.5, 0.4]])
    r = SWARM.goal_radius
    # goal 2 m straight up: (0, R^2 / d^2); goal inside the radius: unit vector
    np.testing.assert_allclose(x[0, 3:5], [0.0, r**2 / 4.0], atol=1e-15)
    np.testing.assert_allclose(x[1, 3:5], [1.0, 0.0])
    np.testing.assert_allclose(x[:, 5], [-math.pi / 2, math.pi])


def test_egocentric_inputs_give_the_goal_bearing_in_the_body_frame_and_the_signal() -> None:
    ego = with_planner(SWARM, input_encoding="egocentric")
    r = SWARM.goal_radius
    ranges = [[0.2, math.inf, 0.3]] * 4
    # heading +y; goal 2 m ahead, 2 m to the left, 2 m behind, and on the robot
    poses = [(1.0, 1.0, math.pi / 2)] * 4
    goals = [(1.0, 3.0), (-1.0, 1.0), (1.0, -1.0), (1.0, 1.0)]
    x = network_inputs(ranges, poses, goals, ego)
    assert x.shape == (4, SWARM.n_inputs)
    np.testing.assert_allclose(x[:, :3], [[0.2, 0.6, 0.3]] * 4)
    np.testing.assert_allclose(
        x[:, 3:], [[1, 0, r / 2], [0, 1, r / 2], [-1, 0, r / 2], [0, 0, 1]], atol=1e-15
    )


@settings(max_examples=50, deadline=None)
@given(
    st.floats(-10, 10), st.floats(-10, 10), st.floats(-math.pi, math.pi),
    st.floats(0.01, 20), st.floats(-math.pi, math.pi), st.floats(-math.pi, math.pi),
)  # fmt: skip
def test_egocentric_goal_is_invariant_to_where_the_map_puts_the_robot(
    x: float, y: float, heading: float, d: float, bearing: float, turn: float
) -> None:
    goal = (x + d * math.cos(heading + bearing), y + d * math.sin(heading + bearing))
    moved = (  # the same situation rotated by ``turn`` about the origin
        (
            x * math.cos(turn) - y * math.sin(turn),
            x * math.sin(turn) + y * math.cos(turn),
            heading + turn,
        ),
        (
            goal[0] * math.cos(turn) - goal[1] * math.sin(turn),
            goal[0] * math.sin(turn) + goal[1] * math.cos(turn),
        ),
    )
    a = egocentric_goal([(x, y, heading)], [goal], 1.0)[0]
    b = egocentric_goal([moved[0]], [moved[1]], 1.0)[0]
    np.testing.assert_allclose(a, b, atol=1e-9)
    np.testing.assert_allclose(a[:2], [math.cos(bearing), math.sin(bearing)], atol=1e-9)
    assert a[2] == pytest.approx(min(1.0, 1.0 / d))


def test_planner_settings_are_checked_and_narrow_the_heading_action() -> None:
    with pytest.raises(ConfigError, match=r"best_genome\.json: input_encoding.*egocentric"):
        with_planner(SWARM, input_encoding="polar", source="run/best_genome.json")
    for bad in (0.0, -1.0, 4.0, True, "1"):
        with pytest.raises(ConfigError, match="heading_change_max"):
            with_planner(SWARM, heading_change_max=bad)
    narrow = with_planner(SWARM, heading_change_max=math.pi / 4)
    assert with_planner(SWARM) == SWARM and narrow.input_encoding == SWARM.input_encoding
    dtheta, _ = actions_from_outputs([[0.0, 0.5], [1.0, 0.5], [0.5, 0.5]], narrow)
    np.testing.assert_allclose(dtheta, [-math.pi / 4, math.pi / 4, 0.0])


def test_a_planner_step_limit_narrows_the_step_and_the_rated_speed() -> None:
    short = with_planner(UGV, step_max=0.5, source="run/best_genome.json")
    assert short.step_max == 0.5 and short.step_min == UGV.step_min
    assert short.rated_speed == pytest.approx(UGV.rated_speed / 4)  # same share of top pace
    assert short.time_budget((1.0, 1.0), (5.0, 4.0)) == pytest.approx(
        4 * UGV.time_budget((1.0, 1.0), (5.0, 4.0))
    )
    _, ds = actions_from_outputs([[0.5, 0.0], [0.5, 1.0]], short)
    np.testing.assert_allclose(ds, [UGV.step_min, 0.5])
    assert with_planner(UGV, step_max=UGV.step_max) == UGV
    for bad in (0.05, 2.5, True, "1"):  # outside [step_min, step_max] of the robot
        with pytest.raises(ConfigError, match=r"best_genome\.json: step_max"):
            with_planner(UGV, step_max=bad, source="run/best_genome.json")


def test_a_planner_step_floor_and_clearance_margin_are_checked() -> None:
    low = with_planner(UGV, step_max=0.5, step_min=0.02, clearance_margin=0.1)
    assert (low.step_min, low.step_max, low.clearance_margin) == (0.02, 0.5, 0.1)
    assert UGV.clearance_margin is None  # the robot file has none: the paper's actions
    for bad in (-0.01, 0.6, True):  # outside [0, the planner's step_max]
        with pytest.raises(ConfigError, match=r"run\.json: step_min"):
            with_planner(UGV, step_max=0.5, step_min=bad, source="run.json")
    for bad in (-0.1, math.inf, math.nan, "0.1"):
        with pytest.raises(ConfigError, match="clearance_margin"):
            with_planner(UGV, clearance_margin=bad)


def test_clearance_limit_keeps_the_margin_to_the_nearest_hit_ahead() -> None:
    # the UGV's sensors face -22.5, 22.5, 67.5, ..., 292.5 deg; turns of at most 45 deg,
    # steps in [0.02, 0.5] m (the shipped UGV configs)
    quarter, c8, c4 = math.pi / 4, math.cos(math.pi / 8), math.cos(math.pi / 4)
    ugv = with_planner(
        UGV, heading_change_max=quarter, step_max=0.5, step_min=0.02, clearance_margin=0.1
    )
    ranges = np.array([[0.4, 0.3, 0.2, 4.0, 4.0, 4.0, 4.0, math.inf]] * 4)
    ranges[2, 1] = 4.0
    ranges[3, :2] = 0.05
    dtheta = np.array([0.0, quarter, -quarter, 0.0])
    expected = [
        0.3 * c8 - 0.1,  # straight on (chord 0): the front pair, 22.5 deg off
        0.2 * c4 - 0.1,  # full left turn (chord 22.5 deg): 67.5 deg is 45 deg off, included
        0.4 - 0.1,  # full right turn: -22.5 deg dead ahead; 22.5 and 292.5 read 4 m
        0.02,  # a wall within the margin leaves step_min
    ]
    np.testing.assert_allclose(clearance_limit(ranges, dtheta, ugv), expected)
    _, ds = actions_from_outputs(
        [[0.5, 1.0], [1.0, 1.0], [0.0, 0.1], [0.5, 1.0]], ugv, ranges
    )  # fmt: skip
    # the limit only shortens a step: the third asks for 0.068 m, under its 0.3 m
    np.testing.assert_allclose(ds, [expected[0], expected[1], 0.02 + 0.48 * 0.1, 0.02])
    free = np.full((1, 8), math.inf)
    assert clearance_limit(free, [0.0], ugv)[0] == 0.5
    with pytest.raises(ValueError, match="range readings"):
        actions_from_outputs([[0.5, 1.0]], ugv)
    np.testing.assert_array_equal(  # without a margin the readings change nothing
        actions_from_outputs([[0.5, 1.0]], UGV, [[0.01] * 8])[1], [UGV.step_max]
    )


def test_gradient_is_the_scaled_gradient_of_one_over_d_outside_the_radius() -> None:
    rng = np.random.default_rng(0)
    p = rng.uniform(0, 10, (50, 2))
    g = rng.uniform(0, 10, (50, 2))
    keep = np.hypot(*(g - p).T) > 1.5
    p, g = p[keep], g[keep]
    eps = 1e-6

    def signal(q: np.ndarray) -> np.ndarray:
        return 1.0 / np.hypot(*(g - q).T)

    fd = np.stack(
        [(signal(p + e) - signal(p - e)) / (2 * eps) for e in (np.array([eps, 0]),
                                                                np.array([0, eps]))],
        axis=1,
    )
    np.testing.assert_allclose(signal_gradient(p, g, 1.0), fd, rtol=1e-5)
    np.testing.assert_array_equal(signal_gradient([(3.0, 4.0)], [(3.0, 4.0)], 1.0), [[0, 0]])


@settings(max_examples=60, deadline=None, derandomize=True)
@given(
    st.tuples(st.floats(-50, 50), st.floats(-50, 50)),
    st.tuples(st.floats(-50, 50), st.floats(-50, 50)),
    st.floats(0.01, 5.0),
)
def test_gradient_is_bounded_and_points_at_the_goal(
    p: tuple[float, float], g: tuple[float, float], radius: float
) -> None:
    grad = signal_gradient([p], [g], radius)[0]
    assert np.hypot(*grad) <= 1.0 + 1e-12
    assert grad @ (np.array(g) - np.array(p)) >= 0.0


def test_actions_from_outputs_map_linearly_and_clip() -> None:
    dtheta, ds = actions_from_outputs([[0, 0], [1, 1], [0.5, 0.5], [-3, 7]], UGV)
    np.testing.assert_allclose(dtheta, [-math.pi, math.pi, 0.0, -math.pi])
    np.testing.assert_allclose(ds, [0.1, 2.0, 1.05, 2.0])
    with pytest.raises(ValueError, match="NaN"):
        actions_from_outputs([[0.5, math.nan]], UGV)
    with pytest.raises(ValueError, match="shape"):
        actions_from_outputs([[0.5, 0.5, 0.5]], UGV)


def test_twist_round_trip() -> None:
    wz, vx = twist_from_action(np.array([0.5, -1.0]), np.array([0.04, 0.08]), 2.0)
    np.testing.assert_allclose(wz, [0.25, -0.5])
    np.testing.assert_allclose(vx, [0.02, 0.04])
    dtheta, ds = action_from_twist(wz, vx, 2.0)
    np.testing.assert_allclose(dtheta, [0.5, -1.0])
    np.testing.assert_allclose(ds, [0.04, 0.08])
    assert float(twist_from_action(math.pi, 2.0, 1.0)[0]) == math.pi
    with pytest.raises(ValueError, match="control period"):
        twist_from_action(0.1, 0.1, 0.0)


def test_experience_point_concatenates_clipped_state_and_action() -> None:
    v = experience_point([[0.1, math.inf, 0.2]], [[0.3, 0.05]], [[0.9, 0.4, 0.5]], SWARM)
    np.testing.assert_allclose(v, [[0.1, 0.6, 0.2, 0.3, 0.05, 0.6, 0.4, 0.5]])
    assert v.shape == (1, 2 * SWARM.n_sensors + 2)
    with pytest.raises(ValueError, match="NaN"):
        experience_point([[0.1, 0.1, 0.2]], [[0.3, 0.05]], [[math.nan, 0.4, 0.5]], SWARM)
    with pytest.raises(ValueError, match="actions"):
        experience_point([[0.1, 0.1, 0.2]], [[0.3]], [[0.1, 0.4, 0.5]], SWARM)
