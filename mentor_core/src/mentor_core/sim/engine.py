"""Batched world stepper: many robots of one profile in one world, stepped together.

The trainer's hot loop. Each robot is alone in its world (robots never see or hit each
other); all of them are stepped at once with numpy over robots, the ray casts and the swept
collision tests in compiled kernels (:mod:`mentor_core.sim.sensors`,
:mod:`mentor_core.sim.collision`).

One decision ``(dtheta, ds)`` moves a robot along its exact unicycle arc, sampled as in
:func:`mentor_core.sim.collision.swept_samples`. The robot stops at the first event along the
samples:

* reached: the first sample within ``goal_radius`` of the goal (unless a collision comes at or
  before it); the robot stops there;
* collided: the first sample whose body overlaps a box or crosses a wall; the robot stops at
  the sample before it (the last collision-free one);
* otherwise it ends at the end of the arc.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from mentor_core.sim.collision import (
    BROAD_PHASE_SLACK,
    EVENT_COLLIDED,
    EVENT_REACHED,
    MAX_SAMPLE_ANGLE,
    sample_counts,
    sweep_bounds,
    sweep_may_collide,
    swept_events,
)
from mentor_core.sim.kinematics import unicycle_arc, wrap_angle
from mentor_core.sim.robots import RobotProfile
from mentor_core.sim.sensors import Backend, sensor_readings
from mentor_core.sim.world import World

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
BoolArray = NDArray[np.bool_]


@dataclass(frozen=True)
class StepResult:
    """Outcome of one decision for every robot ``(n,)``; inactive robots are all False / 0.

    Attributes:
        collided: the swept body hit a box or a wall (the robot stopped before it).
        reached: the robot came within ``goal_radius`` of its goal (and stopped there).
        fraction: share of the control period used, ``stop_sample / n_samples`` in [0, 1].
    """

    collided: BoolArray
    reached: BoolArray
    fraction: FloatArray


class BatchEngine:
    """Poses of ``n`` robots in one world, moved by batched decisions.

    Args:
        world: the arena and its obstacles (shared by every robot).
        profile: body, sensors and goal radius of the robots.
        backend: kernels to use, ``"auto"`` (numba when importable), ``"numba"`` or ``"numpy"``.
        max_sample_step, max_sample_angle: swept-collision sampling, see
            :func:`mentor_core.sim.collision.sample_counts`.
    """

    def __init__(
        self, world: World, profile: RobotProfile, *, backend: Backend = "auto",
        max_sample_step: float | None = None, max_sample_angle: float = MAX_SAMPLE_ANGLE,
    ) -> None:
        self.world = world
        self.profile = profile
        self.backend: Backend = backend
        self.max_sample_step = max_sample_step
        self.max_sample_angle = max_sample_angle
        self._poses = np.zeros((0, 3), dtype=np.float64)
        self._goals = np.zeros((0, 2), dtype=np.float64)

    @property
    def n_robots(self) -> int:
        """Number of robots since the last :meth:`reset`."""
        return int(self._poses.shape[0])

    @property
    def poses(self) -> FloatArray:
        """Current poses ``(n, 3)`` (a read-only view)."""
        view = self._poses.view()
        view.setflags(write=False)
        return view

    @property
    def goals(self) -> FloatArray:
        """Goals ``(n, 2)`` (a read-only view)."""
        view = self._goals.view()
        view.setflags(write=False)
        return view

    def reset(self, starts: ArrayLike, goals: ArrayLike) -> None:
        """Place robot ``i`` at ``starts[i]`` ``(x, y, theta)``, its goal at ``goals[i]``."""
        p = np.array(starts, dtype=np.float64, ndmin=2)
        g = np.array(goals, dtype=np.float64, ndmin=2)
        if p.ndim != 2 or p.shape[1] != 3 or g.shape != (p.shape[0], 2):
            raise ValueError(f"starts must be (n, 3) and goals (n, 2), got {p.shape}, {g.shape}")
        if not (np.isfinite(p).all() and np.isfinite(g).all()):
            raise ValueError("starts and goals must be finite")
        p[:, 2] = wrap_angle(p[:, 2])
        self._poses = p
        self._goals = g

    def goal_distance(self) -> FloatArray:
        """Straight distance (m) from each robot's centre to its goal ``(n,)``."""
        d: FloatArray = np.hypot(
            self._poses[:, 0] - self._goals[:, 0], self._poses[:, 1] - self._goals[:, 1]
        )
        return d

    def observe(self, robots: ArrayLike | None = None) -> FloatArray:
        """Range readings ``(m, n_sensors)`` of ``robots`` (indices; default all), m or +inf."""
        poses = self._poses if robots is None else self._poses[np.asarray(robots, dtype=np.int64)]
        return sensor_readings(poses, self.profile, self.world, backend=self.backend)

    def step(self, dtheta: ArrayLike, ds: ArrayLike, active_mask: ArrayLike) -> StepResult:
        """Move every active robot by one decision; the others stay put.

        Args:
            dtheta: ``(n,)`` heading changes (rad); entries of inactive robots are ignored.
            ds: ``(n,)`` path lengths (m); entries of inactive robots are ignored.
            active_mask: ``(n,)`` bool, the robots that move.
        """
        n = self.n_robots
        mask = np.asarray(active_mask, dtype=np.bool_).reshape(-1)
        dth_all = np.asarray(dtheta, dtype=np.float64).reshape(-1)
        ds_all = np.asarray(ds, dtype=np.float64).reshape(-1)
        if mask.shape != (n,) or dth_all.shape != (n,) or ds_all.shape != (n,):
            raise ValueError(f"dtheta, ds and active_mask must all have shape ({n},)")
        idx = np.flatnonzero(mask)
        collided = np.zeros(n, dtype=np.bool_)
        reached = np.zeros(n, dtype=np.bool_)
        fraction = np.zeros(n, dtype=np.float64)
        if idx.size == 0:
            return StepResult(collided, reached, fraction)
        dth, dist = dth_all[idx], ds_all[idx]
        if not (np.isfinite(dth).all() and np.isfinite(dist).all()):
            raise ValueError("dtheta and ds of active robots must be finite")
        start = self._poses[idx]
        end = unicycle_arc(start, dth, dist)
        stop_fraction = np.ones(idx.size, dtype=np.float64)
        got = np.zeros(idx.size, dtype=np.bool_)
        crash = np.zeros(idx.size, dtype=np.bool_)
        # Broad phase: only decisions whose sweep comes near a box, a wall or the goal are
        # sampled; the others end at the arc's end (the same pose as its last sample).
        bounds = sweep_bounds(start, dth, dist)
        centre, radius = bounds
        goal = self._goals[idx]
        near_goal = np.hypot(centre[:, 0] - goal[:, 0], centre[:, 1] - goal[:, 1]) <= (
            radius + (self.profile.goal_radius + BROAD_PHASE_SLACK)
        )
        near = np.flatnonzero(
            near_goal
            | sweep_may_collide(
                start, dth, dist, self.profile, self.world, backend=self.backend,
                bounds=bounds,
            )
        )
        if near.size:
            counts = sample_counts(
                dth[near], dist[near], self.profile,
                max_sample_step=self.max_sample_step, max_sample_angle=self.max_sample_angle,
            )
            event, stop, end[near] = swept_events(
                start[near], dth[near], dist[near], counts, goal[near], self.profile,
                self.world, backend=self.backend,
            )
            got[near] = event == EVENT_REACHED
            crash[near] = event == EVENT_COLLIDED
            stop_fraction[near] = stop / counts
        self._poses[idx] = end
        collided[idx] = crash
        reached[idx] = got
        fraction[idx] = stop_fraction
        return StepResult(collided, reached, fraction)

