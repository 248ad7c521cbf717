"""rosbag2 (MCAP) bags of MENTOR scenarios and episodes, written and read with ``rosbags``.

No rclpy here: messages are built and parsed with rosbags' ``ROS2_JAZZY`` typestore, so that
``ros2 bag info/play`` on Jazzy and Foxglove open the bags. Only standard message types are
used.

Scenario bag (``format: mentor-scenario-bag``, version 1), every message at bag time 0:

=====================  =============================  ==========================================
topic                  type                           content
=====================  =============================  ==========================================
``/mentor/metadata``   ``std_msgs/msg/String``        JSON: format, version, profile, arena size,
                                                      world name, scenario count, user metadata
``/mentor/obstacles``  ``visualization_msgs/msg/      ns ``arena``: LINE_STRIP around the arena;
                       MarkerArray``                  ns ``obstacles``: one CUBE per box (pose =
                                                      centre, scale = size, frame ``map``);
                                                      ``points`` = the exact corners
                                                      ``(xmin, ymin, 0), (xmax, ymax, h)``
``/mentor/starts``     ``geometry_msgs/msg/PoseArray``  one pose per scenario, yaw quaternion
``/mentor/goals``      ``geometry_msgs/msg/PoseArray``  one pose per scenario, identity rotation
=====================  =============================  ==========================================

Episode bag (``format: mentor-episode-bag``, version 1): ``/mentor/metadata`` as above (with
the robot namespaces) and, per robot namespace ``<ns>``, ``/<ns>/scan``
(``sensor_msgs/LaserScan``, +inf out of range, REP-117), ``/<ns>/odom`` (``nav_msgs/Odometry``,
``odom`` -> ``<ns>/base_link``), ``/<ns>/cmd_vel`` (``geometry_msgs/Twist``), ``/<ns>/goal``
(``geometry_msgs/PoseStamped`` in ``map``) and ``/<ns>/events`` (``std_msgs/String`` JSON).
Bag times and header stamps are simulation time in ns.

Round trips are exact except where the message type forces a conversion: headings travel as
yaw quaternions (back to within 1e-12 rad) and LaserScan ranges are float32 (a read gives
the float32 values; writing what was read is lossless).

Writing is all-or-nothing: the bag is written into a temporary folder beside the target and
renamed into place. Reading raises :class:`~mentor_core.errors.FileFormatError` for a missing,
truncated, corrupt or foreign bag.
"""

from __future__ import annotations

import json
import math
import os
import re
import shutil
import struct
import tempfile
from collections.abc import Callable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path
from typing import TYPE_CHECKING, Any, Final, Literal, cast, get_args

import numpy as np
from numpy.typing import ArrayLike, NDArray
from rosbags.interfaces import (
    Nodetype,
    Qos,
    QosDurability,
    QosHistory,
    QosLiveliness,
    QosReliability,
    QosTime,
)
from rosbags.rosbag2 import Reader, StoragePlugin, Writer
from rosbags.rosbag2.errors import ReaderError
from rosbags.serde import SerdeError
from rosbags.typesys import Stores, get_typestore

from mentor_core.errors import FileFormatError, is_version

if TYPE_CHECKING:
    from rosbags.typesys.store import Typestore

    from mentor_core.robots import RobotProfile
    from mentor_core.world import Scenario, World

SCENARIO_FORMAT: Final = "mentor-scenario-bag"
EPISODE_FORMAT: Final = "mentor-episode-bag"
EVENT_FORMAT: Final = "mentor-episode-event"
VERSION: Final = 1
ROSBAG2_VERSION: Final = 9  # rosbag2 metadata version written (Jazzy writes 9)

