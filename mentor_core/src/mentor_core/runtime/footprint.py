"""A robot's footprint given as Nav2 gives it, as the box the planner keeps clear.

Nav2 takes a robot's shape as ``footprint``, a polygon in the base frame written
``"[[x, y], [x, y], ...]"`` (m), or as ``robot_radius`` where the footprint is ''. A profile's
body is a box centred on the base frame (``length`` along x, ``width`` along y): its collision
guard, its plan's clearance and the goal checks keep that box clear. :func:`footprint_box` is
the smallest such box that holds the polygon (or the circle), so a footprint never shrinks
what is kept clear below the robot's real shape. The network's sensors stay where they were
trained: only what is kept clear changes.
"""

from __future__ import annotations

import math
from dataclasses import replace

import yaml

from mentor_core.sim.robots import RobotProfile

Box = tuple[float, float]


def footprint_box(footprint: str, robot_radius: float = 0.0) -> Box | None:
    """``(length, width)`` (m) of the box about the base frame holding Nav2's ``footprint``
    polygon, or where it is '' a circle of ``robot_radius``; None where both are unset (''
    and 0: the profile's body). ValueError (one line) for a malformed polygon or radius."""
    text = footprint.strip()
    if not text:
        if not (math.isfinite(robot_radius) and robot_radius >= 0.0):
            raise ValueError(f"robot_radius must be a number >= 0 m, got {robot_radius}")
        return (2.0 * robot_radius, 2.0 * robot_radius) if robot_radius > 0.0 else None
    try:
        points = yaml.safe_load(text)
        xy = [(float(p[0]), float(p[1])) for p in points if len(p) == 2]
    except (yaml.YAMLError, TypeError, ValueError, IndexError):
        xy = []
    if len(xy) < 3 or len(xy) != len(points) or not all(map(math.isfinite, sum(xy, ()))):
        raise ValueError(f"footprint {text!r} is not a polygon [[x, y], [x, y], [x, y], ...] "
                         "of three or more finite points (m)")
    length = 2.0 * max(abs(x) for x, _ in xy)
    width = 2.0 * max(abs(y) for _, y in xy)
    if length <= 0.0 or width <= 0.0:
        raise ValueError(f"footprint {text!r} has no area")
    return length, width


def with_footprint(profile: RobotProfile, box: Box | None) -> RobotProfile:
    """``profile`` with its body the box ``(length, width)`` (None: unchanged)."""
    return profile if box is None else replace(profile, length=box[0], width=box[1])


__all__ = ["Box", "footprint_box", "with_footprint"]
