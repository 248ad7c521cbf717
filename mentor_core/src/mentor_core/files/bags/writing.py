"""Writing scenario and episode bags (layout: :mod:`mentor_core.files.bags.records`).

Writing is all-or-nothing: the bag is written into a temporary folder beside the target and
renamed into place.
"""

from __future__ import annotations

import glob
import json
import math
import os
import re
import shutil
import tempfile
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Final

import numpy as np
from rosbags.interfaces import Qos
from rosbags.rosbag2 import StoragePlugin, Writer

from mentor_core.atomic import temp_target
from mentor_core.errors import WriteFault
from mentor_core.files.bags.messages import (
    QOS_COMMAND,
    QOS_LATCHED,
    QOS_SENSOR,
    _header,
    _msg,
    _pose,
    _store,
    _string,
    _tf_message,
    _world_markers,
    scan_geometry,
)
from mentor_core.files.bags.records import (
    BAG_VERSION,
    EPISODE_FORMAT,
    EVENT_FORMAT,
    EVENT_KINDS,
    GOALS_TOPIC,
    METADATA_TOPIC,
    OBSTACLES_TOPIC,
    ROSBAG2_VERSION,
    SCENARIO_FORMAT,
    STARTS_TOPIC,
    TF_STATIC_TOPIC,
    TF_TOPIC,
    RobotEpisode,
    _robot_topics,
)
from mentor_core.sim.frames import MAP_FRAME, ODOM_FRAME
from mentor_core.sim.robot_description import FrameLink
from mentor_core.sim.transforms import Transform2D

if TYPE_CHECKING:
    from mentor_core.sim.robots import RobotProfile
    from mentor_core.sim.world import Scenario, World

_NS_RE: Final = re.compile(r"^[A-Za-z][A-Za-z0-9_]*(/[A-Za-z][A-Za-z0-9_]*)*$")


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


def looks_like_bag(path: str | Path) -> bool:
    """Whether ``path`` is a folder that a bag may replace: a rosbag2 bag (it holds a
    ``metadata.yaml``) or an empty folder."""
    path = Path(path)
    return path.is_dir() and ((path / "metadata.yaml").is_file() or not any(path.iterdir()))


def _write_bag(
    path: str | Path, topics: Sequence[_Topic], out: Sequence[_Out], overwrite: bool
) -> None:
    """Write ``out`` (in order) on ``topics`` (registered in that order, even when empty) as a
    rosbag2 MCAP bag at ``path``, all or nothing."""
    target = Path(path)
    if target.parent.is_dir():  # first: a bag a killed write moved aside comes back
        remove_stale_staging(target)
    if target.exists() or target.is_symlink():
        if not overwrite:
            raise FileExistsError(f"{target}: exists already (pass overwrite=True to replace it)")
        if not looks_like_bag(target):
            raise FileExistsError(f"{target}: exists and is not a rosbag2 bag; not replacing it")
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        staging = Path(
            tempfile.mkdtemp(prefix=f".{target.name}.", suffix=".tmp", dir=target.parent)
        )
    except OSError as err:
        raise WriteFault(target, err) from None
    try:
        _write_staged(staging, target, topics, out)
    except WriteFault:
        raise
    except OSError as err:  # a full disk names no file
        raise WriteFault(target, err) from None
    finally:
        shutil.rmtree(staging, ignore_errors=True)


def remove_stale_staging(target: Path) -> list[Path]:
    """Remove the staging folders (``.<name>.<8 characters>.tmp``) that writes of the bag
    ``target`` killed midway left beside it; returns them. A bag that such a write had moved
    aside to replace it (``<staging>/.replaced``) goes back to ``target`` when nothing took
    its place."""
    removed = []
    for entry in sorted(target.parent.glob(f".{glob.escape(target.name)}.*.tmp")):
        if temp_target(entry) != target or not entry.is_dir() or entry.is_symlink():
            continue
        moved = entry / ".replaced"
        if moved.is_dir() and not (target.exists() or target.is_symlink()):
            os.replace(moved, target)
        shutil.rmtree(entry, ignore_errors=True)
        removed.append(entry)
    return removed


def _write_staged(
    staging: Path, target: Path, topics: Sequence[_Topic], out: Sequence[_Out]
) -> None:
    """Write the bag in ``staging`` and rename it to ``target`` (the old one moved aside)."""
    ts = _store()
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
        "version": BAG_VERSION,
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


def write_episode_bag(
    path: str | Path,
    robots: Sequence[RobotEpisode],
    profile: RobotProfile,
    metadata: Mapping[str, Any] | None = None,
    *,
    world: World | None = None,
    overwrite: bool = False,
    static_frames: Sequence[FrameLink] | None = None,
) -> None:
    """Write recorded robot episodes (one namespace each) as a bag (layout: :mod:`.records`).

    Every scan must hold ``profile.n_sensors`` ranges (m; +inf out of range, no NaN); stamps
    are sim time in ns, non-decreasing per topic. ``world``, when given, is written as
    ``/mentor/obstacles`` at time 0 (as in a scenario bag). ``static_frames``, when given,
    are written on ``/tf_static`` at time 0, and every odometry record as its
    ``odom -> <ns>/base_link`` transform on ``/tf``. Raises ``ValueError`` for bad records,
    ``FileExistsError`` when ``path`` exists and ``overwrite`` is false.
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
        "version": BAG_VERSION,
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
    if static_frames is not None:
        topics.append(_Topic(TF_STATIC_TOPIC, "tf2_msgs/msg/TFMessage", QOS_LATCHED))
        topics.append(_Topic(TF_TOPIC, "tf2_msgs/msg/TFMessage", QOS_COMMAND))
        tree = _tf_message(ts, 0, static_frames)
        first.append(_Out(TF_STATIC_TOPIC, "tf2_msgs/msg/TFMessage", 0, tree))
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
            if static_frames is not None:
                moved = FrameLink(ODOM_FRAME, base, Transform2D(*od.pose))
                tf = _tf_message(ts, od.stamp_ns, [moved])
                add(_Out(TF_TOPIC, "tf2_msgs/msg/TFMessage", od.stamp_ns, tf))
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
                "version": BAG_VERSION,
                "event": ev.kind,
                "scenario": int(ev.scenario),
            }
            add(_Out(topic["events"], "std_msgs/msg/String", ev.stamp_ns, _string(ts, body)))
    timed.sort(key=lambda t: (t[0], t[1]))
    _write_bag(path, topics, [*first, *(t[2] for t in timed)], overwrite)
