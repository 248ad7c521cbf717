"""A view corridor: the network sees only what lies near its way to the goal.

Not in the paper; off by default (the stage ``view_corridor`` of a deployment, or trained with:
the trainer config's ``view_margin``, the genome's metadata's). A
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
(:mod:`~mentor_core.controller.collision_guard`) and the clearance limit still read every
reading.

Chosen on the benchmark's validation split for the shipped Swarm-Robot planners (0.1 m, in
training and at deployment; experiment E064, "A view corridor" and "Trained with
the view corridor"); it cost the UGV's planners goals either way, whose 4 m sensors read the
walls they keep to.
"""

from __future__ import annotations

import math
from typing import Annotated, Any

import numpy as np
from numpy.typing import NDArray
from pydantic import Field, Strict

from mentor_core.controller.stage import Stage, StageRun
from mentor_core.sim.kinematics import to_body
from mentor_core.sim.robots import RobotProfile
from mentor_core.validation import config_dataclass

FloatArray = NDArray[np.float64]


def corridor_ranges(
    ranges: FloatArray, poses: FloatArray, goals: FloatArray, profile: RobotProfile,
    margin: float,
) -> FloatArray:  # fmt: skip
    """The clipped readings (n, k) (m) with those outside the view corridor of ``margin`` m
    set to the sensor range (module docstring); ``poses`` (n, 3) and ``goals`` (n, 2) in the
    map frame. An infinite margin keeps every reading."""
    if margin == math.inf:
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


@config_dataclass
class ViewCorridor(Stage):
    """The stage ``view_corridor`` (module docstring)."""

    name = "view_corridor"
    margin: Annotated[float, Strict(), Field(gt=0.0, allow_inf_nan=True)]
    """m: the network sees what lies within this distance of its way (.inf: everything)."""

    def start(self, n: int, profile: RobotProfile, arena: float | None) -> StageRun:
        return _CorridorRun(profile, self.margin)

    def record(self) -> dict[str, Any]:
        return {} if self.margin == math.inf else {"view_margin": self.margin}


class _CorridorRun(StageRun):
    def __init__(self, profile: RobotProfile, margin: float) -> None:
        self.profile = profile
        self.margin = margin

    def readings(
        self, robots: NDArray[np.int64], readings: FloatArray, poses: FloatArray,
        goals: FloatArray,
    ) -> FloatArray:  # fmt: skip
        return corridor_ranges(readings, poses, goals, self.profile, self.margin)
