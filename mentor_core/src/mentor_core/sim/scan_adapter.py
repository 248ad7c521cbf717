"""A robot's range sensors read off any 2-D laser scan (a ``sensor_msgs/LaserScan``).

A trained planner expects its profile's readings: sensor ``i`` at mount ``(mx, my)`` of the body
frame, facing ``ma``, reading the nearest obstacle along its ray, or within its beam. A real
robot has a lidar instead: ``n`` rays from the lidar's origin at angles
``a_k = angle_min + k * angle_increment`` of the lidar's frame, whose pose on the body is the
mount ``L`` (a :class:`~mentor_core.sim.transforms.Transform2D`, mirrored for a lidar mounted
upside down). :func:`readings_from_scan` derives each reading from the scan:

1. Returns (REP-117): a finite range ``r`` in ``[range_min, range_max]`` is a return at ``r``;
   ``-inf`` (an object closer than ``range_min``) a return at ``range_min``; ``+inf`` (nothing
   within ``range_max``), NaN (no measurement) and finite ranges outside
   ``[range_min, range_max]`` (invalid) are no return. Each return in the body frame:
   ``p_k = L (r_k cos a_k, r_k sin a_k)``.
2. Field of view: the nearest return whose bearing from the sensor's mount,
   ``atan2(p_k - m_i) - ma_i`` (wrapped), lies within half the sensor's field of view (its
   beam width, or ``ray_width`` for a single-ray sensor; 0 by default: the ray alone), at
   distance ``|p_k - m_i|``.
3. Rays: each ray the simulator casts for the sensor (the beam's rays, or its one ray) from the
   mount, to the scan's surface (:func:`scan_surface`: neighbouring returns of one surface
   joined, and the footprint, one increment wide, of a return alone or at a surface's end),
   so that a ray between two
   lidar rays, or a sensor beside the lidar, reads the surface the lidar saw.
4. The reading is the nearer of 2 and 3; beyond ``profile.sensor_range``, or none, ``+inf``
   (the planner's input function clips it to the range, as in training).

A sensor whose field no ray of the scan points into (seen from the lidar) is not *covered*: a
lidar of less than 360 deg cannot see behind; its reading is then ``+inf``, and
:class:`ScanReadings` says so, so that the planner can warn.

Invalid ranges (NaN, and finite ranges outside ``[range_min, range_max]``, such as the 0.0 some
drivers send for no measurement) are unknown, never free: a sensor that reads nothing (``+inf``)
while a ray into its field is invalid is *unknown*, and :class:`ScanReadings` says so, as it
says how many of the scan's rays are valid (:attr:`ScanReadings.valid_share`); the planner
then refuses the scan rather than drive into what it could not see. It refuses too a scan of
which many rays read ``-inf`` (:attr:`ScanReadings.near_share`): something at the body all
round, closer than the sensors' cones begin.

Error against the profile's own readings: what a derived reading can miss is finer than the
scan's increment ``da``: a flat surface is read exactly (float32 rounding aside), a curved
one or a corner within ``r da`` at range ``r``; a ray grazing an obstacle's edge within an
increment may read past it, and a sensor beside the lidar may see past a near obstacle's
edge that hides the view from the lidar (parallax): there the derived reading is what the
lidar can tell. Measured in ``tests/test_scan_adapter.py`` against the simulator.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from mentor_core.sim.robots import RobotProfile
from mentor_core.sim.transforms import IDENTITY, Transform2D

FloatArray = NDArray[np.float64]
#: neighbouring returns farther apart than this many increments (times their range) are two
#: surfaces, not one (:func:`scan_surface`)
LINK_INCREMENTS = 8.0
# bearing slack (rad): a return exactly on a field's edge counts as inside
_EDGE = 1e-12


@dataclass(frozen=True)
class LaserScanData:
    """The fields of a ``sensor_msgs/LaserScan`` the derivation uses (rad, m).

    ``ranges`` is copied to float64; ValueError for non-finite angles or range limits.
    """

    angle_min: float
    angle_increment: float
    range_min: float
    range_max: float
    ranges: FloatArray

    def __post_init__(self) -> None:
        head = (self.angle_min, self.angle_increment, self.range_min, self.range_max)
        if not all(np.isfinite(v) for v in head):
            raise ValueError(f"scan angles and range limits must be finite, got {head}")
        r = np.array(self.ranges, dtype=np.float64).reshape(-1)
        r.setflags(write=False)
        object.__setattr__(self, "ranges", r)

    @property
    def angles(self) -> FloatArray:
        """Ray angles in the scan's frame, rad: ``angle_min + k * angle_increment``."""
        k = np.arange(self.ranges.size, dtype=np.float64)
        out: FloatArray = self.angle_min + k * self.angle_increment
        return out


