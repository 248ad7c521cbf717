"""A collision guard behind the planner: no arc into what the sensors have just read, and a
step back when every arc ahead would hit.

Not in the paper; off by default (the stage ``collision_guard`` of a deployment, never trained
with). Nav2 checks
every trajectory a controller proposes against what its sensors read (DWB's critics on the
costmap, the collision monitor on the raw scans), and its recovery behaviours back the robot
up when it is stuck. Here, at each decision:

1. The guard remembers the points the robot's readings hit in its last
   :data:`MEMORY` decisions, in the world frame (a beam's reading on every ray of its cone:
   the obstacle lies somewhere on that arc), each a square ``2 e`` across, ``e`` a third of
   the engine's sampling step (:func:`~mentor_core.sim.collision.default_sample_step`; the
   size measured). In a simulated arena (``size`` given) its border counts as known, as it
   does for the scan map, whose grid is the arena; without one (a robot on ROS, the planner
   node) only what was read counts, checked in a box world about the robot too large for
   any arc or step back to reach its border.
2. If the planner's arc sweeps the body over none of them, it is driven as is.
3. Else the guard takes the free arc nearest to it among :data:`TURNS` heading changes
   across ``[-h, h]`` and the planner's, times three steps (the planner's, half-way to
   ``step_min``, and ``step_min``; each held to the clearance rule), nearest by
   ``|dtheta' - dtheta| / h + |ds' - ds| / (2 (step_max - step_min))``.
4. If none is free, it backs straight up by the first of :data:`BACKUP_SHARES` of the body
   length that is free of the points behind its centre line (a negative step), else lets
   the planner's arc stand.

Why (experiment E044, "A guard against driving into what the robot has read"): most
of the shipped UGV planners' collisions come at the smallest step, turning on the spot next to
an obstacle read a few cm off a front corner, where every turn would hit; backing up frees
them. Arcs are checked with the simulator's own swept-body test
(:func:`~mentor_core.sim.collision.swept_collision`) against what was read, not against the
world.
"""

from __future__ import annotations

import math
from collections import deque
from typing import Annotated, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from pydantic import Field

from mentor_core.controller.stage import Stage, StageRun
from mentor_core.sim.collision import default_sample_step, swept_collision
from mentor_core.sim.observation import clearance_limit
from mentor_core.sim.robots import RobotProfile
from mentor_core.sim.sensors import beam_frames
from mentor_core.sim.world import World
from mentor_core.validation import Int, config_dataclass

FloatArray = NDArray[np.float64]

#: decisions of readings the guard remembers; longer memories lost on the validation split
#: (remembered beam arcs block gaps: experiment E052, "A longer memory for the
#: collision guard")
MEMORY = 3
#: heading changes tried across ``[-h, h]`` when the planner's arc would hit
TURNS = 9
#: steps back tried, as shares of the body length, when no arc ahead is free
BACKUP_SHARES = (2.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0)


def read_points(poses: ArrayLike, readings: ArrayLike, profile: RobotProfile) -> list[FloatArray]:
    """Per robot, the world-frame points ``(j, 2)`` its readings hit (module docstring):
    ``poses`` ``(m, 3)``, ``readings`` ``(m, k)`` m (+inf or ``>= sensor_range``: no hit)."""
    p = np.asarray(poses, dtype=np.float64).reshape(-1, 3)
    r = np.asarray(readings, dtype=np.float64).reshape(p.shape[0], profile.n_sensors)
    rays = beam_frames(p, profile)  # (m, k, beam rays, 3)
    hit = np.isfinite(r) & (r < profile.sensor_range)
    reach = np.where(hit, r, 0.0)[:, :, None]
    x = rays[..., 0] + reach * np.cos(rays[..., 2])
    y = rays[..., 1] + reach * np.sin(rays[..., 2])
    keep = hit[:, :, None] & profile.distinct_rays[None]  # beam_frames repeats a single ray
    return [np.stack([x[i][keep[i]], y[i][keep[i]]], axis=-1) for i in range(p.shape[0])]


