"""Range sensors: exact ray casts against axis-aligned boxes and the arena walls.

A ray from origin ``o`` along unit direction ``u = (cos a, sin a)`` meets the box
``[xmin, xmax] x [ymin, ymax]`` (slab method) on the parameter interval
``[t_near, t_far]`` with ``t_near = max(min(tx1, tx2), min(ty1, ty2))``,
``t_far = min(max(tx1, tx2), max(ty1, ty2))``, ``tx = (x_edge - ox) * (1 / ux)`` (likewise y);
the ray hits the box when ``t_near <= t_far`` and ``t_far >= 0``, at distance
``max(t_near, 0)`` (so an origin inside a closed box reads 0). The arena walls
``x = 0, x = size, y = 0, y = size`` are seen from inside. A reading beyond ``max_range`` is
``+inf`` (REP-117). Readings from other robots are not modelled here: each training robot is
alone in its world.

Two backends give bit-identical results: a numba kernel (the trainer's hot loop) and a
vectorised numpy version (the fallback, and the reference the tests compare against). Both get
the ray directions from the same numpy ``cos``/``sin`` (of the robots' headings and of the
rays' body-frame angles) and then apply the same ``-``, ``*``, ``/``, ``min`` and ``max``
steps, so no rounding differs.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

if TYPE_CHECKING:
    from mentor_core.sim.robots import RobotProfile
    from mentor_core.sim.world import World

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
Backend = Literal["auto", "numba", "numpy"]

# Rays x boxes handled at once by the numpy backend: bounds its temporaries to ~10 MB each.
NUMPY_CHUNK_ELEMENTS = 1 << 20
# Slack (m) of the per-robot box culling, so that rounding never drops a box in range.
CULL_SLACK = 1e-9


def _wall_distance(
    ox: FloatArray, oy: FloatArray, ux: FloatArray, uy: FloatArray, size: float
) -> FloatArray:
    """Distance (m) from origins inside the arena to the walls along ``u``."""
    with np.errstate(divide="ignore", invalid="ignore"):
        tx = np.where(ux > 0.0, (size - ox) / ux, np.where(ux < 0.0, (0.0 - ox) / ux, np.inf))
        ty = np.where(uy > 0.0, (size - oy) / uy, np.where(uy < 0.0, (0.0 - oy) / uy, np.inf))
    return np.minimum(tx, ty)


def _slab(
    o: FloatArray, u: FloatArray, lo_edge: FloatArray, hi_edge: FloatArray
) -> tuple[FloatArray, FloatArray]:
    """Entry and exit parameters of rays ``(m, 1)`` through slabs ``(1, k)`` -> ``(m, k)``.

    ``t = (edge - o) * (1 / u)``; a ray parallel to the slab (``u == 0``) is inside it for all
    t or for none.
    """
    parallel = u == 0.0
    inv = np.divide(1.0, u, out=np.zeros_like(u), where=~parallel)
    t1 = (lo_edge - o) * inv
    t2 = (hi_edge - o) * inv
    inside = (lo_edge <= o) & (o <= hi_edge)
    t_in = np.where(parallel, np.where(inside, -np.inf, np.inf), np.minimum(t1, t2))
    t_out = np.where(parallel, np.where(inside, np.inf, -np.inf), np.maximum(t1, t2))
    return t_in, t_out


def _cast_numpy(
    ox: FloatArray, oy: FloatArray, ux: FloatArray, uy: FloatArray, boxes: FloatArray,
    size: float,
) -> FloatArray:
    """Nearest hit (m, unbounded) for every ray: walls and boxes, numpy over rays x boxes."""
    best = _wall_distance(ox, oy, ux, uy, size)
    k = boxes.shape[0]
    if k == 0:
        return best
    chunk = max(1, NUMPY_CHUNK_ELEMENTS // k)
    for start in range(0, ox.shape[0], chunk):
        sl = slice(start, start + chunk)
        tx_in, tx_out = _slab(ox[sl, None], ux[sl, None], boxes[None, :, 0], boxes[None, :, 2])
        ty_in, ty_out = _slab(oy[sl, None], uy[sl, None], boxes[None, :, 1], boxes[None, :, 3])
        t_near = np.maximum(tx_in, ty_in)
        t_far = np.minimum(tx_out, ty_out)
        hit = (t_near <= t_far) & (t_far >= 0.0)
        dist = np.where(hit, np.maximum(t_near, 0.0), np.inf)
        best[sl] = np.minimum(best[sl], dist.min(axis=1))
    return best


def _box_scratch(n: int) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """Room for the corners of ``n`` culled boxes, ``x0s, y0s, x1s, y1s`` (compiled by
    numba)."""
    return (np.empty(n, dtype=np.float64), np.empty(n, dtype=np.float64),
            np.empty(n, dtype=np.float64), np.empty(n, dtype=np.float64))


def _near_boxes(
    gx: float, gy: float, cull: float, boxes: FloatArray, x0s: FloatArray, y0s: FloatArray,
    x1s: FloatArray, y1s: FloatArray,
) -> int:
    """Copies the boxes within ``cull`` of ``(gx, gy)`` (axis gap) into ``x0s .. y1s``;
    returns their number (compiled by numba)."""
    n_cand = 0
    for b in range(boxes.shape[0]):
        far_x = max(boxes[b, 0] - gx, gx - boxes[b, 2])
        far_y = max(boxes[b, 1] - gy, gy - boxes[b, 3])
        if max(far_x, far_y) <= cull:
            x0s[n_cand] = boxes[b, 0]
            y0s[n_cand] = boxes[b, 1]
            x1s[n_cand] = boxes[b, 2]
            y1s[n_cand] = boxes[b, 3]
            n_cand += 1
    return n_cand


def _ray_distance(
    x: float, y: float, dx: float, dy: float, x0s: FloatArray, y0s: FloatArray,
    x1s: FloatArray, y1s: FloatArray, n_cand: int, size: float,
) -> float:
    """Distance along one ray to the arena walls or the first of the ``n_cand`` boxes
    (compiled by numba); every arithmetic step is the numpy backend's."""
    inf = np.inf
    tx = (size - x) / dx if dx > 0.0 else ((0.0 - x) / dx if dx < 0.0 else inf)
    ty = (size - y) / dy if dy > 0.0 else ((0.0 - y) / dy if dy < 0.0 else inf)
    best = min(tx, ty)
    ix = 1.0 / dx if dx != 0.0 else 0.0
    iy = 1.0 / dy if dy != 0.0 else 0.0
    for m in range(n_cand):
        t1 = (x0s[m] - x) * ix
        t2 = (x1s[m] - x) * ix
        t3 = (y0s[m] - y) * iy
        t4 = (y1s[m] - y) * iy
        tx_in = min(t1, t2)
        tx_out = max(t1, t2)
        ty_in = min(t3, t4)
        ty_out = max(t3, t4)
        if dx == 0.0:  # parallel to the x slab: inside it for all t or for none
            inside = x0s[m] <= x and x <= x1s[m]
            tx_in = -inf if inside else inf
            tx_out = inf if inside else -inf
        if dy == 0.0:
            inside = y0s[m] <= y and y <= y1s[m]
            ty_in = -inf if inside else inf
            ty_out = inf if inside else -inf
        t_near = max(tx_in, ty_in)
        t_far = min(tx_out, ty_out)
        d = max(t_near, 0.0) if (t_near <= t_far and t_far >= 0.0) else inf
        best = min(best, d)
    return best


