"""The TF tree of a bag, read with rosbags' own Reader and typestore (not mentor_core's)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from rosbags.rosbag2 import Reader
from rosbags.typesys import Stores, get_typestore

from mentor_core.sim.frames import quaternion_to_yaw
from mentor_core.sim.transforms import FrameTree, Transform2D


def tf_tree(bag: Path) -> tuple[FrameTree, dict[str, list[int]]]:
    """The static transforms of ``/tf_static`` and the first of each moving one of ``/tf`` as
    a :class:`FrameTree`, and the bag times (ns) of every moving child frame."""
    ts = get_typestore(Stores.ROS2_JAZZY)
    tree = FrameTree()
    stamps: dict[str, list[int]] = {}
    with Reader(bag) as reader:
        conns = [c for c in reader.connections if c.topic in ("/tf", "/tf_static")]
        assert {c.topic for c in conns} == {"/tf", "/tf_static"}
        assert all(c.msgtype == "tf2_msgs/msg/TFMessage" for c in conns)
        for conn, stamp, raw in reader.messages(connections=conns):
            msg: Any = ts.deserialize_cdr(raw, conn.msgtype)
            for t in msg.transforms:
                q, v = t.transform.rotation, t.transform.translation
                planar = Transform2D(v.x, v.y, quaternion_to_yaw(q.x, q.y, q.z, q.w))
                if conn.topic == "/tf":
                    stamps.setdefault(t.child_frame_id, []).append(stamp)
                    if len(stamps[t.child_frame_id]) > 1:
                        continue
                    assert t.header.stamp.sec * 10**9 + t.header.stamp.nanosec == stamp
                tree.link(t.header.frame_id, t.child_frame_id, planar)
    return tree, stamps
