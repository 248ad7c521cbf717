"""A view corridor: the network sees only what lies near its way to the goal.

Not in the paper; off by default (the planner setting ``RobotProfile.view_margin``, None). A
reading whose hit point lies farther than the margin ``m`` from the segment from the robot to
its goal is shown to the network as nothing seen (the sensor's range)::

    r_i' = sensor_range   if  min over the rays j of sensor i of  dist(h_ij, [0, g]) > m
    r_i' = r_i            otherwise

with ``h_ij = p_i + r_i (cos a_ij, sin a_ij)`` the point at the reading's range along ray ``j``
of sensor ``i`` (mount ``p_i``, facing ``a_ij``, every ray of a beam, since the reading may come
from any of them) and ``[0, g]`` the segment from the robot's origin to the goal, both in the
body frame. On a plan on the scan map (:mod:`mentor_core.navigation.scan_map`) the goal a
network sees is the carrot, and the plan already keeps clear of what the robot has read; a
network that sees every reading swerves from every wall it reads. With the corridor it
reacts only to what stands in the way of the carrot (in training: of the goal or, in a
guided scenario, the waypoint it is shown). The collision guard
(:mod:`mentor_core.sim.collision_guard`) and the clearance limit still read every reading.

Chosen on the benchmark's validation split for the shipped Swarm-Robot planners (0.1 m, in
training and at deployment; experiment E064, "A view corridor" and "Trained with
the view corridor"); it cost the UGV's planners goals either way, whose 4 m sensors read the
walls they keep to.
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from mentor_core.sim.kinematics import to_body
from mentor_core.sim.planner_settings import with_planner
from mentor_core.sim.robots import RobotProfile

FloatArray = NDArray[np.float64]


def corridor_ranges(
    ranges: FloatArray, poses: FloatArray, goals: FloatArray, profile: RobotProfile
) -> FloatArray:
    """The clipped readings (n, k) (m) with those outside the view corridor of
    ``profile.view_margin`` set to the sensor range (module docstring); ``ranges`` themselves
    when the profile has no corridor. ``poses`` (n, 3) and ``goals`` (n, 2) in the map frame.
    """
    margin = profile.view_margin
    if margin is None:
        return ranges
    p = np.asarray(poses, dtype=np.float64)
    goal = to_body(p[:, 2], np.asarray(goals, dtype=np.float64) - p[:, :2])  # (n, 2)
    length = np.hypot(goal[:, 0], goal[:, 1])
    unit = np.divide(goal, length[:, None], out=np.zeros_like(goal), where=length[:, None] > 0)
    mounts = profile.sensor_mounts
    angles = mounts[:, 2:3] + profile.ray_offsets  # (k, rays); a single ray repeated
    # hit points (n, k, rays) in the body frame
    hx = mounts[None, :, 0:1] + ranges[:, :, None] * np.cos(angles)[None]
    hy = mounts[None, :, 1:2] + ranges[:, :, None] * np.sin(angles)[None]
    along = hx * unit[:, 0, None, None] + hy * unit[:, 1, None, None]
    t = np.clip(along, 0.0, length[:, None, None])
    dist = np.hypot(hx - t * unit[:, 0, None, None], hy - t * unit[:, 1, None, None])
    outside = dist.min(axis=2) > margin
    return np.where(outside, profile.sensor_range, ranges)


def set_view_margin(
    profile: RobotProfile, margin: float | None, source: str | Path = ""
) -> RobotProfile:
    """``profile`` with a view corridor of ``margin`` m: None keeps the profile's own, ``inf``
    (everything lies within it) removes any, a positive number replaces it; ConfigError naming
    ``source`` for any other (:func:`~mentor_core.sim.planner_settings.with_planner`)."""
    if margin is None:
        return profile
    if margin == math.inf:
        return dataclasses.replace(profile, view_margin=None)
    return with_planner(profile, view_margin=margin, source=source)
