"""What a robot's planner receives through ROS when the simulator gives it a lidar and an
``odom`` frame apart from ``map``: the same numbers in the simulator node, the planner node and
the in-process reference episode.

* Lidar: the simulator casts :func:`mentor_core.sim.lidar.lidar_scan` with the noise of the
  robot's own generator (:meth:`Wiring.generator`), the LaserScan carries float32 ranges, and the
  planner derives its sensors' readings from them with
  :func:`mentor_core.sim.scan_adapter.readings_from_scan` (the lidar's mount as the planner
  knows it, its single-ray field of view).
* Frames: the simulator's odometry is the pose in ``odom``, ``inverse(map_to_odom)`` applied
  to the pose in ``map`` (then through a quaternion), and the planner turns a goal given in
  ``map`` into ``odom`` with the same transform, so it decides in its odometry frame.

Without a lidar and with ``odom`` = ``map`` (the defaults) nothing changes: the per-sensor
readings as :func:`mentor_core.runtime.simulator.wire_ranges` delivers them, the pose and goal
as they are.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from mentor_core.sim import observation
from mentor_core.sim.frames import quaternion_to_yaw, yaw_to_quaternion
from mentor_core.sim.lidar import LidarSpec, lidar_scan
from mentor_core.sim.scan_adapter import LaserScanData, LidarMount, readings_from_scan
from mentor_core.sim.transforms import IDENTITY, Transform2D

if TYPE_CHECKING:
    from mentor_core.sim.pymunk_world import PymunkWorld
    from mentor_core.sim.robots import RobotProfile

FloatArray = NDArray[np.float64]
Pose = tuple[float, float, float]


def wire_ranges(ranges: ArrayLike, profile: RobotProfile) -> FloatArray:
    """Readings (k,) as a ``sensor_msgs/LaserScan`` delivers them: beyond range ``+inf``
    (REP-117), the rest rounded to float32 (m)."""
    r = np.asarray(ranges, dtype=np.float64).reshape(-1)
    r = np.where(r > profile.sensor_range, np.inf, r)
    return r.astype(np.float32).astype(np.float64)


def wire_pose(pose: Sequence[float]) -> Pose:
    """Pose as a ``nav_msgs/Odometry`` delivers it: x, y unchanged, the heading through a yaw
    quaternion and back (within 1e-12 rad)."""
    x, y, theta = (float(v) for v in pose)
    return x, y, quaternion_to_yaw(*yaw_to_quaternion(theta))


def wire_decision(dtheta: float, ds: float, dt: float) -> tuple[float, float]:
    """Decision as the simulator applies it after a ``geometry_msgs/Twist``: ``(angular.z dt,
    linear.x dt)`` with ``angular.z = dtheta / dt``, ``linear.x = ds / dt`` (rad, m)."""
    wz, vx = observation.twist_from_action(dtheta, ds, dt)
    back_dtheta, back_ds = observation.action_from_twist(wz, vx, dt)
    return float(back_dtheta), float(back_ds)


@dataclass(frozen=True)
class Wiring:
    """A simulated robot's lidar and odometry frame (module docstring).

    Attributes:
        lidar: the simulator's lidar (None: the planner reads the per-sensor scan).
        seed: seed of the lidar noise; robot ``i`` of the simulator draws from
            ``default_rng([seed, i])``.
        ray_width: the planner's field of view of a single-ray sensor, rad.
        planner_mount: the lidar's mount as the planner knows it (None: the true one).
        map_to_odom: the pose of ``odom`` in ``map``.
    """

    lidar: LidarSpec | None = None
    seed: int = 0
    ray_width: float = 0.0
    planner_mount: LidarMount | None = None
    map_to_odom: Transform2D = IDENTITY

    def generator(self, robot_index: int) -> np.random.Generator:
        """The lidar noise generator of the simulator's robot number ``robot_index``."""
        return np.random.default_rng([int(self.seed), int(robot_index)])

    def scan(
        self, physics: PymunkWorld, robot: str, rng: np.random.Generator | None
    ) -> FloatArray:
        """The lidar ranges of ``robot`` now (m, REP-117, float64); ValueError without a
        lidar."""
        if self.lidar is None:
            raise ValueError("no lidar configured")
        return lidar_scan(physics, robot, self.lidar, rng)

    def scan_data(self, ranges: ArrayLike) -> LaserScanData:
        """The lidar scan as the planner receives it (float32 fields)."""
        if self.lidar is None:
            raise ValueError("no lidar configured")
        spec = self.lidar
        # a LaserScan's angles, range limits and ranges are all float32
        head = np.array(
            [spec.angle_min, spec.angle_increment, spec.range_min, spec.range_max],
            dtype=np.float32,
        ).astype(np.float64)
        wired = np.asarray(ranges, dtype=np.float64).astype(np.float32).astype(np.float64)
        a_min, a_inc, r_min, r_max = (float(v) for v in head)
        return LaserScanData(a_min, a_inc, r_min, r_max, wired)

    def readings(self, ranges: ArrayLike, profile: RobotProfile) -> FloatArray:
        """The planner's readings of a lidar scan (the ranges the simulator cast)."""
        assert self.lidar is not None
        mount = self.planner_mount or LidarMount(self.lidar.mount)
        return readings_from_scan(self.scan_data(ranges), mount, profile, self.ray_width).readings

    def odom_pose(self, pose: Sequence[float]) -> Pose:
        """Pose in ``odom`` of a pose in ``map`` (as the odometry carries it, before the
        quaternion)."""
        p = (float(pose[0]), float(pose[1]), float(pose[2]))
        return p if self.map_to_odom.is_identity else self.map_to_odom.inverse().apply_pose(p)

    def odom_goal(self, goal: Sequence[float]) -> tuple[float, float]:
        """A goal in ``map`` turned into ``odom``, as the planner turns it."""
        g = (float(goal[0]), float(goal[1]))
        return g if self.map_to_odom.is_identity else self.map_to_odom.inverse().apply_point(g)

    def wire_pose(self, pose: Sequence[float]) -> Pose:
        """What the planner's odometry says of a pose in ``map``: in ``odom``, the heading
        through a quaternion."""
        x, y, theta = self.odom_pose(pose)
        return x, y, quaternion_to_yaw(*yaw_to_quaternion(theta))
