"""The signed clearance of a robot body's poses: how far each is from colliding.

The physics-agreement tests keep their random poses away from touching configurations, where
two exact geometries may round to different verdicts; this margin (the separating axis gaps of
:mod:`mentor_core.sim.collision`, largest per box, least over boxes and walls) tells them how
far a pose is from one.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from mentor_core.sim.collision import FloatArray, box_arrays

if TYPE_CHECKING:
    from mentor_core.sim.robots import RobotProfile
    from mentor_core.sim.world import World


def separation_margin(poses: ArrayLike, profile: RobotProfile, world: World) -> FloatArray:
    """Signed clearance proxy (m) per pose ``(n,)``: negative iff the body collides.

    For each box the largest separating-axis gap ``|d . axis| - radii``, for each wall the
    signed gap to it; the minimum over boxes and walls. Zero marks a touching configuration,
    which the physics-agreement tests stay away from.
    """
    p = np.asarray(poses, dtype=np.float64).reshape(-1, 3)
    c = np.cos(p[:, 2])[:, None]
    s = np.sin(p[:, 2])[:, None]
    ac, as_ = np.abs(c), np.abs(s)
    a = 0.5 * float(profile.length)
    b = 0.5 * float(profile.width)
    ex = a * ac + b * as_
    ey = a * as_ + b * ac
    x, y = p[:, 0, None], p[:, 1, None]
    walls = np.minimum(np.minimum(x - ex, world.size - (x + ex)),
                       np.minimum(y - ey, world.size - (y + ey)))[:, 0]
    cx, cy, hx, hy = box_arrays(world.obstacles)
    if cx.shape[0] == 0:
        return np.asarray(walls, dtype=np.float64)
    dx, dy = x - cx, y - cy
    gaps = np.maximum(
        np.maximum(np.abs(dx) - (ex + hx), np.abs(dy) - (ey + hy)),
        np.maximum(np.abs(dx * c + dy * s) - (a + (hx * ac + hy * as_)),
                   np.abs(dy * c - dx * s) - (b + (hx * as_ + hy * ac))),
    )
    return np.asarray(np.minimum(walls, gaps.min(axis=1)), dtype=np.float64)


__all__ = ["separation_margin"]