METADATA_TOPIC: Final = "/mentor/metadata"
OBSTACLES_TOPIC: Final = "/mentor/obstacles"
STARTS_TOPIC: Final = "/mentor/starts"
GOALS_TOPIC: Final = "/mentor/goals"
MAP_FRAME: Final = "map"
ODOM_FRAME: Final = "odom"
OBSTACLE_HEIGHT: Final = 0.5  # m, only for display (the world is 2-D)
ARENA_LINE_WIDTH: Final = 0.05  # m, only for display
MARKER_CUBE: Final = 1  # visualization_msgs/Marker.CUBE
MARKER_LINE_STRIP: Final = 4  # visualization_msgs/Marker.LINE_STRIP

EventKind = Literal["started", "reached", "collided", "timed_out"]
EVENT_KINDS: Final[tuple[str, ...]] = get_args(EventKind)

_NS_RE: Final = re.compile(r"^[A-Za-z][A-Za-z0-9_]*(/[A-Za-z][A-Za-z0-9_]*)*$")
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


def yaw_to_quaternion(theta: float) -> tuple[float, float, float, float]:
    """Quaternion ``(x, y, z, w)`` of a rotation by ``theta`` (rad) about +z."""
    half = 0.5 * float(theta)
    return (0.0, 0.0, math.sin(half), math.cos(half))


def quaternion_to_yaw(x: float, y: float, z: float, w: float) -> float:
    """Yaw (rad, wrapped to ``(-pi, pi]``) of a quaternion; roll and pitch are ignored."""
    yaw = math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))
    if x == 0.0 and y == 0.0:
        # pure yaw: this form is exact to a few ulp, also near +-pi
        if w < 0.0:
            z, w = -z, -w
        yaw = 2.0 * math.atan2(z, w)
    return math.pi if yaw <= -math.pi else yaw


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
# Episode records
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class ScanRecord:
    """One range scan: sim time (ns) and ranges (m, sensor order, +inf out of range)."""

    stamp_ns: int
    ranges: tuple[float, ...]


@dataclass(frozen=True)
class OdomRecord:
    """Odometry: pose ``(x, y, theta)`` (m, m, rad) in ``odom`` (= ``map`` in the sim) and
    body twist ``(v, omega)`` (m/s along body x, rad/s about z)."""

    stamp_ns: int
    pose: tuple[float, float, float]
    twist: tuple[float, float]


@dataclass(frozen=True)
class CmdRecord:
    """A velocity command: ``linear_x = ds/dt`` (m/s), ``angular_z = dtheta/dt`` (rad/s)."""

    stamp_ns: int
    linear_x: float
    angular_z: float


@dataclass(frozen=True)
class GoalRecord:
    """A goal ``(x, y)`` (m, ``map`` frame) given at ``stamp_ns``."""

    stamp_ns: int
    goal: tuple[float, float]


@dataclass(frozen=True)
class EventRecord:
    """An episode event; ``scenario`` is the scenario index or -1 when not given."""

    stamp_ns: int
    kind: EventKind
    scenario: int = -1


@dataclass(frozen=True)
class RobotEpisode:
    """Everything recorded for one robot namespace (``ns`` without leading slash)."""

    namespace: str
    scans: tuple[ScanRecord, ...] = ()
    odometry: tuple[OdomRecord, ...] = ()
    commands: tuple[CmdRecord, ...] = ()
    goals: tuple[GoalRecord, ...] = ()
    events: tuple[EventRecord, ...] = ()


@dataclass(frozen=True)
class EpisodeLog:
    """The content of an episode bag."""

    profile_name: str
    robots: tuple[RobotEpisode, ...]
    metadata: Mapping[str, Any] = field(default_factory=dict)
    world: World | None = None  # when the bag holds /mentor/obstacles


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


def _stamp_ns(header: Any) -> int:
    return int(header.stamp.sec) * 1_000_000_000 + int(header.stamp.nanosec)


def _point(ts: Typestore, x: float, y: float, z: float = 0.0) -> Any:
    return _msg(ts, "geometry_msgs/msg/Point", x=float(x), y=float(y), z=float(z))


