"""Body collisions: robot rectangle vs obstacle boxes and arena walls, static and swept.

The robot body is the rectangle ``length x width`` centred on the pose, its long side along
the heading. It collides when it overlaps an obstacle box with positive area (touching is
free) or crosses an arena wall. Overlap is decided by the separating axis theorem on the four
axes x, y, u = (cos theta, sin theta), v = (-sin theta, cos theta): with half-length
``a = length / 2``, half-width ``b = width / 2``, box centre ``C`` and half extents
``(hx, hy)``, ``d = p - C``, the shapes are apart when one of

    |d_x| >= a |c| + b |s| + hx          |d_y| >= a |s| + b |c| + hy
    |d . u| >= a + hx |c| + hy |s|       |d . v| >= b + hx |s| + hy |c|

holds. The body crosses a wall when ``x - ex < 0``, ``x + ex > size`` (``ex = a |c| + b |s|``)
or likewise in y.

Swept collision samples each decision's arc (:func:`mentor_core.sim.kinematics.arc_fraction_poses`)
at ``n`` equal path-length steps, with ``n`` (:func:`sample_counts`) the smallest count such that
no point of the body moves more than ``max_sample_step`` between two samples (a body point at
distance ``<= r`` from the centre moves at most ``|ds| / n + r |dtheta| / n``, ``r`` the
half-diagonal) and the heading turns at most ``max_sample_angle``. The default step is a quarter
of the smaller body dimension: an obstacle corner can then cut into the body by at most about
an eighth of its width between two samples without being seen. The reference physics
(:mod:`mentor_core.sim.pymunk_world`) tests the very same sample poses (:func:`swept_samples`), so
both give the same verdicts.

Two backends give identical verdicts: a numba kernel with a bounding-box broad phase per robot
(the trainer's hot loop), and a vectorised numpy version (fallback and test reference). Both
take the sample poses and their cos/sin from numpy and share every later rounding step.

The engine's step asks :func:`swept_events` what ends each arc first (a collision or the goal).
Its numpy path composes the functions above; its compiled path walks one robot's samples at a
time and stops at the first event, skipping the exact test (and its cos and sin) of a sample
that no wall or box comes within the half-diagonal of. It computes the sample poses with the
same scalar :func:`mentor_core.sim.kinematics.arc_pose` and their cos and sin with the C library's,
which numpy's float64 ``cos``/``sin`` equal on x86-64 (``tests/test_collision.py`` compares
the two paths bit for bit).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from mentor_core.sim.kinematics import arc_fraction_poses, arc_pose
from mentor_core.sim.sensors import Backend, _use_numba

if TYPE_CHECKING:
    from mentor_core.sim.robots import RobotProfile
    from mentor_core.sim.world import World

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
BoolArray = NDArray[np.bool_]

# Largest body-point displacement between two swept samples, as a fraction of the smaller
# body dimension (0.0625 m for the 0.30 x 0.25 m UGV).
SAMPLE_STEP_FRACTION = 0.25
# Largest heading change between two swept samples (rad): keeps long thin bodies honest.
MAX_SAMPLE_ANGLE = np.pi / 16.0
# Samples x boxes handled at once by the numpy backend.
NUMPY_CHUNK_ELEMENTS = 1 << 20
NO_COLLISION = -1
_NO_EVENT = np.iinfo(np.int64).max
# What ends a decision's arc first (:func:`swept_events`).
EVENT_NONE, EVENT_REACHED, EVENT_COLLIDED = 0, 1, 2
# Slack (m) of the swept broad phase, so that rounding never drops a box that overlaps.
BROAD_PHASE_SLACK = 1e-9


def default_sample_step(profile: RobotProfile) -> float:
    """Default ``max_sample_step`` (m): ``SAMPLE_STEP_FRACTION * min(length, width)``."""
    return SAMPLE_STEP_FRACTION * min(profile.length, profile.width)


def sample_counts(
    dtheta: ArrayLike, ds: ArrayLike, profile: RobotProfile, *,
    max_sample_step: float | None = None, max_sample_angle: float = MAX_SAMPLE_ANGLE,
) -> IntArray:
    """Number of arc steps ``n >= 1`` per decision (there are ``n + 1`` sample poses).

    ``n = max(1, ceil((|ds| + r |dtheta|) / max_sample_step), ceil(|dtheta| / max_sample_angle))``
    with ``r = profile.half_diagonal``.
    """
    step = default_sample_step(profile) if max_sample_step is None else float(max_sample_step)
    if not step > 0.0 or not max_sample_angle > 0.0:
        raise ValueError("max_sample_step and max_sample_angle must be positive")
    radius = profile.half_diagonal
    dth = np.abs(np.asarray(dtheta, dtype=np.float64))
    dist = np.abs(np.asarray(ds, dtype=np.float64))
    by_motion = np.ceil((dist + radius * dth) / step)
    by_angle = np.ceil(dth / max_sample_angle)
    return np.maximum(np.maximum(by_motion, by_angle), 1.0).astype(np.int64)


def swept_samples(
    poses: ArrayLike, dtheta: ArrayLike, ds: ArrayLike, counts: ArrayLike
) -> tuple[FloatArray, IntArray]:
    """All robots' sample poses, flat: ``(samples (N, 3), offsets (n + 1,))``.

    Robot ``i``'s sample ``j`` (``0 <= j <= counts[i]``, path-length fraction
    ``j / counts[i]``) is row ``offsets[i] + j``; these rows equal
    ``arc_samples(poses[i:i+1], dtheta[i], ds[i], counts[i])[0]`` bit for bit.
    """
    p = np.asarray(poses, dtype=np.float64).reshape(-1, 3)
    n_steps = np.asarray(counts, dtype=np.int64).reshape(-1)
    per_robot = n_steps + 1
    offsets = np.zeros(p.shape[0] + 1, dtype=np.int64)
    np.cumsum(per_robot, out=offsets[1:])
    robot = np.repeat(np.arange(p.shape[0]), per_robot)
    j = np.arange(offsets[-1], dtype=np.int64) - offsets[robot]
    fractions = j.astype(np.float64) / n_steps[robot].astype(np.float64)
    dth = np.broadcast_to(np.asarray(dtheta, dtype=np.float64), p.shape[:1])[robot]
    dist = np.broadcast_to(np.asarray(ds, dtype=np.float64), p.shape[:1])[robot]
    return arc_fraction_poses(p[robot], dth, dist, fractions), offsets


def sweep_bounds(
    poses: ArrayLike, dtheta: ArrayLike, ds: ArrayLike
) -> tuple[FloatArray, FloatArray]:
    """Disc holding each decision's whole centre path: ``(centres (n, 2), radii (n,))``, m.

    Every point of an arc of length ``|ds|`` lies within ``|ds| / 2`` of the arc's half-way
    point (path length, hence distance, at most ``|ds| / 2`` from it).
    """
    mid = arc_fraction_poses(poses, dtheta, ds, 0.5)
    return mid[..., :2], 0.5 * np.abs(np.asarray(ds, dtype=np.float64))


def sweep_may_collide(
    poses: ArrayLike, dtheta: ArrayLike, ds: ArrayLike, profile: RobotProfile, world: World,
    *, backend: Backend = "auto", bounds: tuple[FloatArray, FloatArray] | None = None,
) -> BoolArray:
    """Broad phase ``(n,)``: False guarantees that no sample of the decision collides.

    The swept body stays in the disc of radius ``|ds| / 2 + half_diagonal`` around the arc's
    half-way point (:func:`sweep_bounds`; pass them as ``bounds`` when already computed); a
    decision whose disc misses every box and stays inside the walls (with
    ``BROAD_PHASE_SLACK``) needs no narrow phase. The numba and numpy backends do the same
    arithmetic (no transcendental functions), so they agree exactly.
    """
    centre, radius = sweep_bounds(poses, dtheta, ds) if bounds is None else bounds
    reach = radius + (profile.half_diagonal + BROAD_PHASE_SLACK)
    x = np.ascontiguousarray(centre[:, 0])
    y = np.ascontiguousarray(centre[:, 1])
    size = float(world.size)
    boxes = np.ascontiguousarray(world.obstacles, dtype=np.float64).reshape(-1, 4)
    if _use_numba(backend) and _broad_phase_numba is not None:
        out = np.empty(x.shape[0], dtype=np.bool_)
        _broad_phase_numba(x, y, reach, boxes, size, out)
        return out
    may = (x - reach < 0.0) | (x + reach > size) | (y - reach < 0.0) | (y + reach > size)
    if boxes.shape[0]:
        gx = np.maximum(np.maximum(boxes[:, 0] - x[:, None], x[:, None] - boxes[:, 2]), 0.0)
        gy = np.maximum(np.maximum(boxes[:, 1] - y[:, None], y[:, None] - boxes[:, 3]), 0.0)
        may |= (gx * gx + gy * gy <= (reach * reach)[:, None]).any(axis=1)
    return may


def _broad_phase_loop(
    x: FloatArray, y: FloatArray, reach: FloatArray, boxes: FloatArray, size: float,
    out: BoolArray,
) -> None:
    """Scalar-loop twin of the numpy broad phase (compiled by numba); stops at the first box."""
    for i in range(x.shape[0]):
        r = reach[i]
        hit = x[i] - r < 0.0 or x[i] + r > size or y[i] - r < 0.0 or y[i] + r > size
        r2 = r * r
        for k in range(boxes.shape[0]):
            if hit:
                break
            gx = max(max(boxes[k, 0] - x[i], x[i] - boxes[k, 2]), 0.0)
            gy = max(max(boxes[k, 1] - y[i], y[i] - boxes[k, 3]), 0.0)
            hit = gx * gx + gy * gy <= r2
        out[i] = hit


def box_arrays(boxes: ArrayLike) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """Box centres and half extents ``(cx, cy, hx, hy)``, each ``(k,)``."""
    b = np.asarray(boxes, dtype=np.float64).reshape(-1, 4)
    return (
        np.ascontiguousarray(0.5 * (b[:, 0] + b[:, 2])),
        np.ascontiguousarray(0.5 * (b[:, 1] + b[:, 3])),
        np.ascontiguousarray(0.5 * (b[:, 2] - b[:, 0])),
        np.ascontiguousarray(0.5 * (b[:, 3] - b[:, 1])),
    )


def _collides_numpy(
    x: FloatArray, y: FloatArray, c: FloatArray, s: FloatArray, a: float, b: float,
    boxes: FloatArray, size: float,
) -> BoolArray:
    """Per pose: does the body overlap a box or cross a wall (numpy, rows x boxes)."""
    ac = np.abs(c)
    as_ = np.abs(s)
    ex = a * ac + b * as_
    ey = a * as_ + b * ac
    hit = (x - ex < 0.0) | (x + ex > size) | (y - ey < 0.0) | (y + ey > size)
    cx, cy, hx, hy = box_arrays(boxes)
    if cx.shape[0] == 0:
        return hit
    chunk = max(1, NUMPY_CHUNK_ELEMENTS // cx.shape[0])
    for start in range(0, x.shape[0], chunk):
        sl = slice(start, start + chunk)
        cc, sc, acc, asc = c[sl, None], s[sl, None], ac[sl, None], as_[sl, None]
        dx = x[sl, None] - cx
        dy = y[sl, None] - cy
        apart = (
            (np.abs(dx) >= ex[sl, None] + hx)
            | (np.abs(dy) >= ey[sl, None] + hy)
            | (np.abs(dx * cc + dy * sc) >= a + (hx * acc + hy * asc))
            | (np.abs(dy * cc - dx * sc) >= b + (hx * asc + hy * acc))
        )
        hit[sl] |= ~apart.all(axis=1)
    return hit


def _candidate_boxes(
    x_min: float, x_max: float, y_min: float, y_max: float, reach: float,
    cx: FloatArray, cy: FloatArray, hx: FloatArray, hy: FloatArray, cand: IntArray,
) -> int:
    """Broad phase of one robot (compiled by numba): writes into ``cand`` the boxes that meet
    the bounding box ``[x_min, x_max] x [y_min, y_max]`` of its sample centres grown by
    ``reach``; returns their number."""
    n_cand = 0
    for k in range(cx.shape[0]):
        if (
            abs(cx[k] - 0.5 * (x_min + x_max)) <= hx[k] + 0.5 * (x_max - x_min) + reach
            and abs(cy[k] - 0.5 * (y_min + y_max)) <= hy[k] + 0.5 * (y_max - y_min) + reach
        ):
            cand[n_cand] = k
            n_cand += 1
    return n_cand


def _pose_may_collide(
    x: float, y: float, reach: float, cx: FloatArray, cy: FloatArray, hx: FloatArray,
    hy: FloatArray, cand: IntArray, n_cand: int, size: float,
) -> bool:
    """Whether a body centred at ``(x, y)`` at any heading may touch a wall or a candidate box
    (compiled by numba). ``reach`` (the half-diagonal plus slack) bounds the body's half
    extents ``ex``, ``ey``, so False implies the first tests of :func:`_pose_collides` all say
    apart: the exact test, and its cos and sin, can be skipped."""
    if x - reach < 0.0 or x + reach > size or y - reach < 0.0 or y + reach > size:
        return True
    for m in range(n_cand):
        k = cand[m]
        if abs(x - cx[k]) < reach + hx[k] and abs(y - cy[k]) < reach + hy[k]:
            return True
    return False


def _pose_collides(
    x: float, y: float, c: float, s: float, a: float, b: float, cx: FloatArray,
    cy: FloatArray, hx: FloatArray, hy: FloatArray, cand: IntArray, n_cand: int, size: float,
) -> bool:
    """Narrow phase of one pose against the walls and the candidate boxes (compiled by numba);
    every rounding step is the numpy backend's."""
    ac = abs(c)
    as_ = abs(s)
    ex = a * ac + b * as_
    ey = a * as_ + b * ac
    hit = x - ex < 0.0 or x + ex > size or y - ey < 0.0 or y + ey > size
    for m in range(n_cand):
        if hit:
            break
        k = cand[m]
        dx = x - cx[k]
        dy = y - cy[k]
        apart = (
            abs(dx) >= ex + hx[k]
            or abs(dy) >= ey + hy[k]
            or abs(dx * c + dy * s) >= a + (hx[k] * ac + hy[k] * as_)
            or abs(dy * c - dx * s) >= b + (hx[k] * as_ + hy[k] * ac)
        )
        hit = not apart
    return hit