@dataclass(frozen=True)
class LidarMount:
    """Where the scan's frame sits on the body: its pose in the body frame and whether it is
    upside down (then a ray at angle ``a`` of the scan faces ``yaw - a`` in the body)."""

    pose: Transform2D = IDENTITY
    inverted: bool = False


@dataclass(frozen=True)
class ScanReadings:
    """Readings (m, profile order, ``+inf`` when nothing in range), which sensors the scan
    covers (some ray points into the field of view), which read nothing only because a ray
    into their field is invalid (``unknown``), and the share of the scan's rays that are valid
    (REP-117: a finite range within the limits, or an infinity)."""

    readings: FloatArray
    covered: NDArray[np.bool_]
    unknown: NDArray[np.bool_]
    valid_share: float
    #: the share of the scan's rays that read an object nearer than ``range_min`` (``-inf``)
    near_share: float

    @property
    def unknown_sensors(self) -> tuple[int, ...]:
        """Indices of the sensors whose reading is unknown (module docstring)."""
        return tuple(int(i) for i in np.flatnonzero(self.unknown))

    @property
    def uncovered(self) -> tuple[int, ...]:
        """Indices of the sensors no ray of the scan points into."""
        return tuple(int(i) for i in np.flatnonzero(~self.covered))


#: the least share of a scan's rays that must be valid for a planner to read it
MIN_VALID_SHARE = 0.5
#: the largest share of a scan's rays that may read an object nearer than range_min (-inf):
#: more is something at the body all round, which the sensors' cones, outside it, miss
MAX_NEAR_SHARE = 0.1


def readings_fault(read: ScanReadings) -> str:
    """Why a planner must not decide on ``read`` (one line), or "" (module docstring): some
    sensor is unknown, fewer than :data:`MIN_VALID_SHARE` of the rays are valid, or more than
    :data:`MAX_NEAR_SHARE` read an object nearer than ``range_min``."""
    if read.near_share > MAX_NEAR_SHARE:
        return (f"{read.near_share:.0%} of the scan's ranges read an object nearer than "
                f"range_min (-inf; at most {MAX_NEAR_SHARE:.0%}): something is at the body")
    if read.valid_share < MIN_VALID_SHARE:
        return (f"only {read.valid_share:.0%} of the scan's ranges are valid (NaN, or outside "
                f"[range_min, range_max]; at least {MIN_VALID_SHARE:.0%} needed)")  # fmt: skip
    if read.unknown_sensors:
        return (f"sensors {list(read.unknown_sensors)} see only invalid ranges (NaN, or outside "
                "[range_min, range_max]): unknown, not free")  # fmt: skip
    return ""


def scan_returns(scan: LaserScanData) -> tuple[FloatArray, FloatArray]:
    """The returns of a scan (module docstring, step 1): their angles and ranges (rad, m)."""
    r = scan.ranges
    valid = _in_limits(scan)
    near = np.isneginf(r)
    keep = valid | near
    dist = np.where(near, scan.range_min, r)[keep]
    return scan.angles[keep], dist


def _in_limits(scan: LaserScanData) -> NDArray[np.bool_]:
    """The finite ranges within ``[range_min, range_max]``."""
    r = scan.ranges
    with np.errstate(invalid="ignore"):
        out: NDArray[np.bool_] = np.isfinite(r) & (r >= scan.range_min) & (r <= scan.range_max)
    return out


def valid_ranges(scan: LaserScanData) -> NDArray[np.bool_]:
    """The scan's valid rays (REP-117): a finite range within the limits, or an infinity
    (``-inf``: an object too near, ``+inf``: nothing within ``range_max``)."""
    out: NDArray[np.bool_] = _in_limits(scan) | np.isinf(scan.ranges)
    return out


def body_directions(angles: ArrayLike, mount: LidarMount) -> FloatArray:
    """Directions (rad, body frame) of scan rays at ``angles`` of the scan's frame."""
    a = np.asarray(angles, dtype=np.float64)
    out: FloatArray = mount.pose.yaw + (-a if mount.inverted else a)
    return out