def _pose(ts: Typestore, x: float, y: float, theta: float = 0.0, z: float = 0.0) -> Any:
    qx, qy, qz, qw = yaw_to_quaternion(theta)
    q = _msg(ts, "geometry_msgs/msg/Quaternion", x=qx, y=qy, z=qz, w=qw)
    return _msg(ts, "geometry_msgs/msg/Pose", position=_point(ts, x, y, z), orientation=q)


def _pose_xyt(pose: Any) -> tuple[float, float, float]:
    q = pose.orientation
    theta = quaternion_to_yaw(float(q.x), float(q.y), float(q.z), float(q.w))
    return (float(pose.position.x), float(pose.position.y), theta)


def _string(ts: Typestore, obj: Mapping[str, Any]) -> Any:
    return _msg(ts, "std_msgs/msg/String", data=json.dumps(obj, allow_nan=False, sort_keys=True))


# --------------------------------------------------------------------------------------------
# Writing
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class _Topic:
    name: str
    msgtype: str
    qos: Qos


@dataclass(frozen=True)
class _Out:
    topic: str
    msgtype: str
    stamp_ns: int
    message: Any


def _looks_like_bag(path: Path) -> bool:
    return path.is_dir() and ((path / "metadata.yaml").is_file() or not any(path.iterdir()))


def _write_bag(
    path: str | Path, topics: Sequence[_Topic], out: Sequence[_Out], overwrite: bool
) -> None:
    """Write ``out`` (in order) on ``topics`` (registered in that order, even when empty) as a
    rosbag2 MCAP bag at ``path``, all or nothing."""
    target = Path(path)
    if target.exists() or target.is_symlink():
        if not overwrite:
            raise FileExistsError(f"{target}: exists already (pass overwrite=True to replace it)")
        if not _looks_like_bag(target):
            raise FileExistsError(f"{target}: exists and is not a rosbag2 bag; not replacing it")
    target.parent.mkdir(parents=True, exist_ok=True)
    ts = _store()
    staging = Path(tempfile.mkdtemp(prefix=f".{target.name}.", suffix=".tmp", dir=target.parent))
    try:
        fresh = staging / target.name
        writer = Writer(fresh, version=ROSBAG2_VERSION, storage_plugin=StoragePlugin.MCAP)
        writer.open()
        try:
            connections = {
                t.name: writer.add_connection(
                    t.name,
                    t.msgtype,
                    typestore=ts,
                    serialization_format="cdr",
                    offered_qos_profiles=[t.qos],
                )
                for t in topics
            }
            for item in out:
                data = ts.serialize_cdr(item.message, item.msgtype)
                writer.write(connections[item.topic], item.stamp_ns, data)
        except BaseException:
            writer.abort()
            raise
        writer.close()
        for name in os.listdir(fresh):
            with open(fresh / name, "rb") as handle:
                os.fsync(handle.fileno())
        if target.exists() or target.is_symlink():
            old = staging / ".replaced"
            os.replace(target, old)
            try:
                os.replace(fresh, target)
            except BaseException:
                os.replace(old, target)
                raise
        else:
            os.replace(fresh, target)
    finally:
        shutil.rmtree(staging, ignore_errors=True)


def _check_stamps(what: str, stamps: Sequence[int]) -> None:
    prev = 0
    for s in stamps:
        if not isinstance(s, int | np.integer) or s < prev:
            raise ValueError(f"{what}: stamps must be non-decreasing integers >= 0 (ns)")
        prev = int(s)


def _metadata_json(meta: Mapping[str, Any] | None) -> dict[str, Any]:
    user = dict(meta or {})
    try:
        json.dumps(user, allow_nan=False)
    except (TypeError, ValueError) as err:
        raise ValueError(f"metadata must be JSON serialisable without NaN/inf: {err}") from None
    return user


def _world_markers(ts: Typestore, world: World) -> list[Any]:
    """The arena outline and one CUBE marker per obstacle (see the module docstring)."""
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