def _first_hit_loop(
    x: FloatArray, y: FloatArray, c: FloatArray, s: FloatArray, offsets: IntArray,
    a: float, b: float, cx: FloatArray, cy: FloatArray, hx: FloatArray, hy: FloatArray,
    size: float, out: IntArray,
) -> None:
    """Scalar-loop twin of the numpy test (compiled by numba): first colliding sample per robot.

    Broad phase: only boxes that meet the bounding box of the robot's sample centres grown by
    the body's half-diagonal can touch any sample; the narrow phase is the exact test above.
    """
    reach = np.sqrt(a * a + b * b) + BROAD_PHASE_SLACK
    cand = np.empty(cx.shape[0], dtype=np.int64)
    for i in range(offsets.shape[0] - 1):
        lo = offsets[i]
        hi = offsets[i + 1]
        n_cand = _candidate_boxes(
            x[lo:hi].min(), x[lo:hi].max(), y[lo:hi].min(), y[lo:hi].max(), reach,
            cx, cy, hx, hy, cand,
        )
        out[i] = -1
        for j in range(lo, hi):
            if _pose_collides(x[j], y[j], c[j], s[j], a, b, cx, cy, hx, hy, cand, n_cand, size):
                out[i] = j - lo
                break


def _events_loop(
    poses: FloatArray, dtheta: FloatArray, ds: FloatArray, counts: IntArray, goals: FloatArray,
    goal_radius: float, a: float, b: float, cx: FloatArray, cy: FloatArray, hx: FloatArray,
    hy: FloatArray, size: float, event: NDArray[np.int8], stop: IntArray, end: FloatArray,
) -> None:
    """Compiled twin of :func:`swept_events`' numpy path, one robot at a time: its sample poses
    (:func:`mentor_core.sim.kinematics.arc_pose` at fraction ``j / n``, as
    :func:`swept_samples`), its broad phase and the exact test of :func:`_first_hit_loop`, the
    goal test of :func:`_first_within`; it stops at the first event."""
    reach = np.sqrt(a * a + b * b) + BROAD_PHASE_SLACK
    cand = np.empty(cx.shape[0], dtype=np.int64)
    longest = counts.max() + 1 if counts.shape[0] else 0
    xs = np.empty(longest, dtype=np.float64)
    ys = np.empty(longest, dtype=np.float64)
    ts = np.empty(longest, dtype=np.float64)
    for i in range(counts.shape[0]):
        n = counts[i]
        for j in range(n + 1):
            f = np.float64(j) / np.float64(n)
            xs[j], ys[j], ts[j] = arc_pose(
                poses[i, 0], poses[i, 1], poses[i, 2], dtheta[i] * f, ds[i] * f
            )
        n_cand = _candidate_boxes(
            xs[: n + 1].min(), xs[: n + 1].max(), ys[: n + 1].min(), ys[: n + 1].max(), reach,
            cx, cy, hx, hy, cand,
        )
        event[i] = EVENT_NONE
        stop[i] = n
        for j in range(n + 1):
            if _pose_may_collide(
                xs[j], ys[j], reach, cx, cy, hx, hy, cand, n_cand, size
            ) and _pose_collides(
                xs[j], ys[j], np.cos(ts[j]), np.sin(ts[j]), a, b, cx, cy, hx, hy, cand, n_cand,
                size,
            ):
                event[i] = EVENT_COLLIDED
                stop[i] = max(j - 1, 0)
                break
            if np.hypot(xs[j] - goals[i, 0], ys[j] - goals[i, 1]) <= goal_radius:
                event[i] = EVENT_REACHED
                stop[i] = j
                break
        k = stop[i]
        end[i, 0] = xs[k]
        end[i, 1] = ys[k]
        end[i, 2] = ts[k]