def fields_of_view(profile: RobotProfile, ray_width: float) -> FloatArray:
    """Full field of view of each sensor (rad, profile order): the beam width where it has a
    beam, else ``ray_width``."""
    widths = np.full(profile.n_sensors, float(ray_width), dtype=np.float64)
    widths[profile.ray_counts > 1] = profile.beam_width
    return widths


def scan_surface(
    points: FloatArray, angles: FloatArray, increment: float, closed: bool
) -> tuple[FloatArray, FloatArray]:
    """Segments ``(a, b)`` (each ``(m, 2)``) joining neighbouring returns of one surface.

    Returns ``k`` and ``k + 1`` of the scan (and the last and first of a full circle,
    ``closed``) are joined when their rays are neighbours (one increment apart) and they lie
    at most :data:`LINK_INCREMENTS` increments apart seen from the lidar
    (``|p_k - p_k+1| <= LINK_INCREMENTS * increment * max(r_k, r_k+1)``): one flat surface at
    up to ~83 deg incidence, not the gap between a near object and the wall behind it.
    """
    a, b = points, np.roll(points, -1, axis=0)
    step = np.abs(_wrapped(np.roll(angles, -1) - angles))
    if not closed:
        a, b, step = a[:-1], b[:-1], step[:-1]
    reach = np.maximum(np.hypot(a[:, 0], a[:, 1]), np.hypot(b[:, 0], b[:, 1]))
    gap = np.hypot(b[:, 0] - a[:, 0], b[:, 1] - a[:, 1])
    inc = abs(increment)
    keep = (np.abs(step - inc) <= 1e-9 + 1e-6 * inc) & (gap <= LINK_INCREMENTS * inc * reach)
    # the footprint of a return at a surface's end, or alone: its beam, one increment wide,
    # across the ray at its range (inside a surface the links say more)
    n = len(points)
    before = np.zeros(n, dtype=bool)  # linked to the previous return
    after = np.zeros(n, dtype=bool)  # linked to the next one
    after[: len(keep)] = keep
    before[(np.arange(len(keep)) + 1) % n] = keep
    end = ~(before & after)
    r = np.hypot(points[end, 0], points[end, 1])
    across = np.stack([-np.sin(angles[end]), np.cos(angles[end])], axis=1) * (0.5 * inc * r)[
        :, None
    ]
    return (
        np.concatenate([a[keep], points[end] - across]),
        np.concatenate([b[keep], points[end] + across]),
    )


def ray_hits(
    origins: FloatArray, directions: FloatArray, seg_a: FloatArray, seg_b: FloatArray
) -> FloatArray:
    """Distance along each ray (origin ``(n, 2)``, direction angle ``(n,)``) to the first
    segment it crosses (``+inf``: none). A ray ``o + t u`` meets segment ``a + s (b - a)`` at
    ``t = (d x e) / (u x e)``, ``s = (d x u) / (u x e)``, ``d = a - o``, ``e = b - a``,
    with ``t >= 0`` and ``0 <= s <= 1``."""
    if len(seg_a) == 0:
        return np.full(len(origins), np.inf, dtype=np.float64)
    ux, uy = np.cos(directions)[:, None], np.sin(directions)[:, None]
    ex, ey = (seg_b - seg_a)[None, :, 0], (seg_b - seg_a)[None, :, 1]
    dx = seg_a[None, :, 0] - origins[:, 0, None]
    dy = seg_a[None, :, 1] - origins[:, 1, None]
    denom = ux * ey - uy * ex
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (dx * ey - dy * ex) / denom
        s = (dx * uy - dy * ux) / denom
    ok = (denom != 0.0) & (t >= 0.0) & (s >= -_EDGE) & (s <= 1.0 + _EDGE)
    out: FloatArray = np.where(ok, t, np.inf).min(axis=1)
    return out