def write_scenario_bag(
    path: str | Path,
    world: World,
    scenarios: Sequence[Scenario],
    profile_name: str,
    metadata: Mapping[str, Any] | None = None,
    *,
    overwrite: bool = False,
) -> None:
    """Write ``world`` and its start/goal ``scenarios`` for robot ``profile_name`` as a bag.

    ``metadata`` is any JSON-serialisable mapping (kept under ``metadata`` in the JSON on
    ``/mentor/metadata``). Raises ``FileExistsError`` when ``path`` exists and ``overwrite``
    is false, ``ValueError`` for a scenario of another world or bad metadata.
    """
    ts = _store()
    for i, sc in enumerate(scenarios):
        if sc.world is not world and sc.world != world:
            raise ValueError(f"scenario {i} belongs to another world")
    size = float(world.size)
    head = {
        "format": SCENARIO_FORMAT,
        "version": VERSION,
        "profile": str(profile_name),
        "arena_size": size,
        "world_name": str(world.name),
        "n_scenarios": len(scenarios),
        "n_obstacles": int(np.asarray(world.obstacles).reshape(-1, 4).shape[0]),
        "metadata": _metadata_json(metadata),
    }
    starts = [_pose(ts, sc.start[0], sc.start[1], sc.start[2]) for sc in scenarios]
    goals = [_pose(ts, sc.goal[0], sc.goal[1]) for sc in scenarios]
    topics = [
        _Topic(METADATA_TOPIC, "std_msgs/msg/String", QOS_LATCHED),
        _Topic(OBSTACLES_TOPIC, "visualization_msgs/msg/MarkerArray", QOS_LATCHED),
        _Topic(STARTS_TOPIC, "geometry_msgs/msg/PoseArray", QOS_LATCHED),
        _Topic(GOALS_TOPIC, "geometry_msgs/msg/PoseArray", QOS_LATCHED),
    ]
    messages = [
        _string(ts, head),
        _msg(ts, "visualization_msgs/msg/MarkerArray", markers=_world_markers(ts, world)),
        _msg(ts, "geometry_msgs/msg/PoseArray", header=_header(ts, 0, MAP_FRAME), poses=starts),
        _msg(ts, "geometry_msgs/msg/PoseArray", header=_header(ts, 0, MAP_FRAME), poses=goals),
    ]
    out = [_Out(t.name, t.msgtype, 0, m) for t, m in zip(topics, messages, strict=True)]
    _write_bag(path, topics, out, overwrite)


def _robot_topics(ns: str) -> dict[str, str]:
    return {
        "scan": f"/{ns}/scan",
        "odom": f"/{ns}/odom",
        "cmd_vel": f"/{ns}/cmd_vel",
        "goal": f"/{ns}/goal",
        "events": f"/{ns}/events",
    }


