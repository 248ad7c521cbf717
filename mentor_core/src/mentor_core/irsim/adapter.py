"""The conversions between IR-SIM and the planner: its lidar's scan in, a velocity command out.

**Scan.** IR-SIM's ``lidar2d`` (``robot.get_lidar_scan()``) gives a LaserScan's fields and a
``valid`` flag per ray: a ray that hit something within ``[range_min, range_max]``. Where it
is not valid, IR-SIM writes the range clipped into the limits (``range_max`` for a ray that
hit nothing), which a ROS driver would not: :func:`scan_data` writes them as REP-117 does,
so that :func:`mentor_core.sim.scan_adapter.readings_from_scan` reads them as the planner
node reads a real lidar's scan:

- a valid ray: its range;
- an invalid ray at or below ``range_min`` (something nearer than the lidar measures):
  ``-inf``;
- any other invalid ray (nothing within ``range_max``): ``+inf``.

The lidar's pose on the body is its ``offset`` ``[x, y, yaw]`` (:func:`lidar_mount`).

**Command.** A decision ``(dtheta, ds)`` (rad, m) held for the control period ``dt`` (s) is
the Twist ``(v, w) = (ds / dt, dtheta / dt)`` (m/s, rad/s;
:func:`mentor_core.sim.observation.twist_from_action`), IR-SIM's action ``[[v], [w]]`` for a
differential drive (:func:`velocity_command`), as the planner node sends it on ``cmd_vel``.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from mentor_core.sim import observation
from mentor_core.sim.scan_adapter import LaserScanData, LidarMount
from mentor_core.sim.transforms import Transform2D

FloatArray = NDArray[np.float64]


def scan_data(scan: Mapping[str, Any]) -> LaserScanData:
    """IR-SIM's scan dict as a LaserScan's fields (module docstring). ValueError for a dict
    without the fields, or whose ``valid`` does not match its ``ranges``."""
    try:
        ranges = np.asarray(scan["ranges"], dtype=np.float64).reshape(-1)
        valid = np.asarray(scan["valid"], dtype=bool).reshape(-1)
        low, high = float(scan["range_min"]), float(scan["range_max"])
        angle_min, increment = float(scan["angle_min"]), float(scan["angle_increment"])
    except (KeyError, TypeError, ValueError) as err:
        raise ValueError(f"not an IR-SIM lidar2d scan: {err}") from None
    if valid.shape != ranges.shape:
        raise ValueError(f"scan: {valid.size} valid flags for {ranges.size} ranges")
    out = np.where(valid, ranges, np.where(ranges <= low, -np.inf, np.inf))
    return LaserScanData(angle_min, increment, low, high, out)


def lidar_mount(offset: Sequence[float] | None) -> LidarMount:
    """The lidar's pose on the body from IR-SIM's ``offset`` ``[x, y, yaw]`` (m, m, rad;
    None: at the body's centre, facing forward)."""
    if offset is None:
        return LidarMount()
    x, y, yaw = (float(v) for v in np.asarray(offset, dtype=np.float64).reshape(-1)[:3])
    return LidarMount(Transform2D(x, y, yaw))


def velocity_command(dtheta: float, ds: float, period: float) -> tuple[float, float]:
    """``(v, w)`` (m/s, rad/s) of a decision ``(dtheta, ds)`` (rad, m) held for ``period``
    s (module docstring)."""
    w, v = observation.twist_from_action(dtheta, ds, period)
    return float(v), float(w)


def irsim_action(command: tuple[float, float]) -> FloatArray:
    """IR-SIM's action ``[[v], [w]]`` of a differential drive for ``(v, w)``."""
    return np.array([[command[0]], [command[1]]], dtype=np.float64)


__all__ = ["irsim_action", "lidar_mount", "scan_data", "velocity_command"]
