"""Message <-> mentor_core conversions of the simulator node (no node, no graph needed).

Frames (REP-105): ``map`` is the arena frame; ``odom`` sits at the ``map_to_odom`` parameter
in it (identity by default), the odometry is in ``odom``; each robot's body frame is
``<ns>/base_link``, its sensors ``<ns>/sensor_<i>`` and its lidar ``<ns>/lidar``
(:func:`mentor_core.robot_links`). Units REP-103.

LaserScan convention: a MENTOR robot's range sensors sit at different points of the body and a
LaserScan cannot say so. ``ranges[i]`` is sensor ``i`` of the robot profile (its order),
``angle_min``/``angle_max`` are the first/last mount angle, ``angle_increment`` is the common
step when the mount angles are evenly spaced and increasing, else 0 (irregular); ``range_min``
is 0, ``range_max`` the sensor range, and out-of-range readings are +inf (REP-117). The
numbers come from :func:`mentor_core.scan_geometry`, so recorded bags agree.
"""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from typing import TYPE_CHECKING, Protocol

import numpy as np
from builtin_interfaces.msg import Time
from geometry_msgs.msg import (
    Point,
    Pose,
    PoseStamped,
    Transform,
    TransformStamped,
    Twist,
    Vector3,
)
from nav_msgs.msg import Odometry
from numpy.typing import ArrayLike
from sensor_msgs.msg import LaserScan
from std_msgs.msg import ColorRGBA, Header, String
from visualization_msgs.msg import Marker, MarkerArray

from mentor_core import (
    ARENA_LINE_WIDTH,
    BAG_VERSION,
    EVENT_FORMAT,
    EVENT_KINDS,
    MAP_FRAME,
    ODOM_FRAME,
    action_from_twist,
    arena_outline,
    box_markers,
    scan_geometry,
)
from mentor_ros_common.messages import quaternion_msg

if TYPE_CHECKING:
    from mentor_core import FrameLink, LidarSpec, RobotProfile, World

_NS_PER_S = 1_000_000_000


def time_from_ns(stamp_ns: int) -> Time:
    """``builtin_interfaces/Time`` of a (sim) time in ns (>= 0)."""
    if stamp_ns < 0:
        raise ValueError(f"time {stamp_ns} ns is negative")
    sec, nanosec = divmod(int(stamp_ns), _NS_PER_S)
    return Time(sec=sec, nanosec=nanosec)


def ns_from_time(stamp: Time) -> int:
    """Time in ns of a ``builtin_interfaces/Time``."""
    return int(stamp.sec) * _NS_PER_S + int(stamp.nanosec)


def laser_scan_from_ranges(
    ranges: ArrayLike, profile: RobotProfile, stamp: Time, frame_id: str
) -> LaserScan:
    """LaserScan of one robot's readings (m, profile sensor order; see the module docstring).

    Readings beyond the sensor range become +inf. ``ValueError`` for a wrong count or NaN.
    """
    r = np.asarray(ranges, dtype=np.float64)
    if r.shape != (profile.n_sensors,):
        raise ValueError(
            f"{r.size} ranges given, profile {profile.name!r} has {profile.n_sensors} sensors"
        )
    if np.isnan(r).any():
        raise ValueError("NaN range reading")
    if (r < 0.0).any():
        raise ValueError("negative range reading")
    geo = scan_geometry(profile)
    return _laser_scan(np.where(r > geo.range_max, np.inf, r), geo, stamp, frame_id)


class _ScanAngles(Protocol):
    """What a LaserScan's header fields come from: a profile's scan geometry or a lidar."""

    @property
    def angle_min(self) -> float: ...
    @property
    def angle_max(self) -> float: ...
    @property
    def angle_increment(self) -> float: ...
    @property
    def range_min(self) -> float: ...
    @property
    def range_max(self) -> float: ...


def _laser_scan(r: np.ndarray, geo: _ScanAngles, stamp: Time, frame_id: str) -> LaserScan:
    return LaserScan(
        header=Header(stamp=stamp, frame_id=frame_id),
        angle_min=geo.angle_min,
        angle_max=geo.angle_max,
        angle_increment=geo.angle_increment,
        time_increment=0.0,
        scan_time=0.0,
        range_min=geo.range_min,
        range_max=geo.range_max,
        ranges=r.astype(np.float32).tolist(),
    )


def odometry_from_pose(
    pose: Sequence[float], twist: Sequence[float], stamp: Time, ns: str
) -> Odometry:
    """Odometry of pose ``(x, y, theta)`` (m, m, rad) and body twist ``(v, omega)`` (m/s,
    rad/s), frame ``odom`` -> ``<ns>/base_link``."""
    x, y, theta = (float(v) for v in pose)
    v, omega = (float(t) for t in twist)
    msg = Odometry()
    msg.header = Header(stamp=stamp, frame_id=ODOM_FRAME)
    msg.child_frame_id = f"{ns}/base_link" if ns else "base_link"
    msg.pose.pose = Pose(position=Point(x=x, y=y, z=0.0), orientation=quaternion_msg(theta))
    msg.twist.twist = Twist(linear=Vector3(x=v), angular=Vector3(z=omega))
    return msg