def write_episode_bag(
    path: str | Path,
    robots: Sequence[RobotEpisode],
    profile: RobotProfile,
    metadata: Mapping[str, Any] | None = None,
    *,
    world: World | None = None,
    overwrite: bool = False,
) -> None:
    """Write recorded robot episodes (one namespace each) as a bag; see the module docstring.

    Every scan must hold ``profile.n_sensors`` ranges (m; +inf out of range, no NaN); stamps
    are sim time in ns, non-decreasing per topic. ``world``, when given, is written as
    ``/mentor/obstacles`` at time 0 (as in a scenario bag). Raises ``ValueError`` for bad
    records, ``FileExistsError`` when ``path`` exists and ``overwrite`` is false.
    """
    ts = _store()
    names = [r.namespace for r in robots]
    for ns in names:
        if not _NS_RE.match(ns):
            raise ValueError(f"robot namespace {ns!r} is not a relative ROS name like 'robot_0'")
    if len(set(names)) != len(names):
        raise ValueError("robot namespaces must be unique")
    geo = scan_geometry(profile)
    head = {
        "format": EPISODE_FORMAT,
        "version": VERSION,
        "profile": str(profile.name),
        "namespaces": names,
        "metadata": _metadata_json(metadata),
    }
    if world is not None:
        head["arena_size"] = float(world.size)
        head["world_name"] = str(world.name)
        head["n_obstacles"] = int(np.asarray(world.obstacles).reshape(-1, 4).shape[0])
    topics = [_Topic(METADATA_TOPIC, "std_msgs/msg/String", QOS_LATCHED)]
    first = [_Out(METADATA_TOPIC, "std_msgs/msg/String", 0, _string(ts, head))]
    if world is not None:
        topics.append(_Topic(OBSTACLES_TOPIC, "visualization_msgs/msg/MarkerArray", QOS_LATCHED))
        markers = _msg(ts, "visualization_msgs/msg/MarkerArray", markers=_world_markers(ts, world))
        first.append(_Out(OBSTACLES_TOPIC, "visualization_msgs/msg/MarkerArray", 0, markers))
    timed: list[tuple[int, int, _Out]] = []  # (stamp, order, item): written in time order

    def add(item: _Out) -> None:
        timed.append((item.stamp_ns, len(timed), item))

    for robot in robots:
        ns = robot.namespace
        topic = _robot_topics(ns)
        base = f"{ns}/base_link"
        for what, stamps in (
            ("scans", [r.stamp_ns for r in robot.scans]),
            ("odometry", [r.stamp_ns for r in robot.odometry]),
            ("commands", [r.stamp_ns for r in robot.commands]),
            ("goals", [r.stamp_ns for r in robot.goals]),
            ("events", [r.stamp_ns for r in robot.events]),
        ):
            _check_stamps(f"{ns} {what}", stamps)
        # register every topic, even an empty one, so readers find all five
        for key, mtype, qos in (
            ("scan", "sensor_msgs/msg/LaserScan", QOS_SENSOR),
            ("odom", "nav_msgs/msg/Odometry", QOS_SENSOR),
            ("cmd_vel", "geometry_msgs/msg/Twist", QOS_COMMAND),
            ("goal", "geometry_msgs/msg/PoseStamped", QOS_LATCHED),
            ("events", "std_msgs/msg/String", QOS_COMMAND),
        ):
            topics.append(_Topic(topic[key], mtype, qos))
        for scan in robot.scans:
            ranges = np.asarray(scan.ranges, dtype=np.float64)
            if ranges.shape != (profile.n_sensors,):
                raise ValueError(
                    f"{ns} scan at {scan.stamp_ns} ns: {ranges.size} ranges, profile "
                    f"{profile.name!r} has {profile.n_sensors} sensors"
                )
            if np.isnan(ranges).any():
                raise ValueError(f"{ns} scan at {scan.stamp_ns} ns: NaN range")
            msg = _msg(
                ts,
                "sensor_msgs/msg/LaserScan",
                header=_header(ts, scan.stamp_ns, base),
                angle_min=geo.angle_min,
                angle_max=geo.angle_max,
                angle_increment=geo.angle_increment,
                range_min=geo.range_min,
                range_max=geo.range_max,
                ranges=ranges.astype(np.float32),
            )
            add(_Out(topic["scan"], "sensor_msgs/msg/LaserScan", scan.stamp_ns, msg))
        for od in robot.odometry:
            pose = _msg(ts, "geometry_msgs/msg/PoseWithCovariance", pose=_pose(ts, *od.pose))
            lin = _msg(ts, "geometry_msgs/msg/Vector3", x=float(od.twist[0]), y=0.0, z=0.0)
            ang = _msg(ts, "geometry_msgs/msg/Vector3", x=0.0, y=0.0, z=float(od.twist[1]))
            twist = _msg(
                ts,
                "geometry_msgs/msg/TwistWithCovariance",
                twist=_msg(ts, "geometry_msgs/msg/Twist", linear=lin, angular=ang),
            )
            msg = _msg(
                ts,
                "nav_msgs/msg/Odometry",
                header=_header(ts, od.stamp_ns, ODOM_FRAME),
                child_frame_id=base,
                pose=pose,
                twist=twist,
            )
            add(_Out(topic["odom"], "nav_msgs/msg/Odometry", od.stamp_ns, msg))
        for cmd in robot.commands:
            if not (math.isfinite(cmd.linear_x) and math.isfinite(cmd.angular_z)):
                raise ValueError(f"{ns} command at {cmd.stamp_ns} ns is not finite")
            lin = _msg(ts, "geometry_msgs/msg/Vector3", x=float(cmd.linear_x), y=0.0, z=0.0)
            ang = _msg(ts, "geometry_msgs/msg/Vector3", x=0.0, y=0.0, z=float(cmd.angular_z))
            msg = _msg(ts, "geometry_msgs/msg/Twist", linear=lin, angular=ang)
            add(_Out(topic["cmd_vel"], "geometry_msgs/msg/Twist", cmd.stamp_ns, msg))
        for goal in robot.goals:
            msg = _msg(
                ts,
                "geometry_msgs/msg/PoseStamped",
                header=_header(ts, goal.stamp_ns, MAP_FRAME),
                pose=_pose(ts, goal.goal[0], goal.goal[1]),
            )
            add(_Out(topic["goal"], "geometry_msgs/msg/PoseStamped", goal.stamp_ns, msg))
        for ev in robot.events:
            if ev.kind not in EVENT_KINDS:
                raise ValueError(f"{ns} event {ev.kind!r} is not one of {list(EVENT_KINDS)}")
            body = {
                "format": EVENT_FORMAT,
                "version": VERSION,
                "event": ev.kind,
                "scenario": int(ev.scenario),
            }
            add(_Out(topic["events"], "std_msgs/msg/String", ev.stamp_ns, _string(ts, body)))
    timed.sort(key=lambda t: (t[0], t[1]))
    _write_bag(path, topics, [*first, *(t[2] for t in timed)], overwrite)