def _cast_loop(
    ox: FloatArray, oy: FloatArray, ux: FloatArray, uy: FloatArray, group: int,
    gx: FloatArray, gy: FloatArray, reach: float, boxes: FloatArray, size: float,
    max_range: float, out: FloatArray,
) -> None:
    """Scalar-loop twin of :func:`_cast_numpy` (compiled by numba); writes ``out``.

    Rays come in groups of ``group`` consecutive rays whose origins lie within ``reach`` of the
    group's centre ``(gx, gy)`` (one robot's sensors). A box farther than
    ``max_range + reach`` from the centre (axis gap) can only give hits beyond ``max_range``,
    read as +inf anyway, so each group casts against the nearer boxes only (copied into
    contiguous arrays so that the inner loop runs without branches). Every arithmetic step is
    the numpy backend's, so the two agree bit for bit.
    """
    x0s, y0s, x1s, y1s = _box_scratch(boxes.shape[0])
    cull = max_range + reach + CULL_SLACK
    for g in range(gx.shape[0]):
        n_cand = _near_boxes(gx[g], gy[g], cull, boxes, x0s, y0s, x1s, y1s)
        for i in range(g * group, (g + 1) * group):
            out[i] = _ray_distance(ox[i], oy[i], ux[i], uy[i], x0s, y0s, x1s, y1s, n_cand, size)


