"""Velocity and acceleration limits on a planner's command (runtime/velocity_limits.py):
issue 56, point 3."""

from __future__ import annotations

import math

import pytest

from mentor_core.runtime.velocity_limits import VelocityLimits, limited_velocity


def test_no_limits_change_nothing() -> None:
    assert limited_velocity((1.0, -1.57), VelocityLimits()) == (1.0, -1.57)
    assert not VelocityLimits().any and VelocityLimits(max_vel_x=0.22).any


def test_speeds_are_scaled_together_so_the_arc_is_kept() -> None:
    burger = VelocityLimits(max_vel_x=0.22, max_vel_theta=2.84)
    v, w = limited_velocity((1.0, 0.5), burger)
    assert v == pytest.approx(0.22) and w == pytest.approx(0.11)
    assert w / v == pytest.approx(0.5)  # the same curvature: the same arc, slower
    v, w = limited_velocity((0.1, -5.68), burger)  # the turn is the binding limit
    assert (v, w) == (pytest.approx(0.05), pytest.approx(-2.84))
    assert limited_velocity((-1.0, 0.0), burger) == (pytest.approx(-0.22), 0.0)  # a step back too


def test_accelerations_are_clipped_over_the_period() -> None:
    limits = VelocityLimits(acc_lim_x=2.5, acc_lim_theta=3.2)
    assert limited_velocity((1.0, 2.0), limits, previous=(0.0, 0.0), dt=0.1) == (
        pytest.approx(0.25), pytest.approx(0.32))
    assert limited_velocity((0.0, 0.0), limits, previous=(0.5, -1.0), dt=0.1) == (
        pytest.approx(0.25), pytest.approx(-0.68))


def test_bad_limits_and_commands_are_refused() -> None:
    with pytest.raises(ValueError, match="max_vel_x"):
        VelocityLimits(max_vel_x=-1.0)
    with pytest.raises(ValueError, match="acc_lim_theta"):
        VelocityLimits(acc_lim_theta=math.nan)
    with pytest.raises(ValueError, match="non-finite"):
        limited_velocity((math.nan, 0.0), VelocityLimits())
    with pytest.raises(ValueError, match="dt"):
        limited_velocity((0.0, 0.0), VelocityLimits(), dt=0.0)
