"""Message <-> mentor_core conversions of the planner node (no node, no graph needed).

The planner reads ``<ns>/scan`` (the simulator's per-sensor scan, ranges in the robot
profile's sensor order, see ``mentor_sim_node.conversions``, or any 2-D lidar's LaserScan, which
``mentor_core.readings_from_scan`` turns into the profile's readings), ``<ns>/odom`` (pose in
its odometry frame), goals (``PoseStamped`` in any frame the planner can link to its odometry
frame) and ``/mentor/obstacles`` (the arena), and answers on ``<ns>/cmd_vel``. The network
inputs themselves come from the one shared function ``mentor_core.network_inputs``, which
clips +inf to the sensor range; nothing here changes a reading.
With a global plan it also reads a ``nav_msgs/OccupancyGrid`` (the map to plan on) and
``nav_msgs/Path`` (a path to follow), both in ``map``, and writes the path it follows as a
``nav_msgs/Path``; with a scan map it writes that map as a ``nav_msgs/OccupancyGrid``
(``mentor_ros_common.messages.occupancy_grid_msg``, which the simulator node's ``/map`` uses
too).
"""

from __future__ import annotations

import json
import math
from typing import TYPE_CHECKING

import numpy as np
from builtin_interfaces.msg import Time
from geometry_msgs.msg import (
    Point,
    Pose,
    PoseStamped,
    TransformStamped,
    Twist,
    Vector3,
)
from nav_msgs.msg import OccupancyGrid as OccupancyGridMsg
from nav_msgs.msg import Odometry, Path
from numpy.typing import ArrayLike, NDArray
from sensor_msgs.msg import LaserScan
from std_msgs.msg import Header, String
from visualization_msgs.msg import MarkerArray

from mentor_core import (
    EVENT_FORMAT,
    EVENT_KINDS,
    MAP_FRAME,
    LaserScanData,
    OccupancyGrid,
    Transform2D,
    planar_transform,
    quaternion_to_yaw,
    scan_geometry,
)
from mentor_core import twist_from_action as _twist_from_action
from mentor_ros_common.messages import quaternion_msg

if TYPE_CHECKING:
    from mentor_core import Bounds, RobotProfile

_NS_PER_S = 1_000_000_000
#: rad, m: how near a scan's geometry must be to the profile's to be its per-sensor scan
_SAME_GEOMETRY = 1e-6


def ns_from_stamp(stamp: Time) -> int:
    """Time in ns of a header stamp (``builtin_interfaces/Time``)."""
    return int(stamp.sec) * _NS_PER_S + int(stamp.nanosec)


def ranges_from_scan(msg: LaserScan, profile: RobotProfile) -> NDArray[np.float64]:
    """Readings (m, float64, profile sensor order) of a scan; +inf is kept.

    ``ValueError`` when the count differs from ``profile.n_sensors`` or a reading is NaN.
    """
    r = np.asarray(msg.ranges, dtype=np.float64)
    if r.shape != (profile.n_sensors,):
        raise ValueError(
            f"scan has {r.size} ranges, profile {profile.name!r} has {profile.n_sensors} sensors"
        )
    if np.isnan(r).any():
        raise ValueError("scan holds a NaN range")
    return r


def pose_from_odometry(msg: Odometry) -> tuple[float, float, float]:
    """Pose ``(x, y, theta)`` (m, m, rad in ``(-pi, pi]``) of an Odometry message.

    ``ValueError`` for a non-finite position or orientation.
    """
    p = msg.pose.pose.position
    q = msg.pose.pose.orientation
    values = (p.x, p.y, q.x, q.y, q.z, q.w)
    if not all(math.isfinite(v) for v in values):
        raise ValueError("odometry pose is not finite")
    if q.x == 0.0 and q.y == 0.0 and q.z == 0.0 and q.w == 0.0:
        raise ValueError("odometry orientation is the zero quaternion")
    return float(p.x), float(p.y), quaternion_to_yaw(q.x, q.y, q.z, q.w)