def readings_from_scan(
    scan: LaserScanData,
    mount: LidarMount,
    profile: RobotProfile,
    ray_width: float = 0.0,
) -> ScanReadings:
    """Each of ``profile``'s sensors read off ``scan`` (see the module docstring).

    ``ray_width``: field of view of a single-ray sensor, rad (0: its ray alone). ValueError
    for a negative width.
    """
    if not (np.isfinite(ray_width) and ray_width >= 0.0):
        raise ValueError(f"ray width must be a finite angle >= 0 rad, got {ray_width}")
    half = 0.5 * fields_of_view(profile, ray_width)
    mounts = profile.sensor_mounts
    angles, dist = scan_returns(scan)
    direction = body_directions(angles, mount)
    origin = mount.pose
    px = origin.x + dist * np.cos(direction)
    py = origin.y + dist * np.sin(direction)
    # 1. the nearest return inside each sensor's field of view
    dx = px[None, :] - mounts[:, 0, None]
    dy = py[None, :] - mounts[:, 1, None]
    bearing = _wrapped(np.arctan2(dy, dx) - mounts[:, 2, None])
    inside = (np.abs(bearing) <= half[:, None] + _EDGE) & (half[:, None] > 0.0)
    distance = np.where(inside, np.hypot(dx, dy), np.inf)
    nearest = distance.min(axis=1) if len(dist) else np.full(profile.n_sensors, np.inf)
    # 2. each of the sensor's rays (as the simulator casts them) against the scan's surface
    rel = np.stack([px - origin.x, py - origin.y], axis=1)
    seg_a, seg_b = scan_surface(rel, direction, scan.angle_increment, _closed(scan))
    shift = np.array([origin.x, origin.y])
    counts = profile.ray_counts
    rows = np.repeat(np.arange(profile.n_sensors), counts)
    offsets = np.concatenate([profile.ray_offsets[i, : counts[i]] for i in range(len(counts))])
    hits = ray_hits(mounts[rows, :2], mounts[rows, 2] + offsets, seg_a + shift, seg_b + shift)
    along = np.full(profile.n_sensors, np.inf)
    np.minimum.at(along, rows, hits)
    found = np.minimum(nearest, along)
    readings = np.where(found <= profile.sensor_range, found, np.inf)
    # coverage: some ray (any value) points within one increment of the field, seen from the
    # lidar's origin
    rays = body_directions(scan.angles, mount)
    off = np.abs(_wrapped(rays[None, :] - mounts[:, 2, None]))
    reach = off <= half[:, None] + abs(scan.angle_increment) + _EDGE
    covered = reach.any(axis=1)
    valid = valid_ranges(scan)
    unknown = np.isinf(readings) & (reach & ~valid[None, :]).any(axis=1)
    share = float(valid.mean()) if valid.size else 0.0
    near = float(np.isneginf(scan.ranges).mean()) if valid.size else 0.0
    return ScanReadings(readings.astype(np.float64), np.asarray(covered, dtype=np.bool_),
                        np.asarray(unknown, dtype=np.bool_), share, near)  # fmt: skip


@dataclass(frozen=True)
class MountedScan:
    """A lidar's scan and where the lidar sits on the body: what a map of the whole scan
    needs (:meth:`rays`)."""

    scan: LaserScanData
    mount: LidarMount = LidarMount()

    def rays(self, pose: ArrayLike) -> tuple[FloatArray, FloatArray]:
        """The scan's valid rays (REP-117, :func:`valid_ranges`) from a robot at ``pose``
        (x, y, theta): each ray's frame ``(k, 3)`` (the lidar's origin and the ray's heading,
        in the frame of ``pose``) and its reading ``(k,)`` (m): a return at its range,
        ``-inf`` (an object nearer than ``range_min``) at ``range_min``, ``+inf`` nothing
        within reach. NaN and finite ranges outside the limits say nothing: left out."""
        x, y, theta = (float(v) for v in np.asarray(pose, dtype=np.float64).reshape(3))
        scan, m = self.scan, self.mount.pose
        valid = valid_ranges(scan)
        r = scan.ranges[valid]
        reading: FloatArray = np.where(np.isneginf(r), scan.range_min, r).astype(np.float64)
        ox, oy = Transform2D(x, y, theta).apply_point((m.x, m.y))
        heading = theta + body_directions(scan.angles[valid], self.mount)
        frames = np.stack([np.full(r.size, ox), np.full(r.size, oy), heading], axis=1)
        return frames, reading


def _closed(scan: LaserScanData) -> bool:
    """The scan goes all round: its last ray is one increment short of its first."""
    n = scan.ranges.size
    return n > 2 and abs(abs(n * scan.angle_increment) - 2.0 * np.pi) <= 1e-6


def _wrapped(a: FloatArray) -> FloatArray:
    out: FloatArray = np.pi - np.mod(np.pi - a, 2.0 * np.pi)
    return out
