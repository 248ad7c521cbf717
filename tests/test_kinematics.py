"""Unicycle arc kinematics: closed forms, the straight-line limit, and arc sampling."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from mentor_core.sim.kinematics import (
    arc_fraction_poses,
    arc_samples,
    to_body,
    unicycle_arc,
    wrap_angle,
)

finite = st.floats(-10.0, 10.0, allow_nan=False)


def test_wrap_angle_range_and_fixed_points() -> None:
    a = np.array([0.0, np.pi, -np.pi, 3 * np.pi, -3 * np.pi, 0.5, 2 * np.pi + 0.5, -0.5])
    w = wrap_angle(a)
    np.testing.assert_allclose(w, [0.0, np.pi, np.pi, np.pi, np.pi, 0.5, 0.5, -0.5], atol=1e-12)
    assert np.all(w > -np.pi) and np.all(w <= np.pi)


def test_straight_line_when_heading_does_not_change() -> None:
    end = unicycle_arc([[1.0, 2.0, np.pi / 6]], [0.0], [2.0])
    np.testing.assert_allclose(end, [[1.0 + np.sqrt(3.0), 3.0, np.pi / 6]], atol=1e-15)


def test_quarter_circle_of_unit_radius() -> None:
    end = unicycle_arc([[0.0, 0.0, 0.0]], [np.pi / 2], [np.pi / 2])
    np.testing.assert_allclose(end, [[1.0, 1.0, np.pi / 2]], atol=1e-15)
    back = unicycle_arc([[0.0, 0.0, 0.0]], [-np.pi], [np.pi])  # half circle to the right
    np.testing.assert_allclose(back, [[0.0, -2.0, np.pi]], atol=1e-15)


@settings(derandomize=True, max_examples=200, deadline=None)
@given(finite, finite, st.floats(-np.pi, np.pi), st.floats(-np.pi, np.pi), st.floats(0.01, 3.0))
def test_matches_curvature_closed_form(
    x: float, y: float, theta: float, dtheta: float, ds: float
) -> None:
    end = unicycle_arc([[x, y, theta]], [dtheta], [ds])[0]
    if abs(dtheta) > 1e-3:
        k = dtheta / ds
        expected = (
            x + (np.sin(theta + dtheta) - np.sin(theta)) / k,
            y - (np.cos(theta + dtheta) - np.cos(theta)) / k,
        )
    else:  # the closed form loses digits here; the third-order expansion does not (its
        # error ds dtheta^3 / 24 stays below 1e-9 m, where the second order's ds dtheta^2 / 6
        # did not at dtheta = 1e-3)
        expected = (
            x + ds * (np.cos(theta) - dtheta * np.sin(theta) / 2 - dtheta**2 * np.cos(theta) / 6),
            y + ds * (np.sin(theta) + dtheta * np.cos(theta) / 2 - dtheta**2 * np.sin(theta) / 6),
        )
    np.testing.assert_allclose(end[:2], expected, atol=1e-9)
    assert abs(np.sin(end[2] - (theta + dtheta))) < 1e-12 and -np.pi < end[2] <= np.pi


def test_continuous_through_zero_turn() -> None:
    tiny = unicycle_arc([[0.0, 0.0, 0.3]] * 3, [-1e-13, 0.0, 1e-13], [1.5] * 3)
    np.testing.assert_allclose(tiny[0], tiny[1], atol=1e-12)
    np.testing.assert_allclose(tiny[2], tiny[1], atol=1e-12)


def test_arc_samples_endpoints_and_equal_spacing() -> None:
    poses = np.array([[1.0, 1.0, 0.2], [3.0, -1.0, -2.0]])
    dth, ds = np.array([1.3, -0.7]), np.array([2.0, 0.5])
    s = arc_samples(poses, dth, ds, 8)
    assert s.shape == (2, 9, 3)
    np.testing.assert_array_equal(s[:, 0, :2], poses[:, :2])
    np.testing.assert_array_equal(s[:, -1], unicycle_arc(poses, dth, ds))
    chords = np.hypot(*np.diff(s[..., :2], axis=1).transpose(2, 0, 1))
    np.testing.assert_allclose(chords, chords[:, :1] * np.ones((1, 8)), rtol=1e-12)
    np.testing.assert_allclose(np.diff(np.unwrap(s[..., 2], axis=1), axis=1),
                               np.repeat(dth[:, None] / 8, 8, axis=1), atol=1e-12)


def test_arc_fraction_poses_broadcasts() -> None:
    f = np.array([0.0, 0.25, 1.0])
    out = arc_fraction_poses(np.array([0.0, 0.0, 0.0]), 0.0, 4.0, f)
    np.testing.assert_allclose(out, [[0, 0, 0], [1, 0, 0], [4, 0, 0]], atol=1e-15)


def test_compiled_arc_agrees_with_its_numpy_twin() -> None:
    from mentor_core.sim import kinematics

    rng = np.random.default_rng(7)
    n = 20_000
    args = [rng.uniform(-20, 20, n), rng.uniform(-20, 20, n), rng.uniform(-np.pi, np.pi, n),
            rng.uniform(-np.pi, np.pi, n), rng.uniform(0.0, 2.0, n)]  # fmt: skip
    args[3][:100] = 0.0  # straight moves
    compiled = unicycle_arc(np.c_[args[0], args[1], args[2]], args[3], args[4])
    twin = np.empty((n, 3))
    kinematics._arc_numpy(*args, twin)
    loop = np.empty((n, 3))
    kinematics._arc_loop(*args, loop)  # the same source, run by Python
    np.testing.assert_allclose(compiled[:, :2], twin[:, :2], rtol=0, atol=1e-12)
    heading = np.remainder(compiled[:, 2] - twin[:, 2] + np.pi, 2 * np.pi) - np.pi
    assert np.abs(heading).max() <= 1e-12
    np.testing.assert_allclose(compiled, loop, rtol=0, atol=1e-12)
    assert (compiled[:, 2] > -np.pi).all() and (compiled[:, 2] <= np.pi).all()
    np.testing.assert_array_equal(compiled[:100, 2], wrap_angle(args[2][:100]))


def test_to_body_by_hand() -> None:
    """A point ahead, to the left and behind a robot facing north, in its body frame."""
    theta = np.full(3, np.pi / 2)
    v = np.array([[0.0, 2.0], [-1.0, 0.0], [0.0, -3.0]])  # north, west, south (map)
    np.testing.assert_allclose(to_body(theta, v), [[2.0, 0.0], [0.0, 1.0], [-3.0, 0.0]],
                               atol=1e-12)  # fmt: skip
    # a heading of zero leaves a vector as it is; the rotation keeps lengths
    np.testing.assert_array_equal(to_body([0.0], [[1.5, -2.0]]), [[1.5, -2.0]])
    rng = np.random.default_rng(0)
    w = rng.normal(size=(20, 2))
    np.testing.assert_allclose(np.hypot(*to_body(rng.uniform(-4, 4, 20), w).T), np.hypot(*w.T))