def pose_stamped_from_goal(goal: Sequence[float], stamp: Time) -> PoseStamped:
    """Goal ``(x, y)`` (m) as a PoseStamped in ``map`` (identity orientation)."""
    gx, gy = (float(v) for v in goal[:2])
    return PoseStamped(
        header=Header(stamp=stamp, frame_id=MAP_FRAME),
        pose=Pose(position=Point(x=gx, y=gy, z=0.0), orientation=quaternion_msg(0.0)),
    )


def twist_to_action(msg: Twist, dt: float) -> tuple[float, float]:
    """Decision ``(dtheta, ds)`` (rad, m) of a command held for ``dt`` s.

    dtheta = angular.z dt, ds = linear.x dt (the other components are ignored: the robot is a
    unicycle). ``ValueError`` for NaN/inf values or ``dt <= 0``.
    """
    wz, vx = float(msg.angular.z), float(msg.linear.x)
    if not (math.isfinite(wz) and math.isfinite(vx)):
        raise ValueError(f"non-finite velocity command (linear.x={vx}, angular.z={wz})")
    dtheta, ds = action_from_twist(wz, vx, dt)
    return float(dtheta), float(ds)


def event_string(
    kind: str, scenario: int, stamp_ns: int, goal: Sequence[float] | None = None
) -> String:
    """An episode event as ``std_msgs/String`` JSON: ``format``, ``version``, ``event``,
    ``scenario`` (as in episode bags), plus ``stamp_ns`` (sim time) and, for ``started``, the
    episode's ``goal`` [x, y] (m, ``map``). ``ValueError`` for an unknown event."""
    if kind not in EVENT_KINDS:
        raise ValueError(f"unknown event {kind!r}")
    body: dict[str, object] = {
        "format": EVENT_FORMAT,
        "version": BAG_VERSION,
        "event": kind,
        "scenario": int(scenario),
        "stamp_ns": int(stamp_ns),
    }
    if goal is not None:
        body["goal"] = [float(goal[0]), float(goal[1])]
    return String(data=json.dumps(body))


def markers_from_world(world: World, stamp: Time | None = None) -> MarkerArray:
    """The arena outline (ns ``arena``) and one CUBE per obstacle (ns ``obstacles``, pose =
    centre, scale = size, ``points`` = exact corners), frame ``map``; as in scenario bags."""
    header = Header(stamp=stamp if stamp is not None else Time(), frame_id=MAP_FRAME)
    arena = Marker(
        header=header,
        ns="arena",
        id=0,
        type=Marker.LINE_STRIP,
        action=Marker.ADD,
        pose=Pose(orientation=quaternion_msg(0.0)),
        scale=Vector3(x=ARENA_LINE_WIDTH),
        color=ColorRGBA(r=0.0, g=0.0, b=0.0, a=1.0),
        points=[Point(x=x, y=y, z=z) for x, y, z in arena_outline(world.size)],
    )
    out = MarkerArray(markers=[arena])
    for box in box_markers(world.obstacles):
        cx, cy, cz = box.centre
        sx, sy, sz = box.scale
        out.markers.append(
            Marker(
                header=header,
                ns="obstacles",
                id=box.id,
                type=Marker.CUBE,
                action=Marker.ADD,
                pose=Pose(position=Point(x=cx, y=cy, z=cz), orientation=quaternion_msg(0.0)),
                scale=Vector3(x=sx, y=sy, z=sz),
                color=ColorRGBA(r=0.5, g=0.5, b=0.5, a=1.0),
                points=[Point(x=x, y=y, z=z) for x, y, z in box.corners],
            )
        )
    return out


def lidar_scan(ranges: ArrayLike, spec: LidarSpec, stamp: Time, frame_id: str) -> LaserScan:
    """LaserScan of a simulated lidar's ranges (m, REP-117 coded: +inf, -inf kept)."""
    return _laser_scan(np.asarray(ranges, dtype=np.float64), spec, stamp, frame_id)


def transforms(links: Sequence[FrameLink], stamp: Time) -> list[TransformStamped]:
    """``geometry_msgs/TransformStamped`` of planar frame links (z 0), for ``/tf`` and
    ``/tf_static``."""
    out = []
    for link in links:
        t = link.transform
        out.append(
            TransformStamped(
                header=Header(stamp=stamp, frame_id=link.parent),
                child_frame_id=link.child,
                transform=Transform(
                    translation=Vector3(x=t.x, y=t.y, z=0.0), rotation=quaternion_msg(t.yaw)
                ),
            )
        )
    return out


def goal_request(msg: PoseStamped) -> tuple[str, tuple[float, float]]:
    """``(frame, (x, y))`` of a goal given as a PoseStamped; ValueError when not finite."""
    x, y = float(msg.pose.position.x), float(msg.pose.position.y)
    if not (math.isfinite(x) and math.isfinite(y)):
        raise ValueError("goal position is not finite")
    return str(msg.header.frame_id), (x, y)