def goal_request(msg: PoseStamped) -> tuple[str, tuple[float, float], float | None]:
    """``(frame, (x, y), yaw)`` of a goal (m, rad; any frame, empty: the map's; yaw None for
    an orientation that is all zeros, as an unset one is). ``ValueError`` for a non-finite
    position or orientation."""
    x, y = float(msg.pose.position.x), float(msg.pose.position.y)
    if not (math.isfinite(x) and math.isfinite(y)):
        raise ValueError("goal position is not finite")
    q = msg.pose.orientation
    quat = [float(q.x), float(q.y), float(q.z), float(q.w)]
    if not all(math.isfinite(v) for v in quat):
        raise ValueError("goal orientation is not finite")
    yaw = quaternion_to_yaw(*quat) if any(quat) else None
    return str(msg.header.frame_id), (x, y), yaw


def is_profile_scan(msg: LaserScan, profile: RobotProfile) -> bool:
    """The scan is the simulator's per-sensor scan of ``profile`` (one range per sensor, its
    angles and range): any other is read as a lidar's."""
    geo = scan_geometry(profile)
    fields = (msg.angle_min, msg.angle_max, msg.angle_increment, msg.range_max)
    want = (geo.angle_min, geo.angle_max, geo.angle_increment, geo.range_max)
    return len(msg.ranges) == profile.n_sensors and all(
        abs(a - b) <= _SAME_GEOMETRY for a, b in zip(fields, want, strict=True)
    )


def scan_data(msg: LaserScan) -> LaserScanData:
    """The fields of any LaserScan the planner derives its readings from (ranges as sent,
    float32 to float64). ``ValueError`` for non-finite angles or limits, or no ranges."""
    if not msg.ranges:
        raise ValueError("scan has no ranges")
    return LaserScanData(
        float(msg.angle_min),
        float(msg.angle_increment),
        float(msg.range_min),
        float(msg.range_max),
        np.asarray(msg.ranges, dtype=np.float64),
    )


def planar(msg: TransformStamped) -> tuple[Transform2D, bool]:
    """A TF transform's planar part and whether its child frame is upside down (``ValueError``
    for a tilted one)."""
    t, q = msg.transform.translation, msg.transform.rotation
    return planar_transform((t.x, t.y, t.z), (q.x, q.y, q.z, q.w))


def arena_bounds(msg: MarkerArray) -> Bounds | None:
    """``(xmin, ymin, xmax, ymax)`` (m) of the arena outline (ns ``arena``) of the simulator's
    obstacle markers, or None without one."""
    for marker in msg.markers:
        if marker.ns == "arena" and marker.points:
            xs = [float(p.x) for p in marker.points]
            ys = [float(p.y) for p in marker.points]
            return (min(xs), min(ys), max(xs), max(ys))
    return None


def event_from_string(msg: String) -> tuple[str, tuple[float, float] | None]:
    """``(event, goal)`` of an episode event (``std_msgs/String`` JSON, see ``docs/ros.md``);
    ``goal`` is the ``started`` event's ``goal`` (x, y) in ``map`` or None.

    ``ValueError`` for text that is not such an event or a goal that is not two finite numbers.
    """
    try:
        body = json.loads(msg.data)
    except json.JSONDecodeError as err:
        raise ValueError(f"event is not JSON ({err.msg})") from None
    if not isinstance(body, dict) or body.get("format") != EVENT_FORMAT:
        raise ValueError(f"not a {EVENT_FORMAT} message")
    kind = body.get("event")
    if kind not in EVENT_KINDS:
        raise ValueError(f"unknown event {kind!r}")
    raw = body.get("goal")
    if raw is None:
        return str(kind), None
    if (
        not isinstance(raw, list)
        or len(raw) != 2
        or not all(isinstance(v, int | float) and math.isfinite(v) for v in raw)
    ):
        raise ValueError(f"event goal {raw!r} is not two finite numbers")
    return str(kind), (float(raw[0]), float(raw[1]))


