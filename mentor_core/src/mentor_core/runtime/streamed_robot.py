"""A robot as a real one streams its data: a kinematic differential drive that takes velocity
commands, a 2-D lidar at its own rate, odometry at another, and the faults real sensors have.

:class:`StreamedRobot` plays a robot other than this project's simulator (by default a
TurtleBot3 Burger as Gazebo runs it: an LDS lidar of 360 rays at 5 Hz, 0.12-3.5 m, mounted
3.2 cm behind the centre; odometry at 30 Hz; 0.22 m/s and 2.84 rad/s at most), so that the
planner node is tried as a user would try it on a robot: it steps in ticks of sim time,
drives the latest command clipped to the base's limits along its arc for one tick (the
:class:`~mentor_core.sim.pymunk_world.PymunkWorld`'s collision checks on the way; a collision
stops it), and says which streams are due. :attr:`StreamedRobot.fault` spoils what it
streams as broken sensors do: ``scan_nan``, ``scan_zero`` and ``scan_inf`` (every range NaN,
0.0, or alternating +-inf), ``scan_stop`` and ``odom_stop`` (that stream goes quiet).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np
from numpy.typing import NDArray

from mentor_core.runtime.velocity_limits import VelocityLimits, limited_velocity
from mentor_core.sim.lidar import LidarSpec, lidar_scan
from mentor_core.sim.pymunk_world import PymunkWorld
from mentor_core.sim.robots import RobotProfile
from mentor_core.sim.transforms import Transform2D
from mentor_core.sim.world import World

FloatArray = NDArray[np.float64]
FAULTS = ("", "scan_nan", "scan_zero", "scan_inf", "scan_stop", "odom_stop")
_NAME = "robot"


@dataclass(frozen=True)
class StreamSpec:
    """What a robot streams and how fast it drives (defaults: a TurtleBot3 Burger in Gazebo).

    Attributes:
        lidar: the lidar (rays, field of view, mount on the body, ranges, noise).
        scan_hz: scans per s of sim time.
        odom_hz: odometry messages per s of sim time.
        tick: s of sim time a step drives (the physics step).
        limits: what the base can do: commands beyond are clipped (its acceleration too).
        body: m, ``(length, width)`` of the box about the base frame that holds the robot
            (the Burger's round 0.105 m; :func:`mentor_core.footprint_box` of a footprint).
    """

    lidar: LidarSpec = field(default_factory=lambda: LidarSpec(
        360, mount=Transform2D(-0.032, 0.0, 0.0), range_min=0.12, range_max=3.5,
        noise=0.01))  # fmt: skip
    scan_hz: float = 5.0
    odom_hz: float = 30.0
    tick: float = 1.0 / 30.0
    limits: VelocityLimits = field(default_factory=lambda: VelocityLimits(
        max_vel_x=0.22, max_vel_theta=2.84, acc_lim_x=2.5, acc_lim_theta=3.2))  # fmt: skip
    body: tuple[float, float] = (0.21, 0.21)

    def __post_init__(self) -> None:
        for name, value in (("scan_hz", self.scan_hz), ("odom_hz", self.odom_hz),
                            ("tick", self.tick), ("body length", self.body[0]),
                            ("body width", self.body[1])):  # fmt: skip
            if not (math.isfinite(value) and value > 0.0):
                raise ValueError(f"{name} must be a positive number, got {value}")


@dataclass(frozen=True)
class Tick:
    """One step's outcome: sim time (s) after it; the pose and velocity ``(v, w)`` if the
    odometry is due (else None); the ranges if a scan is due (else None); a collision."""

    time: float
    odometry: tuple[tuple[float, float, float], tuple[float, float]] | None
    scan: FloatArray | None
    collided: bool


class StreamedRobot:
    """A robot of ``spec`` in ``world``, its body ``spec.body``, at ``pose`` (module
    docstring). ``seed`` draws the lidar's noise."""

    def __init__(self, world: World, profile: RobotProfile, pose: tuple[float, float, float],
                 spec: StreamSpec | None = None, seed: int = 0) -> None:  # fmt: skip
        self.spec = spec or StreamSpec()
        self.profile = replace(profile, length=self.spec.body[0], width=self.spec.body[1])
        self.physics = PymunkWorld(world, self.profile)
        self.physics.add_robot(_NAME, pose)
        self.time = 0.0
        self.velocity = (0.0, 0.0)  # what the base drives
        self.command = (0.0, 0.0)  # what it was told
        self.fault = ""
        self.collisions = 0
        self.distance = 0.0
        self._rng = np.random.default_rng(seed)
        self._ticks = 0
        self._next = {"scan": 0.0, "odom": 0.0}

    @property
    def pose(self) -> tuple[float, float, float]:
        """Where the robot stands (x, y, theta) in the world's frame."""
        return self.physics.pose(_NAME)

    def place(self, pose: tuple[float, float, float]) -> None:
        """Move the robot to ``pose`` (a new start), standing still."""
        self.physics.set_pose(_NAME, pose)
        self.velocity = self.command = (0.0, 0.0)

    def step(self) -> Tick:
        """Drive one tick on the latest command; the streams that fall due."""
        dt = self.spec.tick
        v, w = limited_velocity(self.command, self.spec.limits, self.velocity, dt)
        before = self.pose
        move = self.physics.drive(_NAME, w * dt, v * dt)
        self.distance += math.dist(before[:2], move.pose[:2])
        self.velocity = (0.0, 0.0) if move.collided else (v, w)
        self.collisions += int(move.collided)
        self._ticks += 1
        self.time = self._ticks * dt
        odometry = scan = None
        if self._due("odom", self.spec.odom_hz) and self.fault != "odom_stop":
            odometry = (move.pose, self.velocity)
        if self._due("scan", self.spec.scan_hz) and self.fault != "scan_stop":
            scan = self._spoiled(lidar_scan(self.physics, _NAME, self.spec.lidar, self._rng))
        return Tick(self.time, odometry, scan, move.collided)

    def _due(self, stream: str, hz: float) -> bool:
        if self.time + 1e-9 < self._next[stream]:
            return False
        self._next[stream] += 1.0 / hz
        return True

    def _spoiled(self, ranges: FloatArray) -> FloatArray:
        if self.fault == "scan_nan":
            return np.full_like(ranges, np.nan)
        if self.fault == "scan_zero":
            return np.zeros_like(ranges)
        if self.fault == "scan_inf":
            return np.where(np.arange(ranges.size) % 2 == 0, np.inf, -np.inf)
        return ranges


__all__ = ["FAULTS", "StreamSpec", "StreamedRobot", "Tick"]
