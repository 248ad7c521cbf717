"""A simulated 2-D lidar: a ``sensor_msgs/LaserScan`` of any ray count and field of view.

The lidar sits at ``mount`` on the body (its pose in the body frame). Its ``rays`` rays leave the
lidar's origin at angles ``angle_min + k * angle_increment`` of its frame: a full circle
(``fov`` = 2 pi) from ``-pi`` in steps of ``2 pi / rays`` (no ray twice), else from ``-fov / 2``
to ``fov / 2`` in steps of ``fov / (rays - 1)``. Each ray reads the distance to the first
obstacle, wall or other robot (:meth:`mentor_core.sim.pymunk_world.PymunkWorld.cast`, the
simulator's own ray casts; the robot's own body is not seen), plus Gaussian noise of standard
deviation ``noise`` (m) drawn from the run's generator, then coded as REP-117 says: beyond
``range_max`` ``+inf``, nearer than ``range_min`` ``-inf``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from mentor_core.sim.pymunk_world import PymunkWorld
from mentor_core.sim.transforms import IDENTITY, Transform2D

FloatArray = NDArray[np.float64]
TWO_PI = 2.0 * math.pi


@dataclass(frozen=True)
class LidarSpec:
    """A simulated lidar (module docstring). Units m, rad; ValueError for bad values."""

    rays: int
    fov: float = TWO_PI
    mount: Transform2D = IDENTITY
    range_min: float = 0.0
    range_max: float = 4.0
    noise: float = 0.0

    def __post_init__(self) -> None:
        if isinstance(self.rays, bool) or not isinstance(self.rays, int) or self.rays < 2:
            raise ValueError(f"lidar rays: need an integer >= 2, got {self.rays!r}")
        if not (0.0 < self.fov <= TWO_PI + 1e-12):
            raise ValueError(f"lidar field of view: need (0, 2 pi] rad, got {self.fov}")
        if not (0.0 <= self.range_min < self.range_max < math.inf):
            raise ValueError(
                f"lidar ranges: need 0 <= range_min < range_max < inf, got "
                f"[{self.range_min}, {self.range_max}]"
            )
        if not (0.0 <= self.noise < math.inf):
            raise ValueError(f"lidar noise: need a standard deviation >= 0 m, got {self.noise}")

    @property
    def full_circle(self) -> bool:
        """The rays go all round."""
        return self.fov >= TWO_PI - 1e-12

    @property
    def angle_min(self) -> float:
        """Angle of the first ray in the lidar's frame, rad."""
        return -math.pi if self.full_circle else -0.5 * self.fov

    @property
    def angle_increment(self) -> float:
        """Angle between neighbouring rays, rad."""
        return TWO_PI / self.rays if self.full_circle else self.fov / (self.rays - 1)

    @property
    def angle_max(self) -> float:
        """Angle of the last ray, rad."""
        return self.angle_min + (self.rays - 1) * self.angle_increment

    @property
    def angles(self) -> FloatArray:
        """Every ray's angle in the lidar's frame, rad."""
        k = np.arange(self.rays, dtype=np.float64)
        out: FloatArray = self.angle_min + k * self.angle_increment
        return out


def lidar_scan(
    physics: PymunkWorld,
    robot: str,
    spec: LidarSpec,
    rng: np.random.Generator | None = None,
) -> FloatArray:
    """The ranges (m, REP-117 coded, float64) of ``robot``'s lidar at its current pose.

    ``rng`` draws the noise (one normal per ray and scan); None or ``spec.noise`` 0: none.
    """
    origin = Transform2D(*physics.pose(robot)).compose(spec.mount)
    truth = physics.cast((origin.x, origin.y), origin.yaw + spec.angles, spec.range_max, robot)
    ranges = truth
    if spec.noise > 0.0 and rng is not None:
        ranges = truth + spec.noise * rng.standard_normal(spec.rays)
    with np.errstate(invalid="ignore"):
        out = np.where(ranges > spec.range_max, np.inf, ranges)
        out = np.where(out < spec.range_min, -np.inf, out)
    return np.asarray(out, dtype=np.float64)