def twist_from_action(dtheta: float, ds: float, dt: float) -> Twist:
    """Command for one decision: ``angular.z = dtheta/dt`` (rad/s), ``linear.x = ds/dt`` (m/s).

    The robot then drives the exact unicycle arc with end heading ``theta + dtheta`` and path
    length ``ds`` over ``dt`` s. ``ValueError`` for non-finite values or ``dt <= 0``.
    """
    if not (math.isfinite(dtheta) and math.isfinite(ds)):
        raise ValueError(f"non-finite action (dtheta={dtheta}, ds={ds})")
    angular_z, linear_x = _twist_from_action(dtheta, ds, dt)
    return Twist(linear=Vector3(x=float(linear_x)), angular=Vector3(z=float(angular_z)))


#: frames a map or a path may come in (the simulator's arena frame; '' taken as it)
PLAN_FRAMES = (MAP_FRAME, "")


def _check_frame(frame_id: str, what: str) -> None:
    if frame_id not in PLAN_FRAMES:
        raise ValueError(f"{what} frame {frame_id!r} is not {MAP_FRAME!r}")


def grid_from_occupancy_grid(msg: OccupancyGridMsg) -> OccupancyGrid:
    """The grid of a ``nav_msgs/OccupancyGrid`` in ``map`` (an empty frame is taken as
    ``map``); ``ValueError`` for another frame, a data length other than width x height, or a
    bad resolution, origin or value."""
    _check_frame(msg.header.frame_id, "map")
    info = msg.info
    width, height = int(info.width), int(info.height)
    data = np.asarray(msg.data, dtype=np.int8)
    if width * height == 0 or data.size != width * height:
        raise ValueError(f"map has {data.size} cells for {width} x {height}")
    p, q = info.origin.position, info.origin.orientation
    if not all(math.isfinite(v) for v in (p.x, p.y, q.x, q.y, q.z, q.w)):
        raise ValueError("map origin is not finite")
    yaw = quaternion_to_yaw(q.x, q.y, q.z, q.w) if (q.x, q.y, q.z, q.w) != (0, 0, 0, 0) else 0.0
    return OccupancyGrid(
        float(info.resolution), (float(p.x), float(p.y), yaw), data.reshape(height, width)
    )


def path_from_msg(msg: Path) -> NDArray[np.float64]:
    """Points ``(k, 2)`` (m, ``map``) of a ``nav_msgs/Path``; ``ValueError`` for an empty
    path, another frame (of the path or a pose) or a non-finite point."""
    _check_frame(msg.header.frame_id, "path")
    if not msg.poses:
        raise ValueError("path has no poses")
    for pose in msg.poses:
        if pose.header.frame_id:
            _check_frame(pose.header.frame_id, "path pose")
    points = np.array(
        [(p.pose.position.x, p.pose.position.y) for p in msg.poses], dtype=np.float64
    )
    if not np.isfinite(points).all():
        raise ValueError("path holds a non-finite point")
    return points


def pose_stamped(pose: ArrayLike, frame_id: str, stamp: Time) -> PoseStamped:
    """A ``geometry_msgs/PoseStamped`` of the planar pose ``(x, y, yaw)`` (m, rad)."""
    x, y, yaw = (float(v) for v in np.asarray(pose, dtype=np.float64).reshape(3))
    return PoseStamped(header=Header(stamp=stamp, frame_id=frame_id),
                       pose=Pose(position=Point(x=x, y=y, z=0.0),
                                 orientation=quaternion_msg(yaw)))  # fmt: skip


def path_msg(points: ArrayLike, stamp: Time, frame_id: str = MAP_FRAME) -> Path:
    """A ``nav_msgs/Path`` in ``frame_id`` (default ``map``) through ``points`` ``(k, 2)``
    (m); each pose faces along its segment (the last one along the last segment)."""
    p = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    step = np.diff(p, axis=0)
    yaws = np.arctan2(step[:, 1], step[:, 0]) if len(p) > 1 else np.zeros(0)
    yaws = np.append(yaws, yaws[-1] if len(yaws) else 0.0)
    header = Header(stamp=stamp, frame_id=frame_id)
    poses = []
    for (x, y), yaw in zip(p.tolist(), yaws.tolist(), strict=True):
        pose = Pose(position=Point(x=x, y=y, z=0.0), orientation=quaternion_msg(yaw))
        poses.append(PoseStamped(header=header, pose=pose))
    return Path(header=header, poses=poses)
