"""The wall-following baseline ``bug``: Bug2 with DistBug's leaving rule, on range readings.

The Bug family (Lumelsky & Stepanov 1987; DistBug: Kamon & Rivlin 1997) is the classic
sensor-based planner for an unknown world with a known goal: drive to the goal; at an
obstacle follow its boundary until a leaving rule says the way to the goal is open, then
drive to the goal again. Its memory makes it leave dead ends and traps that hold a purely
reactive planner. Per robot it keeps its mode, the side the wall is on, the goal distance at
the hit point and the least one since, and its odometry
(:class:`mentor_core.benchmark.control.Odometry`, in the frame of its start: the goal
inputs give the goal in that frame, so it needs nothing an evolved planner does not get).

Free ranges are those of the corridor the body sweeps
(:func:`mentor_core.benchmark.control.free_corridor`), on the current hit points and, for a
robot that does not see all round (the Swarm-Robot), those of its last ``MEMORY`` (10)
decisions (:class:`mentor_core.benchmark.control.PointMemory`), as the reactive baseline.

* **to goal**: turn towards the goal's bearing (at most ``h`` per decision, on the spot
  while it lies more than ``h`` off) and step ``min(step_max, free range - d_w, distance)``.
  The way is blocked when the free range towards the goal is below the goal's distance and
  ``d_w + step_max``: the hit point. The robot then follows the obstacle on the freer hand
  (free range at +-60 deg), the obstacle on its other side.
* **follow** (obstacle on side ``s``, distance ``d_w = WALL_DISTANCE`` (2) half body
  diagonals), tangent following as TangentBug's boundary following: the nearest seen point
  within ``SENSE`` (2) ``d_w``, ahead or on side ``s``, gives the direction along the wall
  (perpendicular to the point's bearing), turned by up to 45 deg towards the wall when
  farther than ``d_w`` and away when nearer; turn that way (at most ``h``) and step on
  (the smallest step while it lies more than ``h`` off or the way ahead is shorter than
  ``d_w / 2``). No point near: the wall's end; drive on ``d_w`` past it, then round it on
  an arc of radius ``d_w`` (back to the goal after a full circle without a wall).
* **leave** (DistBug): the goal is in view (free range towards it beyond its distance), or
  ``d - F' <= d_min - step_max`` with ``F' = F - d_w - step_max`` the part of the free range
  ``F`` towards the goal it could drive before counting as blocked again (it would take the
  robot a step nearer than it has been since the hit point), or Bug2's rule: back on the
  start-goal line (the m-line) nearer to the goal than the hit point, with ``F'`` a step.
* **loop**: back at the hit point after going round (more than ``4 pi d_w`` driven since)
  without getting nearer: follow the other way.
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
from mentor_core.sim.robots import RobotProfile
from mentor_core.sim.world import Scenario

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
WALL_DISTANCE = 2.0  # half body diagonals kept from the followed wall
MEMORY = 10  # decisions whose hit points a robot remembers (as the reactive baseline)
SENSE = 2.0  # hit points within SENSE d_w are the wall being followed
_TO_GOAL, _FOLLOW = 0, 1


def bug_policy(
    scenarios: Sequence[Scenario], profile: RobotProfile, driver: Policy | None = None
) -> Policy:
    """A Bug policy for robot ``i`` on ``scenarios[i]`` (module docstring).

    ``driver``: another policy (an evolved planner) that drives in the **to goal** mode in
    place of the straight run at the goal; the hit point, the following and the leaving
    rules stay Bug's (a hybrid: Bug's memory as the other planner's recovery at walls).
    """
    n = len(scenarios)
    odometry = Odometry(np.zeros((n, 3)))
    memory = PointMemory(n, profile, MEMORY)
    mode = np.full(n, _TO_GOAL)
    side = np.ones(n)
    d_hit = np.full(n, np.inf)
    d_min = np.full(n, np.inf)
    hit_xy = np.zeros((n, 2))
    driven = np.zeros(n)  # path driven since the hit point, m
    lost = np.zeros(n, dtype=np.int64)  # decisions in a row without the wall in sight
    goal_xy = np.full((n, 2), np.nan)  # in the odometry frame, from the first inputs
    h = profile.heading_change_max
    d_w = WALL_DISTANCE * profile.half_diagonal
    step = profile.step_max

    def policy(inputs: FloatArray, robots: IntArray) -> FloatArray:
        u = readings(inputs, profile)
        bearing, distance = goal_polar(inputs, profile)
        poses = odometry.poses[robots]
        fresh = np.isnan(goal_xy[robots, 0])
        heading = poses[:, 2] + bearing
        goal_xy[robots[fresh]] = (poses[fresh, :2] + distance[fresh, None]
                                  * np.stack([np.cos(heading[fresh]), np.sin(heading[fresh])],
                                             axis=1))  # fmt: skip
        m = len(robots)
        points = memory.add_and_get(robots, poses, hit_points(u, profile))
        to_goal = free_corridor(u, bearing, profile, points)
        ahead = free_corridor(u, np.zeros(m), profile, points)
        left = free_corridor(u, np.full(m, np.pi / 3), profile, points)
        right = free_corridor(u, np.full(m, -np.pi / 3), profile, points)
        dtheta = np.zeros(len(robots))
        ds = np.full(len(robots), profile.step_min)
        for row, r in enumerate(robots.tolist()):
            d, b = float(distance[row]), float(bearing[row])
            if mode[r] == _FOLLOW:
                d_min[r] = min(d_min[r], d)
                xy = poses[row, :2]
                if _leaves(r, d, float(to_goal[row]), xy):
                    mode[r] = _TO_GOAL
                elif driven[r] > 4 * np.pi * d_w and np.hypot(*(xy - hit_xy[r])) < step:
                    side[r], driven[r] = -side[r], 0.0
            if mode[r] == _TO_GOAL and to_goal[row] < min(d, d_w + step) and abs(b) <= h:
                mode[r] = _FOLLOW
                d_hit[r] = d_min[r] = d
                hit_xy[r] = poses[row, :2]
                driven[r] = 0.0
                lost[r] = 0
                # the freer hand; the wall goes on the other side
                side[r] = -1.0 if left[row] >= right[row] else 1.0
            if mode[r] == _TO_GOAL:
                dtheta[row] = np.clip(b, -h, h)
                if abs(b) <= h:
                    ds[row] = min(step, float(to_goal[row]) - d_w, d)
            else:
                dtheta[row], ds[row] = _follow(r, points[row], float(ahead[row]))
        outputs = outputs_for(dtheta, ds, profile)
        if driver is not None:
            driving = mode[robots] == _TO_GOAL
            if driving.any():
                outputs[driving] = driver(inputs[driving], robots[driving])
        before = odometry.poses[robots, :2].copy()
        odometry.advance(robots, outputs, inputs, profile)
        driven[robots] += np.hypot(*(odometry.poses[robots, :2] - before).T)
        return outputs

    def _leaves(r: int, d: float, free: float, xy: FloatArray) -> bool:
        usable = free - (d_w + step)  # how far it could drive before it is blocked again
        if free >= d or (usable > 0.0 and d - usable <= d_min[r] - step):
            return True
        # Bug2: on the start-goal line (the start is the odometry origin), nearer than the hit
        g = goal_xy[r]
        length = float(np.hypot(*g))
        off = abs(g[0] * xy[1] - g[1] * xy[0]) / max(length, 1e-12)
        return bool(off < 0.5 * step and d < d_hit[r] - step and usable > step)

    def _follow(r: int, pts: FloatArray, ahead: float) -> tuple[float, float]:
        s = float(side[r])
        dist = np.hypot(pts[:, 0], pts[:, 1])
        angle = np.arctan2(pts[:, 1], pts[:, 0])
        # the wall: hit points near enough, ahead or on the wall's side
        near = (dist < SENSE * d_w) & (s * angle > -np.pi / 3)
        if not near.any():
            lost[r] += 1
            if lost[r] * d_w * h > 2.0 * np.pi * d_w:  # gone round once: nothing to follow
                mode[r] = _TO_GOAL
            if lost[r] == 1:  # past the wall's end first (a robot may not see beside it)
                return 0.0, min(step, ahead - 0.5 * d_w, d_w)
            # then round it on an arc of radius d_w
            return s * h, max(profile.step_min, min(step, d_w * h))
        lost[r] = 0
        i = int(np.argmin(np.where(near, dist, np.inf)))
        tangent = angle[i] - s * np.pi / 2  # along the wall, the wall on side s
        correct = s * np.clip((dist[i] - d_w) / d_w, -1.0, 1.0) * np.pi / 4
        heading = float(np.arctan2(np.sin(tangent + correct), np.cos(tangent + correct)))
        turn = float(np.clip(heading, -h, h))
        if abs(heading) > h or ahead < 0.5 * d_w:
            return turn, profile.step_min
        return turn, min(step, ahead - 0.5 * d_w)

    return policy