# --------------------------------------------------------------------------------------------
# Reading
# --------------------------------------------------------------------------------------------

_CORRUPT: Final = (
    ReaderError,
    SerdeError,
    OSError,
    ValueError,
    KeyError,
    IndexError,
    TypeError,
    AttributeError,
    AssertionError,
    struct.error,
    EOFError,
)


def _one_line(err: BaseException) -> str:
    text = " ".join(str(err).split()) or type(err).__name__
    return text if len(text) <= 300 else text[:297] + "..."


@contextmanager
def _faults(path: Path) -> Iterator[None]:
    try:
        yield
    except FileFormatError:
        raise
    except KeyError as err:
        raise FileFormatError(path, f"unreadable bag: missing key {err.args[0]!r}") from err
    except _CORRUPT as err:
        raise FileFormatError(path, f"unreadable bag: {_one_line(err)}") from err


def _read_topics(
    path: str | Path, fmt: str, topics: Callable[[dict[str, Any]], dict[str, str]]
) -> tuple[dict[str, Any], dict[str, list[tuple[int, Any]]]]:
    """Open the bag, check its ``/mentor/metadata`` format/version, read the wanted topics.

    ``topics(head)`` gives ``{topic: msgtype}`` from the metadata JSON; each must exist with
    that type. Returns the metadata JSON and ``{topic: [(bag time ns, message), ...]}``.
    """
    p = Path(path)
    if not p.exists():
        raise FileFormatError(p, "no such bag")
    if not p.is_dir():
        raise FileFormatError(p, "not a rosbag2 bag folder")
    if not (p / "metadata.yaml").is_file():
        raise FileFormatError(p, "not a rosbag2 bag: metadata.yaml is missing")
    ts = _store()
    with _faults(p), Reader(p) as reader:
        conns = {c.topic: c for c in reader.connections}
        meta_conn = conns.get(METADATA_TOPIC)
        if meta_conn is None or meta_conn.msgtype != "std_msgs/msg/String":
            raise FileFormatError(p, f"not a {fmt}: no {METADATA_TOPIC} topic")
        head: Any = None
        for _, _, raw in reader.messages(connections=[meta_conn]):
            text: Any = ts.deserialize_cdr(raw, "std_msgs/msg/String")
            head = json.loads(text.data)
            break
        if not isinstance(head, dict) or head.get("format") != fmt:
            found = head.get("format") if isinstance(head, dict) else None
            raise FileFormatError(p, f"not a {fmt} (format {found!r})")
        if not is_version(head.get("version"), VERSION):
            raise FileFormatError(
                p, f"{fmt} version {head.get('version')!r} is not supported (reads {VERSION})"
            )
        try:
            wanted = topics(head)
        except (KeyError, TypeError, ValueError) as err:
            raise FileFormatError(p, f"bad {METADATA_TOPIC} content: {_one_line(err)}") from err
        for topic, mtype in wanted.items():
            conn = conns.get(topic)
            if conn is None:
                raise FileFormatError(p, f"topic {topic} is missing")
            if conn.msgtype != mtype:
                raise FileFormatError(p, f"topic {topic} has type {conn.msgtype}, not {mtype}")
        data: dict[str, list[tuple[int, Any]]] = {t: [] for t in wanted}
        chosen = [conns[t] for t in wanted]
        for conn, stamp, raw in reader.messages(connections=chosen):
            data[conn.topic].append((int(stamp), ts.deserialize_cdr(raw, conn.msgtype)))
    return head, data


