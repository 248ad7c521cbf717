"""A robot's frames (REP-105) and its URDF, both from its profile, so they never disagree.

Frames of a robot in namespace ``ns`` (``<ns>/<link>``, or ``<link>`` without a namespace):

* ``base_link``: the body frame, origin at the body centre, x forward, y left;
* ``sensor_<i>``: range sensor ``i`` of the profile (reading order), at its mount ``(x, y)``
  facing its angle: x along its ray;
* ``lidar`` (when the robot has one): the frame of its laser scans, at the lidar's mount.

:func:`robot_links` gives the fixed transforms ``base_link -> sensor_<i>`` and
``base_link -> lidar`` (the simulator publishes them on ``/tf_static`` and writes them into its
bags); :func:`robot_urdf` the URDF with the same links and joints (the simulator publishes it on
``robot_description``): a box the size of the body, a small marker per sensor.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from dataclasses import dataclass

from mentor_core.sim.robots import RobotProfile
from mentor_core.sim.transforms import Transform2D

BASE_LINK = "base_link"
LIDAR_LINK = "lidar"
#: display heights (m): the world is 2-D, the URDF needs a third dimension
BODY_HEIGHT = 0.1
SENSOR_SIZE = 0.02


def frame_id(namespace: str, link: str) -> str:
    """The frame of ``link`` of the robot in ``namespace`` (``""``: no prefix)."""
    ns = namespace.strip("/")
    return f"{ns}/{link}" if ns else link


def sensor_link(index: int) -> str:
    """Link name of range sensor ``index`` (reading order)."""
    return f"sensor_{index}"


@dataclass(frozen=True)
class FrameLink:
    """A fixed or moving transform: the pose of frame ``child`` in frame ``parent``."""

    parent: str
    child: str
    transform: Transform2D


def robot_links(
    profile: RobotProfile, namespace: str = "", lidar: Transform2D | None = None
) -> list[FrameLink]:
    """The fixed transforms of a robot's frames (module docstring), sensors in reading order,
    then the lidar's (when ``lidar``, its mount on the body, is given)."""
    base = frame_id(namespace, BASE_LINK)
    links = [
        FrameLink(base, frame_id(namespace, sensor_link(i)), Transform2D(m.x, m.y, m.angle))
        for i, m in enumerate(profile.sensors)
    ]
    if lidar is not None:
        links.append(FrameLink(base, frame_id(namespace, LIDAR_LINK), lidar))
    return links


def _number(value: float) -> str:
    return repr(float(value))


def robot_urdf(
    profile: RobotProfile, namespace: str = "", lidar: Transform2D | None = None
) -> str:
    """The URDF of a robot (module docstring): link names are the frames
    (``<ns>/base_link``, ...), so RViz's RobotModel and Foxglove's URDF layer place it on the
    simulator's TF without a prefix. Joints are ``fixed``, origins those of
    :func:`robot_links` (xyz m, rpy rad)."""
    robot = ET.Element("robot", name=profile.name)
    base = frame_id(namespace, BASE_LINK)
    body = ET.SubElement(robot, "link", name=base)
    visual = ET.SubElement(body, "visual")
    ET.SubElement(visual, "origin", xyz=f"0 0 {_number(0.5 * BODY_HEIGHT)}", rpy="0 0 0")
    geometry = ET.SubElement(visual, "geometry")
    size = f"{_number(profile.length)} {_number(profile.width)} {_number(BODY_HEIGHT)}"
    ET.SubElement(geometry, "box", size=size)
    for link in robot_links(profile, namespace, lidar):
        child = ET.SubElement(robot, "link", name=link.child)
        mark = ET.SubElement(child, "visual")
        ET.SubElement(mark, "origin", xyz=f"0 0 {_number(BODY_HEIGHT)}", rpy="0 0 0")
        shape = ET.SubElement(mark, "geometry")
        ET.SubElement(shape, "box", size=" ".join([_number(SENSOR_SIZE)] * 3))
        joint = ET.SubElement(
            robot, "joint", name=f"{link.child}_joint".replace("/", "_"), type="fixed"
        )
        ET.SubElement(joint, "parent", link=link.parent)
        ET.SubElement(joint, "child", link=link.child)
        t = link.transform
        ET.SubElement(
            joint, "origin", xyz=f"{_number(t.x)} {_number(t.y)} 0", rpy=f"0 0 {_number(t.yaw)}"
        )
    ET.indent(robot)
    return '<?xml version="1.0"?>\n' + ET.tostring(robot, encoding="unicode") + "\n"


def urdf_joints(urdf: str) -> dict[str, tuple[str, Transform2D]]:
    """Child link -> (parent link, planar origin) of every joint of a URDF made by
    :func:`robot_urdf` (its roll and pitch must be 0). ValueError for other XML."""
    try:
        root = ET.fromstring(urdf)
    except ET.ParseError as err:
        raise ValueError(f"not XML ({err})") from None
    out = {}
    for joint in root.iter("joint"):
        parent, child, origin = joint.find("parent"), joint.find("child"), joint.find("origin")
        if parent is None or child is None or origin is None:
            raise ValueError(f"joint {joint.get('name')!r} lacks parent, child or origin")
        x, y, _ = (float(v) for v in origin.get("xyz", "0 0 0").split())
        roll, pitch, yaw = (float(v) for v in origin.get("rpy", "0 0 0").split())
        if roll or pitch:
            raise ValueError(f"joint {joint.get('name')!r} is not planar")
        out[str(child.get("link"))] = (str(parent.get("link")), Transform2D(x, y, yaw))
    return out

