"""MENTOR data as ROS message fields: the typestore, message builders, QoS and display geometry.

No rclpy here: messages are built and parsed with rosbags' ``ROS2_JAZZY`` typestore, so that
``ros2 bag info/play`` on Jazzy and Foxglove open the bags. Only standard message types are
used.

Round trips are exact except where the message type forces a conversion: headings travel as
yaw quaternions (back to within 1e-12 rad) and LaserScan ranges are float32 (a read gives
the float32 values; writing what was read is lossless).

The ``_``-prefixed builders are private to :mod:`mentor_core.files.bags`; the public names
(QoS profiles, :func:`scan_geometry`, :func:`box_markers`, :func:`arena_outline`) are shared
with the node packages, which fill rclpy messages with the same numbers.
"""

from __future__ import annotations

import json
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from functools import lru_cache
from typing import TYPE_CHECKING, Any, Final

import numpy as np
from numpy.typing import ArrayLike
from rosbags.interfaces import (
    Nodetype,
    Qos,
    QosDurability,
    QosHistory,
    QosLiveliness,
    QosReliability,
    QosTime,
)
from rosbags.typesys import Stores, get_typestore

from mentor_core.sim.frames import MAP_FRAME, yaw_to_quaternion

if TYPE_CHECKING:
    from rosbags.typesys.store import Typestore

    from mentor_core.sim.robot_description import FrameLink
    from mentor_core.sim.robots import RobotProfile
    from mentor_core.sim.world import World

OBSTACLE_HEIGHT: Final = 0.5  # m, only for display (the world is 2-D)
ARENA_LINE_WIDTH: Final = 0.05  # m, only for display
MARKER_CUBE: Final = 1  # visualization_msgs/Marker.CUBE
MARKER_LINE_STRIP: Final = 4  # visualization_msgs/Marker.LINE_STRIP

_INFINITE: Final = QosTime(sec=9223372036, nsec=854775807)  # rmw "infinite" duration


def _qos(depth: int, reliable: bool, latched: bool) -> Qos:
    return Qos(
        history=QosHistory.KEEP_LAST,
        depth=depth,
        reliability=QosReliability.RELIABLE if reliable else QosReliability.BEST_EFFORT,
        durability=QosDurability.TRANSIENT_LOCAL if latched else QosDurability.VOLATILE,
        deadline=_INFINITE,
        lifespan=_INFINITE,
        liveliness=QosLiveliness.AUTOMATIC,
        liveliness_lease_duration=_INFINITE,
        avoid_ros_namespace_conventions=False,
    )


#: Offered QoS recorded per topic kind: latched (transient local) for the static scene and
#: goals, sensor-data QoS (best effort, depth 5) for scan/odom, reliable depth 10 for commands.
QOS_LATCHED: Final = _qos(1, reliable=True, latched=True)
QOS_SENSOR: Final = _qos(5, reliable=False, latched=False)
QOS_COMMAND: Final = _qos(10, reliable=True, latched=False)

# --------------------------------------------------------------------------------------------
# Geometry shared with the node packages (they fill rclpy messages with the same numbers)
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class ScanGeometry:
    """LaserScan angle and range fields describing a robot's range sensors.

    Ranges travel in the profile's sensor order. A LaserScan cannot describe mounts at
    arbitrary positions and angles, so: ``angle_min``/``angle_max`` are the first/last mount
    angle (rad, body frame), ``angle_increment`` is the common step when the mount angles are
    evenly spaced and increasing, else 0 (irregular); ``range_min`` is 0 and ``range_max`` the
    sensor range (m).
    """

    angle_min: float
    angle_max: float
    angle_increment: float
    range_min: float
    range_max: float


def scan_geometry(profile: RobotProfile) -> ScanGeometry:
    """The :class:`ScanGeometry` of ``profile``'s sensors."""
    angles = profile.sensor_angles
    if angles.size == 0:
        return ScanGeometry(0.0, 0.0, 0.0, 0.0, float(profile.sensor_range))
    increment = 0.0
    if angles.size > 1:
        steps = np.diff(angles)
        if steps[0] > 0.0 and np.allclose(steps, steps[0], rtol=0.0, atol=1e-9):
            increment = float(steps[0])
    return ScanGeometry(
        float(angles[0]), float(angles[-1]), increment, 0.0, float(profile.sensor_range)
    )


@dataclass(frozen=True)
class BoxMarker:
    """Display geometry of one obstacle box: a CUBE marker plus its exact corners (m)."""

    id: int
    centre: tuple[float, float, float]
    scale: tuple[float, float, float]
    corners: tuple[tuple[float, float, float], tuple[float, float, float]]


def box_markers(obstacles: ArrayLike) -> list[BoxMarker]:
    """CUBE geometry of ``(k, 4)`` boxes ``[xmin, ymin, xmax, ymax]`` (m), ids ``0..k-1``."""
    boxes = np.asarray(obstacles, dtype=np.float64).reshape(-1, 4)
    out = []
    h = OBSTACLE_HEIGHT
    for i, (x0, y0, x1, y1) in enumerate(boxes.tolist()):
        out.append(
            BoxMarker(
                id=i,
                centre=(0.5 * (x0 + x1), 0.5 * (y0 + y1), 0.5 * h),
                scale=(x1 - x0, y1 - y0, h),
                corners=((x0, y0, 0.0), (x1, y1, h)),
            )
        )
    return out


