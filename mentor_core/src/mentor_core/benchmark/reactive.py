"""The reactive baseline ``vfh``: a vector-field-histogram planner on the range readings.

VFH+ (Ulrich & Borenstein 1998) picks, once per decision, the steering direction of least
cost among the directions its histogram shows free, cost

    g(phi) = mu_1 |phi - beta| + mu_2 |phi| + mu_3 |phi - phi_prev|

(angles wrapped, body frame: ``beta`` the goal's bearing, ``0`` the heading, ``phi_prev`` the
previous decision's direction), VFH+'s weights ``mu = (5, 2, 2)`` (goal first, then little
turning, then consistency). The histogram here is made of the robot's ``k`` readings and,
as VFH's histogram grid keeps what was seen, of the hit points of its last ``MEMORY`` (10)
decisions carried along by odometry (:class:`mentor_core.benchmark.control.PointMemory`;
only for a robot whose sensors do not see all round, the Swarm-Robot). A direction ``phi``
(72, every 5 deg) is free when the corridor the body sweeps along it, a circumscribed
radius wide, holds no seen point nearer than ``SAFE`` (2.5) half body diagonals plus a step
(nor the goal's distance), and a sensor faces within 45 deg of it
(:func:`mentor_core.benchmark.control.free_corridor`); unseen is not free. The robot turns
towards the chosen direction by at most ``h`` and steps ``min(step_max, free range - margin,
goal distance)`` (margin: the clearance rule's), the smallest step while the direction lies
more than ``h`` off; with no free direction it turns on the spot towards the most open one,
the way it began turning while it stays blocked.

No memory of where it has been, like the evolved networks: a local minimum (a U-shaped trap,
a room whose door faces away from the goal) holds it, as it holds any reactive planner.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from mentor_core.benchmark.control import (
    Odometry,
    PointMemory,
    free_corridor,
    goal_polar,
    hit_points,
    outputs_for,
    readings,
)
from mentor_core.sim.episode import Policy
from mentor_core.sim.kinematics import wrap_angle
from mentor_core.sim.robots import RobotProfile
from mentor_core.sim.world import Scenario

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
WEIGHTS = (5.0, 2.0, 2.0)  # VFH+'s mu_1 (goal), mu_2 (heading), mu_3 (previous direction)
SAFE = 2.5  # half body diagonals a free direction keeps, besides one step
MEMORY = 10  # decisions whose hit points a robot remembers
DIRECTIONS = np.linspace(-np.pi, np.pi, 72, endpoint=False)


def reactive_policy(scenarios: Sequence[Scenario], profile: RobotProfile) -> Policy:
    """A VFH+ policy for robot ``i`` on ``scenarios[i]`` (module docstring)."""
    odometry = Odometry(np.zeros((len(scenarios), 3)))
    memory = PointMemory(len(scenarios), profile, MEMORY)
    previous = np.zeros(len(scenarios))  # last direction, body frame after the last turn
    spin = np.zeros(len(scenarios))  # the way a blocked robot turns: -1, +1 (0: not blocked)
    h = profile.heading_change_max
    safe = SAFE * profile.half_diagonal + profile.step_max
    margin = profile.clearance_margin or 0.0

    def policy(inputs: FloatArray, robots: IntArray) -> FloatArray:
        u = readings(inputs, profile)
        bearing, distance = goal_polar(inputs, profile)
        m = len(robots)
        seen = memory.add_and_get(robots, odometry.poses[robots], hit_points(u, profile))
        free = free_corridor(u, np.broadcast_to(DIRECTIONS, (m, DIRECTIONS.size)), profile,
                             seen)  # fmt: skip
        ok = free >= np.minimum(safe, distance[:, None] + profile.half_diagonal)
        w1, w2, w3 = WEIGHTS
        cost = (w1 * np.abs(wrap_angle(DIRECTIONS[None, :] - bearing[:, None]))
                + w2 * np.abs(DIRECTIONS[None, :])
                + w3 * np.abs(wrap_angle(DIRECTIONS[None, :] - previous[robots, None])))
        cost = np.where(ok, cost, np.inf)
        best = np.argmin(cost, axis=1)
        blocked = ~np.isfinite(cost[np.arange(m), best])
        # blocked: turn towards the most open direction, and on the way already begun when
        # the last decision was blocked too (no dithering between two walls)
        opening = DIRECTIONS[np.argmax(free, axis=1)]
        keep = blocked & (spin[robots] != 0.0)
        opening = np.where(keep, spin[robots] * np.pi, opening)
        spin[robots] = np.where(blocked, np.where(keep, spin[robots], np.sign(opening)), 0.0)
        chosen = np.where(blocked, opening, DIRECTIONS[best])
        dtheta = np.clip(chosen, -h, h)
        ahead = free_corridor(u, 0.5 * dtheta, profile, seen)
        step = np.minimum(np.minimum(profile.step_max, ahead - margin), distance)
        aligned = np.abs(chosen) <= h
        ds = np.where(blocked | ~aligned, profile.step_min, step)
        previous[robots] = chosen - dtheta
        outputs = outputs_for(dtheta, ds, profile)
        odometry.advance(robots, outputs, inputs, profile)
        return outputs

    return policy
