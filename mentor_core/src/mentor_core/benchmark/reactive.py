"""The reactive baseline ``vfh``: a vector-field-histogram planner on the range readings.

VFH+ (Ulrich & Borenstein 1998) picks, once per decision, the steering direction of least
cost among the directions its range readings show free, cost

    g(phi) = mu_1 |phi - beta| + mu_2 |phi| + mu_3 |phi - phi_prev|

(angles wrapped, body frame: ``beta`` the goal's bearing, ``0`` the heading, ``phi_prev`` the
previous decision's direction), VFH+'s weights ``mu = (5, 2, 2)`` (goal first, then little
turning, then consistency). Here the histogram is the robot's ``k`` readings: a direction
``phi`` (72, every 5 deg) is free when the readings within 45 deg of it
(:func:`mentor_core.benchmark.control.free_along`) leave at least ``SAFE`` (2.5) half body
diagonals plus one step, and the goal lies nearer than what they show; where no sensor looks
(behind the Swarm-Robot) nothing counts as free. The robot turns towards the chosen direction
by at most ``h`` and steps ``min(step_max, free range - margin, goal distance)``; with no free
direction it turns on the spot (smallest step) towards the most open one.

Memoryless but for ``phi_prev``, like the evolved networks; a local minimum (a U-shaped trap,
a room whose door faces away from the goal) holds it, as it holds any purely reactive planner.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from mentor_core.benchmark.control import free_along, goal_polar, outputs_for, readings
from mentor_core.sim.episode import Policy
from mentor_core.sim.kinematics import wrap_angle
from mentor_core.sim.robots import RobotProfile
from mentor_core.sim.world import Scenario

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
WEIGHTS = (5.0, 2.0, 2.0)  # VFH+'s mu_1 (goal), mu_2 (heading), mu_3 (previous direction)
SAFE = 2.5  # half body diagonals a free direction keeps, besides one step
DIRECTIONS = np.linspace(-np.pi, np.pi, 72, endpoint=False)


def reactive_policy(scenarios: Sequence[Scenario], profile: RobotProfile) -> Policy:
    """A VFH+ policy for robot ``i`` on ``scenarios[i]`` (module docstring)."""
    previous = np.zeros(len(scenarios))  # last direction, body frame after the last turn
    h = profile.heading_change_max
    safe = SAFE * profile.half_diagonal + profile.step_max
    margin = profile.clearance_margin or 0.0

    def policy(inputs: FloatArray, robots: IntArray) -> FloatArray:
        u = readings(inputs, profile)
        bearing, distance = goal_polar(inputs, profile)
        m = len(robots)
        free = np.stack([free_along(u, np.full(m, phi), profile) for phi in DIRECTIONS], axis=1)
        free = np.nan_to_num(free, nan=0.0)  # unseen is not free
        ok = free >= np.minimum(safe, distance[:, None] + profile.half_diagonal)
        w1, w2, w3 = WEIGHTS
        cost = (w1 * np.abs(wrap_angle(DIRECTIONS[None, :] - bearing[:, None]))
                + w2 * np.abs(DIRECTIONS[None, :])
                + w3 * np.abs(wrap_angle(DIRECTIONS[None, :] - previous[robots, None])))
        cost = np.where(ok, cost, np.inf)
        best = np.argmin(cost, axis=1)
        blocked = ~np.isfinite(cost[np.arange(m), best])
        chosen = np.where(blocked, DIRECTIONS[np.argmax(free, axis=1)], DIRECTIONS[best])
        dtheta = np.clip(chosen, -h, h)
        ahead = np.nan_to_num(free_along(u, 0.5 * dtheta, profile), nan=0.0)
        step = np.minimum(np.minimum(profile.step_max, ahead - margin), distance)
        aligned = np.abs(chosen) <= h
        ds = np.where(blocked | ~aligned, profile.step_min, step)
        previous[robots] = chosen - dtheta
        return outputs_for(dtheta, ds, profile)

    return policy
