"""Reading scenario and episode bags (layout: :mod:`mentor_core.files.bags.records`).

Reading raises :class:`~mentor_core.errors.FileFormatError` for a missing, truncated, corrupt
or foreign bag.
"""

from __future__ import annotations

import json
import struct
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING, Any, Final, cast

import numpy as np
from numpy.typing import NDArray
from rosbags.rosbag2 import Reader
from rosbags.rosbag2.errors import ReaderError
from rosbags.serde import SerdeError

from mentor_core.errors import FileFormatError, is_version
from mentor_core.files.bags.messages import MARKER_CUBE, _store
from mentor_core.files.bags.records import (
    BAG_VERSION,
    EPISODE_FORMAT,
    EVENT_KINDS,
    GOALS_TOPIC,
    METADATA_TOPIC,
    OBSTACLES_TOPIC,
    SCENARIO_FORMAT,
    STARTS_TOPIC,
    CmdRecord,
    EpisodeLog,
    EventKind,
    EventRecord,
    GoalRecord,
    OdomRecord,
    RobotEpisode,
    ScanRecord,
    _robot_topics,
)
from mentor_core.sim.frames import quaternion_to_yaw
from mentor_core.validation import read_yaml

if TYPE_CHECKING:
    from mentor_core.sim.world import Scenario, World

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
    RecursionError,
)



def _stamp_ns(header: Any) -> int:
    return int(header.stamp.sec) * 1_000_000_000 + int(header.stamp.nanosec)


def _pose_xyt(pose: Any) -> tuple[float, float, float]:
    q = pose.orientation
    theta = quaternion_to_yaw(float(q.x), float(q.y), float(q.z), float(q.w))
    return (float(pose.position.x), float(pose.position.y), theta)


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
    try:  # within the bounds of size, nesting and aliases before rosbags reads it
        read_yaml(p / "metadata.yaml")
    except FileFormatError as err:
        raise FileFormatError(p, f"unreadable bag: metadata.yaml: {err.fault}") from None
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
        if not is_version(head.get("version"), BAG_VERSION):
            raise FileFormatError(
                p, f"{fmt} version {head.get('version')!r} is not supported (reads {BAG_VERSION})"
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
    from mentor_core.sim.world import World

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
    from mentor_core.sim.world import Scenario

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
