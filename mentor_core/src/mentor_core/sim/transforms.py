"""Planar rigid transforms between frames (REP-105), and a tree of them (as tf2 keeps them).

A :class:`Transform2D` ``T = (x, y, yaw)`` is the pose of a child frame in its parent frame:
it maps a point given in the child frame into the parent frame,
``p_parent = R(yaw) p_child + (x, y)``, and a pose ``(px, py, ptheta)`` into
``(R(yaw) (px, py) + (x, y), ptheta + yaw)`` (heading wrapped to ``(-pi, pi]``). Composition
``A.compose(B)`` is the child of B's child seen from A's parent; ``T.inverse()`` maps back. The
identity leaves every number unchanged, bit for bit (no wrap of an angle already wrapped), so a
simulator whose ``odom`` coincides with ``map`` publishes the very same poses as before.

A 3-D ROS transform (translation, quaternion) of a frame that only turns about z, or is turned
upside down (a 2-D lidar mounted on its head, roll pi), is planar: :func:`planar_transform`
gives its :class:`Transform2D` and whether it is mirrored. Tilted frames are refused.

:class:`FrameTree` holds transforms parent -> child by frame name, each frame with at most one
parent, and looks up the transform between any two frames of one tree (the fallback of the
nodes where ``tf2_ros`` is not installed, and the simulator's own frames).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

#: |z-axis tilt| (1 - |R_zz|) below which a frame counts as planar
PLANAR_TOLERANCE = 1e-6


def _wrap(angle: float) -> float:
    """``angle`` wrapped to ``(-pi, pi]``; unchanged (bit for bit) when it lies there."""
    if -math.pi < angle <= math.pi:
        return angle
    wrapped = math.pi - math.fmod(math.pi - angle, 2.0 * math.pi)
    if wrapped > math.pi:  # fmod keeps the sign of a negative dividend
        wrapped -= 2.0 * math.pi
    return math.pi if wrapped <= -math.pi else wrapped


@dataclass(frozen=True)
class Transform2D:
    """Pose ``(x, y, yaw)`` (m, m, rad) of a child frame in its parent frame (module docstring).

    ValueError for a value that is not finite.
    """

    x: float = 0.0
    y: float = 0.0
    yaw: float = 0.0

    def __post_init__(self) -> None:
        values = (float(self.x), float(self.y), float(self.yaw))
        if not all(math.isfinite(v) for v in values):
            raise ValueError(f"a transform is three finite numbers (x, y, yaw), got {values}")
        object.__setattr__(self, "x", values[0])
        object.__setattr__(self, "y", values[1])
        object.__setattr__(self, "yaw", _wrap(values[2]))

    @classmethod
    def of(cls, values: Sequence[float]) -> Transform2D:
        """From ``[x, y, yaw]`` (a parameter's list); ValueError for another length."""
        if len(values) != 3:
            raise ValueError(f"expected [x, y, yaw] (m, m, rad), got {list(values)}")
        return cls(float(values[0]), float(values[1]), float(values[2]))

    @property
    def is_identity(self) -> bool:
        """All three numbers are 0."""
        return self.x == 0.0 and self.y == 0.0 and self.yaw == 0.0

    def as_tuple(self) -> tuple[float, float, float]:
        """``(x, y, yaw)``."""
        return (self.x, self.y, self.yaw)

    def apply_point(self, xy: Sequence[float]) -> tuple[float, float]:
        """Point ``(x, y)`` of the child frame in the parent frame, m."""
        px, py = float(xy[0]), float(xy[1])
        if self.yaw == 0.0:
            return (self.x + px, self.y + py)
        c, s = math.cos(self.yaw), math.sin(self.yaw)
        return (self.x + (c * px - s * py), self.y + (s * px + c * py))

    def apply_pose(self, pose: Sequence[float]) -> tuple[float, float, float]:
        """Pose ``(x, y, theta)`` of the child frame in the parent frame."""
        x, y = self.apply_point(pose)
        return (x, y, _wrap(float(pose[2]) + self.yaw))

    def compose(self, other: Transform2D) -> Transform2D:
        """``self`` then ``other``: the pose of ``other``'s child in ``self``'s parent."""
        return Transform2D(*self.apply_pose(other.as_tuple()))

    def inverse(self) -> Transform2D:
        """The parent frame's pose in the child frame."""
        if self.yaw == 0.0:
            return Transform2D(-self.x, -self.y, 0.0)
        c, s = math.cos(self.yaw), math.sin(self.yaw)
        return Transform2D(-(c * self.x + s * self.y), s * self.x - c * self.y, -self.yaw)


IDENTITY = Transform2D()


def planar_transform(
    translation: Sequence[float], rotation: Sequence[float]
) -> tuple[Transform2D, bool]:
    """The planar part of a ROS transform: translation ``(x, y, z)`` (z ignored) and unit
    quaternion ``(qx, qy, qz, qw)``. Returns the transform and whether the child frame is
    upside down (its z axis points down: its x-y plane is mirrored, a scan's angles turn the
    other way; the yaw is then the direction of the child's x axis).

    ValueError for a rotation that tilts the child's z axis off the vertical, or a zero or
    non-finite quaternion.
    """
    qx, qy, qz, qw = (float(v) for v in rotation)
    norm = math.sqrt(qx * qx + qy * qy + qz * qz + qw * qw)
    if not math.isfinite(norm) or norm == 0.0:
        raise ValueError("the rotation is not a unit quaternion")
    qx, qy, qz, qw = qx / norm, qy / norm, qz / norm, qw / norm
    r_zz = 1.0 - 2.0 * (qx * qx + qy * qy)
    if 1.0 - abs(r_zz) > PLANAR_TOLERANCE:
        raise ValueError("the frame is tilted (not planar): its z axis is not vertical")
    if r_zz > 0.0 and qx == 0.0 and qy == 0.0:
        yaw = 2.0 * math.atan2(qz, qw)  # pure yaw, exact to a few ulp (as frames.py)
    else:
        yaw = math.atan2(2.0 * (qx * qy + qw * qz), 1.0 - 2.0 * (qy * qy + qz * qz))
    return Transform2D(float(translation[0]), float(translation[1]), yaw), r_zz < 0.0


class FrameTree:
    """Planar transforms parent -> child by frame name; each frame has at most one parent."""

    def __init__(self) -> None:
        self._parent: dict[str, tuple[str, Transform2D]] = {}

    def link(self, parent: str, child: str, transform: Transform2D) -> None:
        """The pose of ``child`` in ``parent`` (replaces the child's earlier parent).

        ValueError for an empty name, a frame its own parent, or a loop.
        """
        if not parent or not child or parent == child:
            raise ValueError(f"cannot link frame {child!r} to parent {parent!r}")
        if child in self.chain(parent):
            raise ValueError(f"linking {child!r} under {parent!r} would make a loop")
        self._parent[child] = (parent, transform)

    def frames(self) -> set[str]:
        """Every frame named so far."""
        return set(self._parent) | {p for p, _ in self._parent.values()}

    def lookup(self, target: str, source: str) -> Transform2D:
        """The pose of frame ``source`` in frame ``target`` (it maps points given in
        ``source`` into ``target``). LookupError when the two frames are not linked."""
        if target == source:
            return IDENTITY
        up_source = self.chain(source)
        up_target = self.chain(target)
        common = next((f for f in up_source if f in up_target), None)
        if common is None:
            raise LookupError(f"no transform from frame {source!r} to frame {target!r}")
        return self._from_root(up_target, common).inverse().compose(
            self._from_root(up_source, common)
        )

    def chain(self, frame: str) -> list[str]:
        """``frame`` and its ancestors, nearest first."""
        chain = [frame]
        while chain[-1] in self._parent:
            chain.append(self._parent[chain[-1]][0])
        return chain

    def _from_root(self, chain: list[str], root: str) -> Transform2D:
        """Pose of ``chain[0]`` in its ancestor ``root``."""
        out = IDENTITY
        for frame in chain[: chain.index(root)]:
            out = self._parent[frame][1].compose(out)
        return out