_first_hit_numba: Callable[..., None] | None
_events_numba: Callable[..., None] | None
_broad_phase_numba: Callable[..., None] | None
try:
    from numba import njit

    # No fastmath: verdicts must round exactly like the numpy backend. The scalar helpers are
    # compiled first so that the loops calling them compile against them.
    _candidate_boxes = njit(cache=True)(_candidate_boxes)
    _pose_may_collide = njit(cache=True)(_pose_may_collide)
    _pose_collides = njit(cache=True)(_pose_collides)
    _first_hit_numba = njit(cache=True)(_first_hit_loop)
    _events_numba = njit(cache=True)(_events_loop)
    _broad_phase_numba = njit(cache=True)(_broad_phase_loop)
except ImportError:  # pragma: no cover - numba is in the lock file; numpy stays the fallback
    _first_hit_numba = None
    _events_numba = None
    _broad_phase_numba = None


def first_collisions(
    samples: ArrayLike, offsets: ArrayLike, profile: RobotProfile, world: World, *,
    backend: Backend = "auto",
) -> IntArray:
    """Index (within its robot) of each robot's first colliding sample, or -1.

    Args:
        samples: ``(N, 3)`` flat sample poses, as from :func:`swept_samples`.
        offsets: ``(n + 1,)`` robot ``i`` owns rows ``offsets[i]:offsets[i + 1]`` (non-empty).
    """
    p = np.asarray(samples, dtype=np.float64).reshape(-1, 3)
    off = np.ascontiguousarray(offsets, dtype=np.int64).reshape(-1)
    x = np.ascontiguousarray(p[:, 0])
    y = np.ascontiguousarray(p[:, 1])
    c = np.cos(p[:, 2])
    s = np.sin(p[:, 2])
    a = 0.5 * float(profile.length)
    b = 0.5 * float(profile.width)
    size = float(world.size)
    if _use_numba(backend) and _first_hit_numba is not None:
        out = np.empty(off.shape[0] - 1, dtype=np.int64)
        _first_hit_numba(x, y, c, s, off, a, b, *box_arrays(world.obstacles), size, out)
        return out
    hit = _collides_numpy(x, y, c, s, a, b, np.asarray(world.obstacles), size)
    j = np.arange(p.shape[0], dtype=np.int64)
    big = np.iinfo(np.int64).max
    local = np.where(hit, j, big)
    first = np.minimum.reduceat(local, off[:-1]) if off.shape[0] > 1 else local[:0]
    return np.where(first == big, NO_COLLISION, first - off[:-1])


