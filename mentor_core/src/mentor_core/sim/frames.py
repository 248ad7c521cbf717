"""Frame and angle conventions of MENTOR's ROS side (REP-103 units, REP-105 frames).

``map`` is the arena frame; ``odom`` the odometry frame (the simulator places it at a fixed
pose in ``map``, identity by default: :mod:`mentor_core.sim.transforms`). Headings (yaw, rad,
counter-clockwise about +z) travel as quaternions ``(x, y, z, w)``: :func:`yaw_to_quaternion`
and back with :func:`quaternion_to_yaw`. The bags and the node packages fill their messages
with these same numbers.
"""

from __future__ import annotations

import math
from typing import Final

MAP_FRAME: Final = "map"
ODOM_FRAME: Final = "odom"


def yaw_to_quaternion(theta: float) -> tuple[float, float, float, float]:
    """Quaternion ``(x, y, z, w)`` of a rotation by ``theta`` (rad) about +z."""
    half = 0.5 * float(theta)
    return (0.0, 0.0, math.sin(half), math.cos(half))


def quaternion_to_yaw(x: float, y: float, z: float, w: float) -> float:
    """Yaw (rad, wrapped to ``(-pi, pi]``) of a quaternion; roll and pitch are ignored."""
    yaw = math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))
    if x == 0.0 and y == 0.0:
        # pure yaw: this form is exact to a few ulp, also near +-pi
        if w < 0.0:
            z, w = -z, -w
        yaw = 2.0 * math.atan2(z, w)
    return math.pi if yaw <= -math.pi else yaw
