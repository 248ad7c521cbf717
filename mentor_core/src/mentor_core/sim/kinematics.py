"""Unicycle kinematics over one control period (REP-103 units: m, rad).

A decision ``(dtheta, ds)`` moves the robot along the exact circular arc that ends with heading
``theta + dtheta`` after a path length ``ds`` (the paper's "rotate, then translate" with the
same end heading and the same distance travelled). All functions are pure and vectorised over
robots; poses are ``(x, y, theta)`` float64 rows with theta wrapped to ``(-pi, pi]``.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
from numpy.typing import ArrayLike, NDArray

FloatArray = NDArray[np.float64]

TWO_PI = 2.0 * np.pi


def wrap_angle(angles: ArrayLike) -> FloatArray:
    """Wrap angles (rad) onto ``(-pi, pi]``: ``pi - ((pi - a) mod 2 pi)``."""
    a = np.asarray(angles, dtype=np.float64)
    return np.pi - np.mod(np.pi - a, TWO_PI)


def to_body(theta: ArrayLike, vectors: ArrayLike) -> FloatArray:
    """Map-frame vectors (n, 2) in the body frames of headings ``theta`` (n,), rad: each
    rotated by ``-theta``, ``(c x + s y, -s x + c y)``."""
    t = np.asarray(theta, dtype=np.float64)
    v = np.asarray(vectors, dtype=np.float64)
    c, s = np.cos(t), np.sin(t)
    return np.column_stack([c * v[:, 0] + s * v[:, 1], -s * v[:, 0] + c * v[:, 1]])


def _arc_points(
    x: FloatArray, y: FloatArray, theta: FloatArray, dtheta: FloatArray, ds: FloatArray
) -> FloatArray:
    """Elementwise end pose of the arc; every argument has the same shape ``s``; -> ``s + (3,)``.

    With curvature ``k = dtheta / ds`` the exact arc is
    ``x' = x + (sin(theta + dtheta) - sin theta) / k``, ``y' = y - (cos(theta + dtheta) -
    cos theta) / k``. The same point is reached by the chord of length
    ``ds * sin(dtheta / 2) / (dtheta / 2)`` (``ds`` when ``dtheta = 0``) along heading
    ``theta + dtheta / 2``, which has no division by a vanishing curvature.

    One compiled loop (numba) computes it for every caller (the engine, both of its backends,
    and the reference physics), so they all move robots along bit-identical arcs; the numpy
    version is the fallback without numba.
    """
    shape = x.shape
    fx, fy, ft, fdt, fds = (
        np.ascontiguousarray(v, dtype=np.float64).reshape(-1) for v in (x, y, theta, dtheta, ds)
    )
    out = np.empty((fx.shape[0], 3), dtype=np.float64)
    if _arc_numba is not None:
        _arc_numba(fx, fy, ft, fdt, fds, out)
    else:
        _arc_numpy(fx, fy, ft, fdt, fds, out)
    return out.reshape(*shape, 3)


def _arc_numpy(
    x: FloatArray, y: FloatArray, theta: FloatArray, dtheta: FloatArray, ds: FloatArray,
    out: FloatArray,
) -> None:
    half = 0.5 * dtheta
    safe = np.where(half == 0.0, 1.0, half)
    chord = np.where(half == 0.0, ds, ds * (np.sin(safe) / safe))
    mid = theta + half
    out[:, 0] = x + chord * np.cos(mid)
    out[:, 1] = y + chord * np.sin(mid)
    out[:, 2] = wrap_angle(theta + dtheta)


def arc_pose(
    x: float, y: float, theta: float, dtheta: float, ds: float
) -> tuple[float, float, float]:
    """One end pose of the arc, scalar (compiled by numba; ``%`` is Python's floor modulo, as
    ``np.mod``). Every compiled caller (:func:`_arc_loop`, the narrow phase of
    :func:`mentor_core.sim.collision.swept_events`) moves robots with this one function, so they
    agree bit for bit."""
    half = 0.5 * dtheta
    chord = ds if half == 0.0 else ds * (math.sin(half) / half)
    mid = theta + half
    return (
        x + chord * math.cos(mid),
        y + chord * math.sin(mid),
        math.pi - ((math.pi - (theta + dtheta)) % TWO_PI),
    )


def _arc_loop(
    x: FloatArray, y: FloatArray, theta: FloatArray, dtheta: FloatArray, ds: FloatArray,
    out: FloatArray,
) -> None:
    """Scalar twin of :func:`_arc_numpy`: :func:`arc_pose` per robot (compiled by numba)."""
    for i in range(x.shape[0]):
        out[i, 0], out[i, 1], out[i, 2] = arc_pose(x[i], y[i], theta[i], dtheta[i], ds[i])


_arc_numba: Callable[..., None] | None
try:
    from numba import njit

    # no fastmath: IEEE rounding throughout; arc_pose is compiled first so that the loops
    # calling it (here and in collision) compile against it. numba's on-disk cache does not
    # notice a change to a callee in another file: after editing arc_pose, clear the cache
    # (NUMBA_CACHE_DIR) or collision's loop keeps the old one.
    arc_pose = njit(cache=True)(arc_pose)
    _arc_numba = njit(cache=True)(_arc_loop)
except ImportError:  # pragma: no cover - numba is in the lock file
    _arc_numba = None


def unicycle_arc(poses: ArrayLike, dtheta: ArrayLike, ds: ArrayLike) -> FloatArray:
    """End poses ``(n, 3)`` after one decision.

    Args:
        poses: ``(n, 3)`` start poses ``(x, y, theta)`` (m, m, rad).
        dtheta: ``(n,)`` heading change over the control period (rad).
        ds: ``(n,)`` path length along the arc (m).
    """
    p = np.asarray(poses, dtype=np.float64).reshape(-1, 3)
    dth = np.broadcast_to(np.asarray(dtheta, dtype=np.float64), p.shape[:1])
    dist = np.broadcast_to(np.asarray(ds, dtype=np.float64), p.shape[:1])
    return _arc_points(p[:, 0], p[:, 1], p[:, 2], dth, dist)


def arc_fraction_poses(
    poses: ArrayLike, dtheta: ArrayLike, ds: ArrayLike, fractions: ArrayLike
) -> FloatArray:
    """Poses at path-length ``fractions`` of each robot's arc; broadcasting -> ``shape + (3,)``.

    ``poses[..., i]``, ``dtheta``, ``ds`` and ``fractions`` broadcast together; the pose at
    fraction ``f`` is the arc with ``(f * dtheta, f * ds)``, so ``f = 1`` is exactly
    :func:`unicycle_arc`. The engine and the reference physics both call this, so they test
    bit-identical sample poses.
    """
    p = np.asarray(poses, dtype=np.float64)
    f = np.asarray(fractions, dtype=np.float64)
    dth = np.asarray(dtheta, dtype=np.float64) * f
    dist = np.asarray(ds, dtype=np.float64) * f
    x, y, th, dth, dist = np.broadcast_arrays(p[..., 0], p[..., 1], p[..., 2], dth, dist)
    return _arc_points(x, y, th, dth, dist)


def arc_samples(
    poses: ArrayLike, dtheta: ArrayLike, ds: ArrayLike, n_samples: int
) -> FloatArray:
    """Poses ``(n, n_samples + 1, 3)`` at path-length fractions ``j / n_samples``.

    Sample 0 is the start pose (theta wrapped), sample ``n_samples`` the end of the arc.
    """
    if n_samples < 1:
        raise ValueError(f"n_samples must be >= 1, got {n_samples}")
    p = np.asarray(poses, dtype=np.float64).reshape(-1, 3)
    fractions = np.arange(n_samples + 1, dtype=np.float64) / np.float64(n_samples)
    dth = np.asarray(dtheta, dtype=np.float64).reshape(-1, 1)
    dist = np.asarray(ds, dtype=np.float64).reshape(-1, 1)
    return arc_fraction_poses(p[:, None, :], dth, dist, fractions[None, :])