def _single(path: str | Path, data: dict[str, list[tuple[int, Any]]], topic: str) -> Any:
    msgs = data[topic]
    if len(msgs) != 1:
        raise FileFormatError(path, f"topic {topic} holds {len(msgs)} messages, expected 1")
    return msgs[0][1]


def _world_from_markers(p: Path, head: dict[str, Any], markers: Any) -> World:
    """The world of a ``/mentor/obstacles`` MarkerArray and the metadata's arena size."""
    from mentor_core.world import World

    size = float(head["arena_size"])
    boxes: list[tuple[int, list[float]]] = []
    for mk in markers.markers:
        if mk.ns != "obstacles":
            continue
        if int(mk.type) != MARKER_CUBE:
            raise FileFormatError(p, f"obstacle marker {mk.id} is not a CUBE")
        q = mk.pose.orientation
        if abs(quaternion_to_yaw(q.x, q.y, q.z, q.w)) > 1e-9:
            raise FileFormatError(p, f"obstacle marker {mk.id} is not axis-aligned")
        if len(mk.points) == 2:
            a, b = mk.points
            box = [a.x, a.y, b.x, b.y]
        else:  # a CUBE from another tool: centre and size only
            cx, cy, sx, sy = mk.pose.position.x, mk.pose.position.y, mk.scale.x, mk.scale.y
            box = [cx - 0.5 * sx, cy - 0.5 * sy, cx + 0.5 * sx, cy + 0.5 * sy]
        boxes.append((int(mk.id), [float(v) for v in box]))
    boxes.sort(key=lambda t: t[0])
    if "n_obstacles" in head and len(boxes) != int(head["n_obstacles"]):
        raise FileFormatError(
            p, f"{len(boxes)} obstacle markers, metadata says {head['n_obstacles']}"
        )
    obstacles: NDArray[np.float64] = np.array([b for _, b in boxes], dtype=np.float64).reshape(
        -1, 4
    )
    world = World(size=size, obstacles=obstacles, name=str(head.get("world_name", "")))
    return world


