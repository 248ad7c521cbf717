"""Following a global path: the point a lookahead distance ahead along it (a "carrot").

Nav2 splits navigation into a global planner (a path through the map) and a local controller
that steers along it; here the controller is the evolved network, given the carrot as its goal.
A path is a polyline ``(k, 2)`` in the map frame (m). The robot's progress is the arc length
``s*`` of the point of the path nearest to it; the carrot is the point at arc length
``min(s* + lookahead, L)``, ``L`` the path's length, so the carrot is the path's end once the
robot is within ``lookahead`` of it.

The nearest point is searched only from the progress already made (``from_s``) onwards, so a
path that comes back near itself (round a wall's end) is not cut short.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

FloatArray = NDArray[np.float64]


def as_path(points: ArrayLike) -> FloatArray:
    """A path as a float64 ``(k, 2)`` array of at least one finite point; ValueError otherwise."""
    path = np.asarray(points, dtype=np.float64)
    if path.ndim != 2 or path.shape[1] != 2 or len(path) == 0:
        raise ValueError(f"a path is a (k, 2) array of points, got shape {path.shape}")
    if not np.all(np.isfinite(path)):
        raise ValueError("a path's points must be finite")
    return path


def cumulative_length(path: ArrayLike) -> FloatArray:
    """Arc length (m) at each vertex: ``s_0 = 0``, ``s_i = s_{i-1} + |p_i - p_{i-1}|``."""
    p = as_path(path)
    return np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(p, axis=0).T))])


def _path_and_lengths(
    path: ArrayLike, lengths: FloatArray | None
) -> tuple[FloatArray, FloatArray]:
    """The checked path and its :func:`cumulative_length`, or, with ``lengths`` (the caller's
    for this path, checked when it was computed), the path as it is and them."""
    if lengths is not None:
        return np.asarray(path, dtype=np.float64), lengths
    p = as_path(path)
    return p, cumulative_length(p)


def progress(
    path: ArrayLike, xy: ArrayLike, from_s: float = 0.0, lengths: FloatArray | None = None
) -> float:
    """Arc length (m) of the path's point nearest to ``xy``, searched from ``from_s`` on;
    ``lengths``: the path's :func:`cumulative_length`, when the caller has it."""
    p, s = _path_and_lengths(path, lengths)
    if len(p) == 1:
        return 0.0
    q = np.asarray(xy, dtype=np.float64)[:2]
    a, b = p[:-1], p[1:]
    seg = b - a
    seg_len = s[1:] - s[:-1]
    # projection of q on each segment, clamped to it; zero-length segments project on a
    along = np.einsum("ij,ij->i", q - a, seg)
    t = np.where(seg_len > 0, along / np.maximum(seg_len**2, 1e-300), 0.0)
    t = np.clip(t, 0.0, 1.0)
    s_on = s[:-1] + t * seg_len
    # segments entirely behind from_s are out; the one containing it starts at from_s
    keep = s[1:] >= from_s
    s_on = np.maximum(s_on, from_s)
    points = a + ((s_on - s[:-1]) / np.where(seg_len > 0, seg_len, 1.0))[:, None] * seg
    dist = np.hypot(*(points - q).T)
    dist[~keep] = np.inf
    return float(s_on[int(np.argmin(dist))])


def point_at(
    path: ArrayLike, s_query: float, lengths: FloatArray | None = None
) -> tuple[float, float]:
    """The path's point at arc length ``s_query`` (m), clamped to ``[0, L]``; ``lengths``:
    the path's :func:`cumulative_length`, when the caller has it."""
    p, s = _path_and_lengths(path, lengths)
    q = float(np.clip(s_query, 0.0, s[-1]))
    x = float(np.interp(q, s, p[:, 0]))
    y = float(np.interp(q, s, p[:, 1]))
    return x, y


def lookahead_point(
    path: ArrayLike, xy: ArrayLike, lookahead: float, from_s: float = 0.0,
    lengths: FloatArray | None = None,
) -> tuple[tuple[float, float], float]:  # fmt: skip
    """``(carrot, s*)``: the point ``lookahead`` m along the path past the robot's progress
    ``s*`` (the nearest point at or after ``from_s``), and that progress, to pass as the next
    call's ``from_s``; ``lengths``: the path's :func:`cumulative_length`, when the caller has
    it."""
    if not lookahead > 0.0:
        raise ValueError(f"lookahead must be positive, got {lookahead}")
    p, s = _path_and_lengths(path, lengths)
    s_star = progress(p, xy, from_s, s)
    return point_at(p, s_star + lookahead, s), s_star