def _readings_loop(
    poses: FloatArray, c: FloatArray, s: FloatArray, mounts: FloatArray, cr: FloatArray,
    sr: FloatArray, counts: IntArray, reach: float, boxes: FloatArray, size: float,
    max_range: float, out: FloatArray,
) -> None:
    """:func:`sensor_readings` of every robot in one pass (compiled by numba): robot ``g``'s
    sensor ``i`` sits at its mount (``c``, ``s`` the cos and sin of its heading, the same
    products as :func:`sensor_frames`) and casts its first ``counts[i]`` rays, of body-frame
    directions ``(cr[i, r], sr[i, r])``, turned by the heading as :func:`_ray_directions`
    does (the rest of a row repeats its first ray); its reading is the nearest hit within
    ``max_range``, else +inf."""
    x0s, y0s, x1s, y1s = _box_scratch(boxes.shape[0])
    cull = max_range + reach + CULL_SLACK
    for g in range(poses.shape[0]):
        x = poses[g, 0]
        y = poses[g, 1]
        n_cand = _near_boxes(x, y, cull, boxes, x0s, y0s, x1s, y1s)
        for i in range(mounts.shape[0]):
            mx = mounts[i, 0]
            my = mounts[i, 1]
            ox = x + (mx * c[g] - my * s[g])
            oy = y + (mx * s[g] + my * c[g])
            nearest = np.inf
            for r in range(counts[i]):
                ux = c[g] * cr[i, r] - s[g] * sr[i, r]
                uy = s[g] * cr[i, r] + c[g] * sr[i, r]
                d = _ray_distance(ox, oy, ux, uy, x0s, y0s, x1s, y1s, n_cand, size)
                nearest = min(nearest, np.inf if d > max_range else d)
            out[g, i] = nearest


_cast_numba: Callable[..., None] | None
_readings_numba: Callable[..., None] | None
try:
    from numba import njit

    # No fastmath: the kernels must round exactly like the numpy backend. The scalar helpers
    # are compiled first so that the loops calling them compile against them.
    _box_scratch = njit(cache=True)(_box_scratch)
    _near_boxes = njit(cache=True)(_near_boxes)
    _ray_distance = njit(cache=True)(_ray_distance)
    _cast_numba = njit(cache=True)(_cast_loop)
    _readings_numba = njit(cache=True)(_readings_loop)
except ImportError:  # pragma: no cover - numba is in the lock file; numpy stays the fallback
    _cast_numba = None
    _readings_numba = None

HAVE_NUMBA = _cast_numba is not None


def _use_numba(backend: Backend) -> bool:
    if backend == "numba" and not HAVE_NUMBA:
        raise ValueError("backend 'numba' requested but numba is not importable")
    if backend not in ("auto", "numba", "numpy"):
        raise ValueError(f"unknown backend {backend!r}")
    return backend != "numpy" and HAVE_NUMBA


