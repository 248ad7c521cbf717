"""The oracle: a shortest path, followed within the same action limits (the upper bound).

It knows the world and its true pose (odometry from the known start,
:class:`mentor_core.benchmark.control.Odometry`). It plans shortest paths for discs of
``LADDER`` (1.25, 2, 3, 4) half body diagonals (the first and last legs need only keep the
1.25 of the start's and goal's clearance; the body's circumscribed disc where none is found)
and drives the one it expects to be fastest: a path that hugs a wall is shorter, but the
clearance rule (``observation.clearance_limit``) shortens every step the sensors see a wall
ahead in, so the estimate is the path's length at the step the rule allows at poses sampled
along it (from the engine's own ray casts), plus one decision per ``h`` of turning at its
corners. It drives the path vertex by vertex:

* heading error ``alpha`` to the next vertex above ``ALIGNED`` (0.02 rad): turn by
  ``clip(alpha, +-h)`` with the smallest step (``step_min``), nearly on the spot;
* else the arc whose chord points at the vertex (``dtheta = 2 alpha``), as long as the chord
  ``min(step_max sin(alpha) / alpha, distance)`` allows; it ends on the vertex when the
  vertex is that near (a vertex nearer than ``step_min`` counts as reached).

The margin of at least a quarter half diagonal (UGV 0.05 m, Swarm-Robot 0.0125 m) absorbs the
few millimetres the turning steps and the chord arcs stray from the path. Every action
passes through ``actions_from_outputs`` (the clearance rule too), as every planner's does.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from mentor_core.benchmark.control import Odometry, outputs_for
from mentor_core.navigation.shortest_path import VisibilityGraph
from mentor_core.sim.episode import Policy
from mentor_core.sim.kinematics import wrap_angle
from mentor_core.sim.observation import clearance_limit
from mentor_core.sim.robots import RobotProfile
from mentor_core.sim.sensors import sensor_readings
from mentor_core.sim.world import Scenario, World

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
ALIGNED = 0.02  # rad: heading error below which the oracle drives on
LADDER = (1.25, 2.0, 3.0, 4.0)  # planning radii, half body diagonals


def expected_time(path: FloatArray, world: World, profile: RobotProfile) -> float:
    """Decisions the oracle expects to need on ``path`` (module docstring): at poses every
    half step along it, facing along it, the step the clearance rule allows; plus
    ``ceil(|turn| / h)`` at every corner (and at the start, from the path's first heading)."""
    seg = np.diff(path, axis=0)
    lengths = np.hypot(*seg.T)
    keep = lengths > 0
    seg, lengths = seg[keep], lengths[keep]
    if not len(seg):
        return 0.0
    heading = np.arctan2(seg[:, 1], seg[:, 0])
    spacing = 0.5 * profile.step_max
    counts = np.maximum(1, np.ceil(lengths / spacing).astype(np.int64))
    which = np.repeat(np.arange(len(seg)), counts)
    offset = np.concatenate([np.arange(c) for c in counts]) + 0.5
    along = offset * (lengths / counts)[which]
    start = path[:-1][keep]
    poses = np.column_stack([start[which] + along[:, None] * (seg / lengths[:, None])[which],
                             heading[which]])  # fmt: skip
    if profile.clearance_margin is None:
        steps = np.full(len(poses), profile.step_max)
    else:
        steps = clearance_limit(sensor_readings(poses, profile, world), np.zeros(len(poses)),
                                profile)  # fmt: skip
    driving = float(np.sum((lengths / counts)[which] / steps))
    turns = np.abs(wrap_angle(np.diff(heading)))
    return driving + float(np.sum(np.ceil(turns / profile.heading_change_max)))


def oracle_paths(scenarios: Sequence[Scenario], profile: RobotProfile) -> list[FloatArray]:
    """The path ``(k, 2)`` the oracle follows in each scenario (module docstring); the
    straight line to the goal where not even the circumscribed disc has a path."""
    graphs: dict[int, list[VisibilityGraph]] = {}
    paths = []
    for sc in scenarios:
        key = id(sc.world)
        if key not in graphs:
            radii = [profile.half_diagonal] + [f * profile.half_diagonal for f in LADDER]
            graphs[key] = [VisibilityGraph(sc.world, r) for r in radii]
        tight, ends, *wider = graphs[key]
        found = [p for p in (ends.path(sc.start, sc.goal),
                             *(g.path(sc.start, sc.goal, ends=ends) for g in wider))
                 if p is not None]  # fmt: skip
        if not found:
            fallback = tight.path(sc.start, sc.goal)
            paths.append(fallback.points if fallback is not None
                         else np.array([sc.start[:2], sc.goal], dtype=np.float64))  # fmt: skip
            continue
        cost = [expected_time(p.points, sc.world, profile) for p in found]
        paths.append(found[int(np.argmin(cost))].points)
    return paths


def oracle_policy(scenarios: Sequence[Scenario], profile: RobotProfile) -> Policy:
    """A policy for robot ``i`` on ``scenarios[i]`` (module docstring)."""
    paths = oracle_paths(scenarios, profile)
    odometry = Odometry([sc.start for sc in scenarios])
    target = np.ones(len(scenarios), dtype=np.int64)  # index of the next path vertex
    h = profile.heading_change_max
    near = max(profile.step_min, 1e-6)

    def policy(inputs: FloatArray, robots: IntArray) -> FloatArray:
        dtheta = np.empty(len(robots))
        ds = np.empty(len(robots))
        for row, r in enumerate(robots.tolist()):
            x, y, theta = odometry.poses[r]
            path = paths[r]
            while (target[r] < len(path) - 1
                   and np.hypot(*(path[target[r]] - (x, y))) < near):  # fmt: skip
                target[r] += 1
            vx, vy = path[target[r]]
            dist = float(np.hypot(vx - x, vy - y))
            alpha = float(wrap_angle(np.arctan2(vy - y, vx - x) - theta)) if dist > 0 else 0.0
            if abs(alpha) > ALIGNED:
                dtheta[row], ds[row] = float(np.clip(alpha, -h, h)), profile.step_min
                continue
            shrink = np.sinc(alpha / np.pi)  # sin(alpha) / alpha: chord / arc
            chord = min(profile.step_max * shrink, dist)
            dtheta[row], ds[row] = 2.0 * alpha, chord / shrink
        outputs = outputs_for(dtheta, ds, profile)
        odometry.advance(robots, outputs, inputs, profile)
        return outputs

    return policy