class CollisionGuard:
    """The guard of ``n`` robots of ``profile`` in an arena of side ``size`` m, or on no
    arena (None: the poses may lie anywhere, as odometry's do) (module docstring):
    :meth:`observe` the readings, then :meth:`vet` the actions, every decision."""

    def __init__(
        self, n: int, profile: RobotProfile, size: float | None = None, memory: int = MEMORY
    ) -> None:
        self.profile = profile
        self.size = None if size is None else float(size)
        self.half = default_sample_step(profile) / 3.0
        # without an arena, the half-side of the box world about the robot: a body's arc
        # (at most step_max) or step back (2/3 of its length) stays well inside it
        self.reach = profile.step_max + profile.length + profile.width + 2.0 * self.half
        self.recent: list[deque[FloatArray]] = [deque(maxlen=memory) for _ in range(n)]
        self.changed = 0  # arcs replaced by a free one
        self.backed = 0  # steps back

    def reset(self, robots: ArrayLike | None = None) -> None:
        """Forget every reading of robots ``robots`` (None: all): a new episode."""
        chosen = range(len(self.recent)) if robots is None else np.asarray(robots).tolist()
        for i in chosen:
            self.recent[i].clear()

    def observe(self, robots: ArrayLike, poses: ArrayLike, readings: ArrayLike) -> None:
        """Remember what robots ``robots`` ``(m,)`` at ``poses`` ``(m, 3)`` read."""
        points = read_points(poses, readings, self.profile)
        for i, seen in zip(np.asarray(robots).tolist(), points, strict=True):
            self.recent[i].append(seen)

    def vet(
        self, robots: ArrayLike, poses: ArrayLike, dtheta: ArrayLike, ds: ArrayLike,
        readings: ArrayLike,
    ) -> tuple[FloatArray, FloatArray]:  # fmt: skip
        """The decisions ``(dtheta, ds)`` ``(m,)`` each robot drives instead of the planner's
        (module docstring); ``readings`` ``(m, k)`` are the ones the planner decided on."""
        p = np.asarray(poses, dtype=np.float64).reshape(-1, 3)
        dth = np.array(dtheta, dtype=np.float64).reshape(-1)
        step = np.array(ds, dtype=np.float64).reshape(-1)
        r = np.asarray(readings, dtype=np.float64).reshape(p.shape[0], -1)
        for k, i in enumerate(np.asarray(robots).tolist()):
            if not self._within_reach(i, p[k], abs(step[k])):
                continue
            world, pose = self._obstacles(i, p[k])
            if swept_collision(pose, dth[k], step[k], self.profile, world)[0] < 0:
                continue
            choice = self._free_arc(pose, dth[k], step[k], r[k], world)
            if choice is not None:
                dth[k], step[k] = choice
                self.changed += 1
                continue
            back = self._step_back(i, p[k])
            if back is not None:
                dth[k], step[k] = 0.0, back
                self.backed += 1
        return dth, step

    def _within_reach(self, robot: int, pose: FloatArray, step: float) -> bool:
        """Whether an arc of length ``step`` from ``pose`` could reach a remembered point's
        box or, in an arena, its border (a cheap test that skips the swept check exactly: no
        point of the body leaves the disc of ``step`` plus its half-diagonal about its
        start, and a point's box, shifted inside the arena by at most its half-width, from
        the square of twice that about the point); False without points."""
        seen = [points for points in self.recent[robot] if len(points)]
        if not seen:
            return False
        reach = step + self.profile.half_diagonal + 2.0 * math.sqrt(2.0) * self.half + 1e-9
        x, y = float(pose[0]), float(pose[1])
        if self.size is not None and min(x, y, self.size - x, self.size - y) <= reach:
            return True
        return any(
            bool((np.square(points - pose[:2]).sum(axis=1) <= reach * reach).any())
            for points in seen
        )

    def _obstacles(
        self, robot: int, pose: FloatArray, behind: bool = False
    ) -> tuple[World, FloatArray]:
        """A robot's remembered points (it has some: :meth:`_within_reach`) as small boxes of
        a world, and its ``pose`` in that world; ``behind``: only the points behind its
        centre line. The world is the arena, or without one a box ``2 reach`` across centred
        on the robot (the points beyond it out of the body's reach)."""
        points = np.concatenate(list(self.recent[robot]))
        if behind:
            ahead = (points - pose[:2]) @ np.array([math.cos(pose[2]), math.sin(pose[2])])
            points = points[ahead < 0.0]
        side = 2.0 * self.half
        if self.size is not None:
            low = np.clip(points - self.half, 0.0, self.size - side)
            return World(self.size, np.concatenate([low, low + side], axis=1)), pose
        shift = pose[:2] - self.reach
        low = points - shift - self.half
        low = low[np.all((low >= 0.0) & (low <= 2.0 * self.reach - side), axis=1)]
        boxes = np.concatenate([low, low + side], axis=1)
        return World(2.0 * self.reach, boxes), np.append(pose[:2] - shift, pose[2])

    def _free_arc(
        self, pose: FloatArray, dtheta: float, ds: float, readings: FloatArray, world: World
    ) -> tuple[float, float] | None:
        """The free candidate arc nearest the planner's, or None (module docstring, 3)."""
        prof = self.profile
        h = prof.heading_change_max
        turns, steps = np.meshgrid(
            np.unique(np.append(np.linspace(-h, h, TURNS), dtheta)),
            np.unique([ds, 0.5 * (ds + prof.step_min), prof.step_min]),
        )
        turns, steps = turns.ravel(), steps.ravel()
        if prof.clearance_margin is not None:
            limit = clearance_limit(np.repeat(readings[None], turns.size, axis=0), turns, prof)
            steps = np.minimum(steps, limit)
        poses = np.repeat(pose[None], turns.size, axis=0)
        free = swept_collision(poses, turns, steps, prof, world) < 0
        if not free.any():
            return None
        span = prof.step_max - prof.step_min
        cost = np.abs(turns - dtheta) / h + 0.5 * np.abs(steps - ds) / span
        j = int(np.argmin(np.where(free, cost, np.inf)))
        return float(turns[j]), float(steps[j])

    def _step_back(self, robot: int, pose: FloatArray) -> float | None:
        """The longest free step back of :data:`BACKUP_SHARES` (negative, m), or None. Driving
        straight back, the body can only meet points behind its centre line; those ahead are
        left out, so that a body already within a box's half-width of the wall it faces can
        still back away from it."""
        world, pose = self._obstacles(robot, pose, behind=True)
        backs = -self.profile.length * np.asarray(BACKUP_SHARES)
        poses = np.repeat(pose[None], backs.size, axis=0)
        free = np.flatnonzero(swept_collision(poses, 0.0, backs, self.profile, world) < 0)
        return float(backs[free[0]]) if free.size else None


@config_dataclass
class CollisionGuardStage(Stage):
    """The stage ``collision_guard`` (module docstring)."""

    name = "collision_guard"
    memory: Annotated[Int, Field(ge=1, le=100)] = MEMORY
    """Decisions of readings remembered."""

    def start(self, n: int, profile: RobotProfile, arena: float | None) -> StageRun:
        return _GuardRun(CollisionGuard(n, profile, arena, self.memory))

    def record(self) -> dict[str, Any]:
        return {"collision_guard": True} if self.memory == MEMORY else {
            "collision_guard": True, "guard_memory": self.memory}


class _GuardRun(StageRun):
    def __init__(self, guard: CollisionGuard) -> None:
        self.guard = guard

    def reset(self, robots: NDArray[np.int64] | None = None) -> None:
        self.guard.reset(robots)

    def actions(
        self, robots: NDArray[np.int64], poses: FloatArray, dtheta: FloatArray, ds: FloatArray,
        readings: FloatArray,
    ) -> tuple[FloatArray, FloatArray]:  # fmt: skip
        self.guard.observe(robots, poses, readings)
        return self.guard.vet(robots, poses, dtheta, ds, readings)