def swept_events(
    poses: ArrayLike, dtheta: ArrayLike, ds: ArrayLike, counts: ArrayLike, goals: ArrayLike,
    profile: RobotProfile, world: World, *, backend: Backend = "auto",
) -> tuple[NDArray[np.int8], IntArray, FloatArray]:
    """What ends each decision's arc first, sampled as :func:`swept_samples` with ``counts``.

    A robot reaches its goal at the first sample within ``profile.goal_radius`` of
    ``goals[i]``, unless a sample at or before it collides (:func:`first_collisions`); it
    collides at the first colliding sample and stops at the one before it (at the start when
    the start collides); otherwise it ends at the arc's end.

    Returns:
        ``(event (n,), stop (n,), end (n, 3))``: ``EVENT_NONE``, ``EVENT_REACHED`` or
        ``EVENT_COLLIDED``; the sample index the robot stops at (``counts[i]`` at the arc's
        end); that sample's pose. Both backends give bit-identical results.
    """
    p = np.ascontiguousarray(poses, dtype=np.float64).reshape(-1, 3)
    n = np.ascontiguousarray(counts, dtype=np.int64).reshape(-1)
    dth = np.ascontiguousarray(np.broadcast_to(np.asarray(dtheta, dtype=np.float64), n.shape))
    dist = np.ascontiguousarray(np.broadcast_to(np.asarray(ds, dtype=np.float64), n.shape))
    g = np.ascontiguousarray(goals, dtype=np.float64).reshape(-1, 2)
    radius = float(profile.goal_radius)
    if _use_numba(backend) and _events_numba is not None:
        event = np.empty(n.shape[0], dtype=np.int8)
        stop = np.empty(n.shape[0], dtype=np.int64)
        end = np.empty((n.shape[0], 3), dtype=np.float64)
        _events_numba(
            p, dth, dist, n, g, radius, 0.5 * float(profile.length), 0.5 * float(profile.width),
            *box_arrays(world.obstacles), float(world.size), event, stop, end,
        )
        return event, stop, end
    samples, offsets = swept_samples(p, dth, dist, n)
    hit = first_collisions(samples, offsets, profile, world, backend=backend)
    arrive = _first_within(samples, offsets, g, radius)
    hit_at = np.where(hit < 0, _NO_EVENT, hit)
    got = arrive < hit_at
    crash = ~got & (hit >= 0)
    stop = np.where(got, arrive, np.where(crash, np.maximum(hit - 1, 0), n))
    event = np.where(got, EVENT_REACHED, np.where(crash, EVENT_COLLIDED, EVENT_NONE))
    return event.astype(np.int8), stop, samples[offsets[:-1] + stop]


