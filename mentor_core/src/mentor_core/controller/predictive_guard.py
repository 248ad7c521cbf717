"""A collision guard that looks at where a moving obstacle will be (issue 59): the guard of
:mod:`~mentor_core.controller.collision_guard` on readings moved forward in time.

Not built in and off in every shipped deployment: a plugin stage
(``predictive_guard: {plugin: "mentor_core.controller.predictive_guard:PredictiveGuard"}``,
in place of ``collision_guard``), tried on the IR-SIM validation worlds in experiment E097.

At each decision, for each sensor that read something within range now and at the last
decision, with the robot's heading changed by less than ``turn_limit`` rad in between: the
point read last time, ``q`` (world frame, on the sensor's axis), lies at ``|q - m|`` from the
sensor's mount ``m`` now. A static surface in front of the sensor reads no nearer than that
(it reads the same along the ray the robot drove, farther along a surface it passes); a
reading ``r`` nearer by more than ``least_speed`` x the robot's rated speed x the period is
something that came towards the robot, at ``c = (|q - m| - r) / dt``. Its reading a
``horizon`` of periods ahead is ``max(0, r - c horizon dt)``, and the guard vets the
planner's arc against those predicted readings (the nearer of predicted and read); with
``network`` the network sees them too, so that it steers away early.
"""

from __future__ import annotations

from typing import Annotated, Any

import numpy as np
from numpy.typing import NDArray
from pydantic import Field

from mentor_core.controller.collision_guard import MEMORY, CollisionGuardStage
from mentor_core.controller.stage import Stage, StageRun
from mentor_core.sim.robots import RobotProfile
from mentor_core.validation import Float, Int, config_dataclass

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]


@config_dataclass
class PredictiveGuard(Stage):
    """The stage ``predictive_guard`` (module docstring)."""

    name = "predictive_guard"
    memory: Annotated[Int, Field(ge=1, le=100)] = MEMORY
    """Decisions of readings the guard remembers (as ``collision_guard``'s)."""
    horizon: Annotated[Float, Field(ge=0.0, le=20.0)] = 2.0
    """Control periods ahead the readings of a moving obstacle are predicted for."""
    least_speed: Annotated[Float, Field(gt=0.0, le=10.0)] = 0.2
    """Share of the robot's rated speed an obstacle must come closer at to count as moving."""
    turn_limit: Annotated[Float, Field(gt=0.0, le=3.2)] = 0.45
    """rad: a sensor of a robot that turned more than this since the last decision is not
    compared."""
    network: bool = False
    """Whether the network sees the predicted readings too."""

    def start(self, n: int, profile: RobotProfile, arena: float | None) -> StageRun:
        guard = CollisionGuardStage(memory=self.memory).start(n, profile, arena)
        return _PredictiveRun(self, n, profile, guard)

    def record(self) -> dict[str, Any]:
        return {"predictive_guard": True, "horizon": self.horizon,
                "least_speed": self.least_speed, "network": self.network}  # fmt: skip


class _PredictiveRun(StageRun):
    def __init__(self, stage: PredictiveGuard, n: int, profile: RobotProfile,
                 guard: StageRun) -> None:  # fmt: skip
        self.stage = stage
        self.profile = profile
        self.guard = guard
        k = profile.n_sensors
        self.last_pose = np.full((n, 3), np.nan)
        self.last_read = np.full((n, k), np.inf)
        self.predicted = np.full((n, k), np.inf)

    def reset(self, robots: IntArray | None = None) -> None:
        rows = slice(None) if robots is None else robots
        self.last_pose[rows] = np.nan
        self.last_read[rows] = np.inf
        self.predicted[rows] = np.inf
        self.guard.reset(robots)

    def readings(self, robots: IntArray, readings: FloatArray, poses: FloatArray,
                 goals: FloatArray) -> FloatArray:  # fmt: skip
        p = self.profile
        r = np.where(readings < p.sensor_range, readings, np.inf)
        mounts = p.sensor_mounts
        theta = poses[:, 2:3]
        c, s = np.cos(theta), np.sin(theta)
        mx = poses[:, 0:1] + c * mounts[None, :, 0] - s * mounts[None, :, 1]
        my = poses[:, 1:2] + s * mounts[None, :, 0] + c * mounts[None, :, 1]
        last = self.last_pose[robots]
        lr = self.last_read[robots]
        lt = last[:, 2:3] + mounts[None, :, 2]
        lc, ls = np.cos(last[:, 2:3]), np.sin(last[:, 2:3])
        lmx = last[:, 0:1] + lc * mounts[None, :, 0] - ls * mounts[None, :, 1]
        lmy = last[:, 1:2] + ls * mounts[None, :, 0] + lc * mounts[None, :, 1]
        with np.errstate(invalid="ignore"):
            qx, qy = lmx + lr * np.cos(lt), lmy + lr * np.sin(lt)
            gap = np.hypot(qx - mx, qy - my)
            turned = np.abs(np.angle(np.exp(1j * (theta - last[:, 2:3]))))
            dt = p.control_period
            closing = (gap - r) / dt
            moving = (np.isfinite(r) & np.isfinite(lr) & (turned < self.stage.turn_limit)
                      & (closing > self.stage.least_speed * p.rated_speed))  # fmt: skip
        ahead = np.maximum(r - np.where(moving, closing, 0.0) * self.stage.horizon * dt, 0.0)
        self.predicted[robots] = np.where(moving, ahead, np.inf)
        self.last_pose[robots] = poses
        self.last_read[robots] = r
        if not self.stage.network:
            return readings
        out: FloatArray = np.minimum(readings, self.predicted[robots])
        return out

    def actions(self, robots: IntArray, poses: FloatArray, dtheta: FloatArray, ds: FloatArray,
                readings: FloatArray) -> tuple[FloatArray, FloatArray]:  # fmt: skip
        seen = np.minimum(readings, self.predicted[robots])
        return self.guard.actions(robots, poses, dtheta, ds, seen)


__all__ = ["PredictiveGuard"]