def read_scenario_bag(
    path: str | Path,
) -> tuple[World, list[Scenario], str, dict[str, Any]]:
    """Read a bag written by :func:`write_scenario_bag`.

    Returns ``(world, scenarios, profile_name, metadata)``; ``FileFormatError`` for anything
    missing, corrupt, foreign or of another version.
    """
    from mentor_core.world import Scenario

    wanted = {
        OBSTACLES_TOPIC: "visualization_msgs/msg/MarkerArray",
        STARTS_TOPIC: "geometry_msgs/msg/PoseArray",
        GOALS_TOPIC: "geometry_msgs/msg/PoseArray",
    }
    head, data = _read_topics(path, SCENARIO_FORMAT, lambda _h: wanted)
    p = Path(path)
    with _faults(p):
        world = _world_from_markers(p, head, _single(p, data, OBSTACLES_TOPIC))
        starts = _single(p, data, STARTS_TOPIC).poses
        goals = _single(p, data, GOALS_TOPIC).poses
        if len(starts) != len(goals) or len(starts) != int(head["n_scenarios"]):
            raise FileFormatError(
                p,
                f"{len(starts)} starts and {len(goals)} goals for {head['n_scenarios']} scenarios",
            )
        scenarios = [
            Scenario(
                world=world,
                start=_pose_xyt(s),
                goal=(float(g.position.x), float(g.position.y)),
            )
            for s, g in zip(starts, goals, strict=True)
        ]
        meta = head.get("metadata", {})
        if not isinstance(meta, dict):
            raise FileFormatError(p, "metadata in /mentor/metadata is not a JSON object")
        return world, scenarios, str(head["profile"]), meta


def _episode_topics(head: dict[str, Any]) -> dict[str, str]:
    names = head["namespaces"]
    if not isinstance(names, list) or not all(isinstance(n, str) for n in names):
        raise ValueError("namespaces must be a list of strings")
    wanted: dict[str, str] = {}
    for ns in names:
        t = _robot_topics(ns)
        wanted[t["scan"]] = "sensor_msgs/msg/LaserScan"
        wanted[t["odom"]] = "nav_msgs/msg/Odometry"
        wanted[t["cmd_vel"]] = "geometry_msgs/msg/Twist"
        wanted[t["goal"]] = "geometry_msgs/msg/PoseStamped"
        wanted[t["events"]] = "std_msgs/msg/String"
    if "arena_size" in head:
        wanted[OBSTACLES_TOPIC] = "visualization_msgs/msg/MarkerArray"
    return wanted


def read_episode_bag(path: str | Path) -> EpisodeLog:
    """Read a bag written by :func:`write_episode_bag` (``FileFormatError`` on any fault)."""
    head, data = _read_topics(path, EPISODE_FORMAT, _episode_topics)
    p = Path(path)
    robots = []
    with _faults(p):
        for ns in head["namespaces"]:
            t = _robot_topics(ns)
            scans = tuple(
                ScanRecord(_stamp_ns(m.header), tuple(float(r) for r in m.ranges))
                for _, m in data[t["scan"]]
            )
            odometry = tuple(
                OdomRecord(
                    _stamp_ns(m.header),
                    _pose_xyt(m.pose.pose),
                    (float(m.twist.twist.linear.x), float(m.twist.twist.angular.z)),
                )
                for _, m in data[t["odom"]]
            )
            commands = tuple(
                CmdRecord(stamp, float(m.linear.x), float(m.angular.z))
                for stamp, m in data[t["cmd_vel"]]
            )
            goals = tuple(
                GoalRecord(
                    _stamp_ns(m.header), (float(m.pose.position.x), float(m.pose.position.y))
                )
                for _, m in data[t["goal"]]
            )
            events = []
            for stamp, m in data[t["events"]]:
                body = json.loads(m.data)
                if body.get("event") not in EVENT_KINDS:
                    raise FileFormatError(p, f"{t['events']}: unknown event {body.get('event')!r}")
                events.append(
                    EventRecord(
                        stamp, cast(EventKind, body["event"]), int(body.get("scenario", -1))
                    )
                )
            robots.append(RobotEpisode(ns, scans, odometry, commands, goals, tuple(events)))
        meta = head.get("metadata", {})
        if not isinstance(meta, dict):
            raise FileFormatError(p, "metadata in /mentor/metadata is not a JSON object")
        world = (
            _world_from_markers(p, head, _single(p, data, OBSTACLES_TOPIC))
            if OBSTACLES_TOPIC in data
            else None
        )
        return EpisodeLog(str(head["profile"]), tuple(robots), meta, world)
