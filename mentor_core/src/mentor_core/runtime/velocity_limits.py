"""A robot's velocity and acceleration limits, applied to a planner's command.

A network decides an arc: a turn ``dtheta`` and a path length ``ds`` per control period, which
the planner sends as ``(v, omega) = (ds, dtheta) / dt``. A robot slower than the one it was
trained for (a TurtleBot3 Burger tops out at 0.22 m/s) cannot drive it in one period, so
:func:`limited_velocity` first scales both speeds by one factor, until each is within its
limit: the robot then drives the same arc, more slowly (as Nav2's Regulated Pure Pursuit slows
along its path rather than leave it). Then each speed's change since the last command is
clipped to its acceleration limit times the period, as Nav2's velocity smoother does. A limit
of 0 (or infinity) is none. Names and units follow Nav2's controller parameters:
``max_vel_x`` (m/s), ``max_vel_theta`` (rad/s), ``acc_lim_x`` (m/s^2), ``acc_lim_theta``
(rad/s^2).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

Velocity = tuple[float, float]


@dataclass(frozen=True)
class VelocityLimits:
    """Speed and acceleration limits (module docstring); 0 or infinity: none."""

    max_vel_x: float = 0.0
    max_vel_theta: float = 0.0
    acc_lim_x: float = 0.0
    acc_lim_theta: float = 0.0

    def __post_init__(self) -> None:
        for name, value in vars(self).items():
            if math.isnan(value) or value < 0.0:
                raise ValueError(f"{name} must be >= 0 (0: no limit), got {value}")

    @property
    def any(self) -> bool:
        """Whether any limit is set."""
        return any(_set(v) for v in vars(self).values())


def _set(limit: float) -> bool:
    return 0.0 < limit < math.inf


def limited_velocity(
    command: Velocity, limits: VelocityLimits, previous: Velocity = (0.0, 0.0), dt: float = 1.0
) -> Velocity:
    """``command`` ``(v, omega)`` within ``limits``: both speeds scaled by one factor to their
    speed limits, then each change from ``previous`` clipped to its acceleration limit over
    ``dt`` s (module docstring). ValueError for a non-finite command or ``dt <= 0``."""
    v, w = float(command[0]), float(command[1])
    if not (math.isfinite(v) and math.isfinite(w)):
        raise ValueError(f"non-finite command ({v}, {w})")
    if not dt > 0.0:
        raise ValueError(f"dt must be positive, got {dt}")
    scale = 1.0
    if _set(limits.max_vel_x) and abs(v) > limits.max_vel_x:
        scale = min(scale, limits.max_vel_x / abs(v))
    if _set(limits.max_vel_theta) and abs(w) > limits.max_vel_theta:
        scale = min(scale, limits.max_vel_theta / abs(w))
    v, w = v * scale, w * scale
    if _set(limits.acc_lim_x):
        step = limits.acc_lim_x * dt
        v = min(max(v, previous[0] - step), previous[0] + step)
    if _set(limits.acc_lim_theta):
        step = limits.acc_lim_theta * dt
        w = min(max(w, previous[1] - step), previous[1] + step)
    return v, w


__all__ = ["Velocity", "VelocityLimits", "limited_velocity"]