def _first_within(
    samples: FloatArray, offsets: IntArray, goals: FloatArray, radius: float
) -> IntArray:
    """Per robot, the first sample index within ``radius`` of its goal, else ``_NO_EVENT``."""
    goal = np.repeat(goals, np.diff(offsets), axis=0)
    within = np.hypot(samples[:, 0] - goal[:, 0], samples[:, 1] - goal[:, 1]) <= radius
    rows = np.arange(samples.shape[0], dtype=np.int64)
    first = np.minimum.reduceat(np.where(within, rows, _NO_EVENT), offsets[:-1])
    return np.where(first == _NO_EVENT, _NO_EVENT, first - offsets[:-1])


def robot_collides(
    poses: ArrayLike, profile: RobotProfile, world: World, *, backend: Backend = "auto"
) -> BoolArray:
    """Whether each body at ``poses`` ``(n, 3)`` overlaps a box or crosses a wall -> ``(n,)``."""
    p = np.asarray(poses, dtype=np.float64).reshape(-1, 3)
    offsets = np.arange(p.shape[0] + 1, dtype=np.int64)
    first = first_collisions(p, offsets, profile, world, backend=backend)
    return np.asarray(first == 0, dtype=np.bool_)


def swept_collision(
    poses: ArrayLike, dtheta: ArrayLike, ds: ArrayLike, profile: RobotProfile, world: World,
    *, max_sample_step: float | None = None, max_sample_angle: float = MAX_SAMPLE_ANGLE,
    backend: Backend = "auto",
) -> IntArray:
    """First colliding sample index along each decision's arc ``(n,)``, -1 when free.

    Sample ``j`` of robot ``i`` is the arc pose at fraction ``j / sample_counts(...)[i]``; 0 is
    the start pose, so an index of 0 means the robot already collides where it stands. Only
    decisions that pass the broad phase (:func:`sweep_may_collide`) are sampled; the others
    cannot collide.
    """
    p = np.asarray(poses, dtype=np.float64).reshape(-1, 3)
    dth = np.broadcast_to(np.asarray(dtheta, dtype=np.float64), p.shape[:1])
    dist = np.broadcast_to(np.asarray(ds, dtype=np.float64), p.shape[:1])
    out = np.full(p.shape[0], NO_COLLISION, dtype=np.int64)
    near = np.flatnonzero(sweep_may_collide(p, dth, dist, profile, world, backend=backend))
    counts = sample_counts(
        dth[near], dist[near], profile,
        max_sample_step=max_sample_step, max_sample_angle=max_sample_angle,
    )
    samples, offsets = swept_samples(p[near], dth[near], dist[near], counts)
    out[near] = first_collisions(samples, offsets, profile, world, backend=backend)
    return out