def _cast(
    origins: FloatArray, ux: FloatArray, uy: FloatArray, boxes: ArrayLike, arena_size: float,
    max_range: float, backend: Backend, group: int, centres: FloatArray, reach: float,
) -> FloatArray:
    """Rays from ``origins`` ``(n, 2)`` along unit directions ``(ux, uy)`` ``(n,)``, grouped
    ``group`` at a time around ``centres`` (m): :func:`cast_rays`'s readings."""
    b = np.ascontiguousarray(boxes, dtype=np.float64).reshape(-1, 4)
    ox = np.ascontiguousarray(origins[:, 0])
    oy = np.ascontiguousarray(origins[:, 1])
    size = float(arena_size)
    if _use_numba(backend) and _cast_numba is not None:
        dist = np.empty(ox.shape[0], dtype=np.float64)
        gx = np.ascontiguousarray(centres[:, 0])
        gy = np.ascontiguousarray(centres[:, 1])
        _cast_numba(ox, oy, ux, uy, group, gx, gy, reach, b, size, float(max_range), dist)
    else:
        dist = _cast_numpy(ox, oy, ux, uy, b, size)
    dist[dist > max_range] = np.inf
    return dist


def cast_rays(
    origins: ArrayLike, angles: ArrayLike, boxes: ArrayLike, arena_size: float,
    max_range: float, *, backend: Backend = "auto",
) -> FloatArray:
    """Distance (m) along each ray to the first box or arena wall; ``+inf`` beyond range.

    Args:
        origins: ``(n, 2)`` ray origins inside the arena ``[0, size]^2`` (m, map frame).
        angles: ``(n,)`` ray directions (rad, map frame).
        boxes: ``(k, 4)`` obstacles ``[xmin, ymin, xmax, ymax]`` (m).
        arena_size: side of the square arena (m).
        max_range: sensor range max (m); a first hit farther than this reads ``+inf``.
        backend: ``"numba"``, ``"numpy"`` or ``"auto"`` (numba when importable).

    Returns:
        ``(n,)`` float64 distances; 0 for an origin inside (or on) a box.
    """
    o = np.asarray(origins, dtype=np.float64).reshape(-1, 2)
    a = np.asarray(angles, dtype=np.float64).reshape(-1)
    if a.shape[0] != o.shape[0]:
        raise ValueError(f"{o.shape[0]} origins but {a.shape[0]} angles")
    return _cast(o, np.cos(a), np.sin(a), boxes, arena_size, max_range, backend, 1, o, 0.0)


def sensor_frames(poses: ArrayLike, profile: RobotProfile) -> FloatArray:
    """Map-frame origin and direction of every sensor: ``(n, 3)`` poses -> ``(n, s, 3)``.

    A mount ``(mx, my, ma)`` in the body frame (x forward, y left) of a robot at
    ``(x, y, theta)`` sits at ``(x + mx cos theta - my sin theta, y + mx sin theta +
    my cos theta)`` and faces ``theta + ma`` (rad, not wrapped).
    """
    p = np.asarray(poses, dtype=np.float64).reshape(-1, 3)
    mounts = profile.sensor_mounts
    c = np.cos(p[:, 2])[:, None]
    s = np.sin(p[:, 2])[:, None]
    out = np.empty((p.shape[0], mounts.shape[0], 3), dtype=np.float64)
    out[..., 0] = p[:, 0, None] + (mounts[None, :, 0] * c - mounts[None, :, 1] * s)
    out[..., 1] = p[:, 1, None] + (mounts[None, :, 0] * s + mounts[None, :, 1] * c)
    out[..., 2] = p[:, 2, None] + mounts[None, :, 2]
    return out


