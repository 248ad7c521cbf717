"""The frames a planner works with: where its goals, its scans and its odometry meet.

The planner decides in its odometry frame (the ``header.frame_id`` of its odometry, ``odom`` in
REP-105; its body frame is the odometry's ``child_frame_id``):

* a goal in any frame it can link to the odometry frame is turned into it when it arrives,
  and into ``map`` to be checked against the known area;
* a laser scan in any frame is read off from that frame's pose on the body (the lidar's
  mount).

Where ``tf2_ros`` imports (a full ROS 2 install) the node hands :class:`PlannerFrames` a
``lookup`` into its TF buffer, and every transform comes from ``/tf`` and ``/tf_static``.
Without it (a pip-only install) the frames are the fallback: ``map -> odom`` from the
``map_to_odom`` parameter, ``odom -> base`` from the latest odometry, and the scan's frame at
the ``lidar_mount`` parameter on the body, whatever its name.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

from mentor_core.sim.frames import MAP_FRAME, ODOM_FRAME
from mentor_core.sim.robot_description import BASE_LINK
from mentor_core.sim.scan_adapter import LidarMount
from mentor_core.sim.transforms import IDENTITY, FrameTree, Transform2D

#: ``lookup(target, source)``: the pose of frame ``source`` in frame ``target`` and whether
#: ``source`` is upside down in it; raises LookupError when they are not linked
Lookup = Callable[[str, str], tuple[Transform2D, bool]]


class PlannerFrames:
    """A planner's frames (module docstring).

    Args:
        map_frame: the frame of the map (goals with an empty frame are in it).
        map_to_odom: the pose of the odometry frame in ``map_frame`` (fallback).
        lidar_mount: the scan frame's mount on the body (fallback).
        lookup: the TF buffer's lookup, where ``tf2_ros`` is installed.
    """

    def __init__(
        self,
        map_frame: str = MAP_FRAME,
        map_to_odom: Transform2D = IDENTITY,
        lidar_mount: LidarMount | None = None,
        lookup: Lookup | None = None,
    ) -> None:
        self.map_frame = map_frame
        self.map_to_odom = map_to_odom
        self.lidar_mount = lidar_mount or LidarMount()
        self._lookup = lookup
        self.odom_frame = ODOM_FRAME
        self.base_frame = BASE_LINK
        self._pose = IDENTITY
        self.has_odometry = False  # the body frame is known (the odometry's child)

    @property
    def uses_tf(self) -> bool:
        """Transforms come from a TF buffer."""
        return self._lookup is not None

    def on_odometry(self, frame: str, child: str, pose: Sequence[float]) -> None:
        """The latest odometry: its frame, its child (body) frame, the pose."""
        self.odom_frame = frame or self.odom_frame
        self.base_frame = child or self.base_frame
        self._pose = Transform2D(float(pose[0]), float(pose[1]), float(pose[2]))
        self.has_odometry = True

    def transform(self, target: str, source: str) -> Transform2D:
        """The pose of frame ``source`` in frame ``target``; LookupError when unknown."""
        if self._lookup is not None:
            return self._lookup(target, source)[0]
        tree = FrameTree()
        if self.map_frame != self.odom_frame:
            tree.link(self.map_frame, self.odom_frame, self.map_to_odom)
        if self.base_frame != self.odom_frame:
            tree.link(self.odom_frame, self.base_frame, self._pose)
        return tree.lookup(target, source)

    def goal(
        self, frame: str, xy: Sequence[float]
    ) -> tuple[tuple[float, float], tuple[float, float] | None]:
        """A goal ``xy`` (m) given in ``frame`` (empty: the map's), in the odometry frame and
        in the map (None when the map is not linked). LookupError when the goal's frame is
        not linked to the odometry frame."""
        source = frame or self.map_frame
        odom = self.transform(self.odom_frame, source).apply_point(xy)
        try:
            in_map: tuple[float, float] | None = self.transform(
                self.map_frame, source
            ).apply_point(xy)
        except LookupError:
            in_map = None
        return odom, in_map

    def heading(self, frame: str, yaw: float) -> float:
        """A goal's heading ``yaw`` (rad) given in ``frame`` (empty: the map's), in the
        odometry frame. LookupError as :meth:`goal`."""
        source = frame or self.map_frame
        return self.transform(self.odom_frame, source).apply_pose((0.0, 0.0, yaw))[2]

    def mount(self, scan_frame: str) -> LidarMount:
        """Where the scan's frame sits on the body; LookupError (TF) when unknown."""
        if self._lookup is None:
            return self.lidar_mount
        pose, inverted = self._lookup(self.base_frame, scan_frame)
        return LidarMount(pose, inverted)