def arena_outline(size: float) -> list[tuple[float, float, float]]:
    """Closed LINE_STRIP (5 points, m) around the arena ``[0, size] x [0, size]``."""
    s = float(size)
    return [(0.0, 0.0, 0.0), (s, 0.0, 0.0), (s, s, 0.0), (0.0, s, 0.0), (0.0, 0.0, 0.0)]


# --------------------------------------------------------------------------------------------
# rosbags message helpers
# --------------------------------------------------------------------------------------------


@lru_cache(maxsize=1)
def _store() -> Typestore:
    return get_typestore(Stores.ROS2_JAZZY)


_BASE_DEFAULTS: Final[dict[str, Any]] = {"string": "", "bool": False}


def _default_value(ts: Typestore, desc: tuple[Any, Any]) -> Any:
    kind, spec = desc
    if kind == Nodetype.BASE:
        name = spec[0]
        if name in _BASE_DEFAULTS:
            return _BASE_DEFAULTS[name]
        return 0.0 if name.startswith("float") else 0
    if kind == Nodetype.NAME:
        return _msg(ts, spec)
    inner, count = spec
    if inner[0] == Nodetype.BASE and inner[1][0] not in _BASE_DEFAULTS:
        dtype = np.dtype(inner[1][0].replace("byte", "uint8").replace("char", "uint8"))
        return np.zeros(count if kind == Nodetype.ARRAY else 0, dtype=dtype)
    if kind == Nodetype.ARRAY:
        return [_default_value(ts, inner) for _ in range(count)]
    return []


def _msg(ts: Typestore, typename: str, **fields: Any) -> Any:
    """A rosbags message of ``typename`` with defaults for every field not given."""
    values = {
        name: fields[name] if name in fields else _default_value(ts, desc)
        for name, desc in ts.fielddefs[typename][1]
    }
    return ts.types[typename](**values)


def _header(ts: Typestore, stamp_ns: int, frame_id: str) -> Any:
    sec, nanosec = divmod(int(stamp_ns), 1_000_000_000)
    stamp = _msg(ts, "builtin_interfaces/msg/Time", sec=sec, nanosec=nanosec)
    return _msg(ts, "std_msgs/msg/Header", stamp=stamp, frame_id=frame_id)


def _point(ts: Typestore, x: float, y: float, z: float = 0.0) -> Any:
    return _msg(ts, "geometry_msgs/msg/Point", x=float(x), y=float(y), z=float(z))


def _pose(ts: Typestore, x: float, y: float, theta: float = 0.0, z: float = 0.0) -> Any:
    qx, qy, qz, qw = yaw_to_quaternion(theta)
    q = _msg(ts, "geometry_msgs/msg/Quaternion", x=qx, y=qy, z=qz, w=qw)
    return _msg(ts, "geometry_msgs/msg/Pose", position=_point(ts, x, y, z), orientation=q)


def _tf_message(ts: Typestore, stamp_ns: int, links: Sequence[FrameLink]) -> Any:
    """A ``tf2_msgs/TFMessage`` of planar transforms (z 0), all stamped ``stamp_ns``."""
    transforms = []
    for link in links:
        t = link.transform
        qx, qy, qz, qw = yaw_to_quaternion(t.yaw)
        transforms.append(
            _msg(
                ts,
                "geometry_msgs/msg/TransformStamped",
                header=_header(ts, stamp_ns, link.parent),
                child_frame_id=link.child,
                transform=_msg(
                    ts,
                    "geometry_msgs/msg/Transform",
                    translation=_msg(ts, "geometry_msgs/msg/Vector3", x=t.x, y=t.y, z=0.0),
                    rotation=_msg(ts, "geometry_msgs/msg/Quaternion", x=qx, y=qy, z=qz, w=qw),
                ),
            )
        )
    return _msg(ts, "tf2_msgs/msg/TFMessage", transforms=transforms)


def _string(ts: Typestore, obj: Mapping[str, Any]) -> Any:
    return _msg(ts, "std_msgs/msg/String", data=json.dumps(obj, allow_nan=False, sort_keys=True))


def _world_markers(ts: Typestore, world: World) -> list[Any]:
    """The arena outline and one CUBE marker per obstacle (layout: :mod:`.records`)."""
    size = float(world.size)
    grey = _msg(ts, "std_msgs/msg/ColorRGBA", r=0.5, g=0.5, b=0.5, a=1.0)
    black = _msg(ts, "std_msgs/msg/ColorRGBA", r=0.0, g=0.0, b=0.0, a=1.0)
    markers = [
        _msg(
            ts,
            "visualization_msgs/msg/Marker",
            header=_header(ts, 0, MAP_FRAME),
            ns="arena",
            id=0,
            type=MARKER_LINE_STRIP,
            pose=_pose(ts, 0.0, 0.0),
            scale=_msg(ts, "geometry_msgs/msg/Vector3", x=ARENA_LINE_WIDTH, y=0.0, z=0.0),
            color=black,
            points=[_point(ts, *p) for p in arena_outline(size)],
        )
    ]
    for box in box_markers(world.obstacles):
        markers.append(
            _msg(
                ts,
                "visualization_msgs/msg/Marker",
                header=_header(ts, 0, MAP_FRAME),
                ns="obstacles",
                id=box.id,
                type=MARKER_CUBE,
                pose=_pose(ts, box.centre[0], box.centre[1], 0.0, box.centre[2]),
                scale=_msg(
                    ts, "geometry_msgs/msg/Vector3", x=box.scale[0], y=box.scale[1], z=box.scale[2]
                ),
                color=grey,
                points=[_point(ts, *c) for c in box.corners],
            )
        )
    return markers