def beam_frames(poses: ArrayLike, profile: RobotProfile) -> FloatArray:
    """Map-frame origin and direction of every ray of every beam: ``(n, s, beam_rays, 3)``.

    Ray ``j`` of sensor ``i`` starts at the sensor's origin (:func:`sensor_frames`) and faces
    its direction plus ``profile.ray_offsets[i, j]``; a single-ray sensor's one ray is its
    frame (repeated ``beam_rays`` times when other sensors have the beam).
    """
    frames = sensor_frames(poses, profile)[:, :, None, :]
    if profile.beam_rays == 1:
        return frames
    out = np.repeat(frames, profile.beam_rays, axis=2)
    out[..., 2] += profile.ray_offsets
    return out


def _body_ray_directions(profile: RobotProfile) -> tuple[FloatArray, FloatArray]:
    """Cos and sin of every ray's angle from the body's x axis (its sensor's facing plus
    its offset, ``profile.ray_offsets``): ``(n_sensors, beam_rays)`` each."""
    angles = profile.sensor_mounts[:, 2, None] + profile.ray_offsets
    return np.cos(angles), np.sin(angles)


def _ray_directions(
    c: FloatArray, s: FloatArray, profile: RobotProfile
) -> tuple[FloatArray, FloatArray]:
    """Map-frame unit directions ``(ux, uy)`` of every ray, ``(n, n_sensors, beam_rays)``
    each, of robots whose headings have cos ``c`` and sin ``s`` ``(n,)``.

    A ray at angle ``a`` from the body's x axis of a robot heading ``theta`` faces
    ``theta + a``: ``u = R(theta) (cos a, sin a) = (c cos a - s sin a, s cos a + c sin a)``,
    four products per ray instead of a cos and a sin (those of ``a`` are the profile's).
    """
    cr, sr = _body_ray_directions(profile)
    c3 = c[:, None, None]
    s3 = s[:, None, None]
    return c3 * cr - s3 * sr, s3 * cr + c3 * sr


def sensor_readings(
    poses: ArrayLike, profile: RobotProfile, world: World, *, backend: Backend = "auto"
) -> FloatArray:
    """Range readings ``(n, n_sensors)`` (m, ``+inf`` beyond ``profile.sensor_range``).

    Reading ``i`` comes from ``profile.sensors[i]``: the nearest hit of its beam's rays
    (:func:`beam_frames`; one ray for a sensor without a beam), cast from its origin along
    :func:`_ray_directions`. The numba backend does each robot's mounts, ray directions, box
    culling, rays and range cut in one compiled loop (:func:`_readings_loop`), without
    temporaries; the readings are the numpy backend's, bit for bit.
    """
    p = np.ascontiguousarray(poses, dtype=np.float64).reshape(-1, 3)
    mounts = profile.sensor_mounts
    # one robot's rays share a box culling: its mounts all lie within `reach` of its centre
    reach = float(np.hypot(mounts[:, 0], mounts[:, 1]).max())
    c = np.cos(p[:, 2])
    s = np.sin(p[:, 2])
    if _use_numba(backend) and _readings_numba is not None:
        cr, sr = _body_ray_directions(profile)
        readings = np.empty((p.shape[0], mounts.shape[0]), dtype=np.float64)
        _readings_numba(
            p, c, s, mounts, cr, sr, profile.ray_counts, reach,
            np.ascontiguousarray(world.obstacles, dtype=np.float64).reshape(-1, 4),
            float(world.size), float(profile.sensor_range), readings,
        )
        return readings
    origins = np.repeat(sensor_frames(p, profile)[:, :, None, :2], profile.beam_rays, axis=2)
    ux, uy = _ray_directions(c, s, profile)
    dist = _cast(
        origins.reshape(-1, 2), ux.reshape(-1), uy.reshape(-1), world.obstacles, world.size,
        profile.sensor_range, backend, profile.n_sensors * profile.beam_rays, p[:, :2], reach,
    )
    found: FloatArray = dist.reshape(ux.shape).min(axis=2)
    return found
