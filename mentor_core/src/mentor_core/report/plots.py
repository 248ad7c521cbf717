"""Figures of worlds, scenarios, robots, rays and trajectories (matplotlib, no pyplot).

Functions draw on an ``Axes`` they are given; :func:`new_figure` makes a figure on the Agg
canvas without touching pyplot's global state or the process-wide backend, and
:func:`save_png` writes it atomically. Importing this module selects no backend.
"""

from __future__ import annotations

import io
from collections.abc import Sequence
from pathlib import Path

import numpy as np
from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.patches import Circle, Polygon, Rectangle
from numpy.typing import ArrayLike

from mentor_core.atomic import write_bytes_atomic
from mentor_core.sim.robots import RobotProfile, body_corners
from mentor_core.sim.sensors import sensor_frames
from mentor_core.sim.world import Scenario, World

OBSTACLE_COLOR = "0.35"
START_COLOR = "tab:green"
GOAL_COLOR = "tab:red"
ROBOT_COLOR = "tab:blue"
RAY_HIT_COLOR = "tab:orange"
RAY_FREE_COLOR = "0.6"


def new_figure(width_in: float = 7.0, height_in: float = 7.0) -> Figure:
    """A figure on its own Agg canvas (no pyplot, no global backend change)."""
    fig = Figure(figsize=(width_in, height_in), layout="constrained")
    FigureCanvasAgg(fig)
    return fig


def save_png(fig: Figure, path: str | Path, dpi: int = 120) -> None:
    """Render ``fig`` as PNG and write it atomically (never a half-written file)."""
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=dpi)
    write_bytes_atomic(path, buffer.getvalue())


def draw_world(
    ax: Axes,
    world: World,
    scenarios: Sequence[Scenario] = (),
    profile: RobotProfile | None = None,
    pose: ArrayLike | None = None,
    trajectory: ArrayLike | None = None,
    rays: ArrayLike | None = None,
) -> None:
    """Draw the arena, obstacles, scenarios and optionally a robot, its rays and a path.

    Args:
        ax: target axes (its limits and aspect are set to the arena).
        world: arena and obstacles (m).
        scenarios: starts (triangle pointing along the heading) and goals (cross; with the
            goal-radius circle when ``profile`` is given); numbered by position.
        profile: the robot; needed for ``pose`` and ``rays``.
        pose: (x, y, theta) at which the body rectangle is drawn.
        trajectory: (m, 2+) map-frame positions drawn as a polyline.
        rays: (k,) readings at ``pose`` in sensor order; each ray ends at its hit point (solid,
            with a dot), or at the sensor range when +inf (dashed).
    """
    size = world.size
    ax.add_patch(Rectangle((0.0, 0.0), size, size, fill=False, edgecolor="black", lw=1.5))
    for x0, y0, x1, y1 in world.obstacles:
        ax.add_patch(Rectangle((x0, y0), x1 - x0, y1 - y0, color=OBSTACLE_COLOR))
    for i, sc in enumerate(scenarios):
        _draw_scenario(ax, sc, i, profile, size)
    if (pose is not None or rays is not None) and profile is None:
        raise ValueError("drawing a robot pose or rays needs its profile")
    if rays is not None and pose is None:
        raise ValueError("drawing rays needs the pose they were read at")
    if profile is not None and pose is not None:
        corners = body_corners(profile, pose)[0]
        ax.add_patch(Polygon(corners, closed=True, color=ROBOT_COLOR, alpha=0.8, zorder=4))
        if rays is not None:
            _draw_rays(ax, profile, pose, rays)
    if trajectory is not None:
        path = np.atleast_2d(np.asarray(trajectory, dtype=np.float64))
        ax.plot(path[:, 0], path[:, 1], color=ROBOT_COLOR, lw=1.5, zorder=3)
    margin = 0.03 * size
    ax.set_xlim(-margin, size + margin)
    ax.set_ylim(-margin, size + margin)
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")


def _draw_scenario(
    ax: Axes, sc: Scenario, index: int, profile: RobotProfile | None, size: float
) -> None:
    (sx, sy, th), (gx, gy) = sc.start, sc.goal
    ax.plot(
        [sx], [sy], marker=(3, 0, np.degrees(th) - 90.0), color=START_COLOR, ms=8, zorder=5
    )
    ax.plot([gx], [gy], marker="x", color=GOAL_COLOR, ms=7, zorder=5)
    if profile is not None:
        ax.add_patch(Circle((gx, gy), profile.goal_radius, fill=False, color=GOAL_COLOR, lw=0.8))
    offset = 0.01 * size
    ax.annotate(str(index), (sx + offset, sy + offset), fontsize=7, color=START_COLOR)
    ax.annotate(str(index), (gx + offset, gy + offset), fontsize=7, color=GOAL_COLOR)


def _draw_rays(ax: Axes, profile: RobotProfile, pose: ArrayLike, rays: ArrayLike) -> None:
    readings = np.asarray(rays, dtype=np.float64).reshape(-1)
    if readings.shape != (profile.n_sensors,):
        raise ValueError(f"expected {profile.n_sensors} readings, got {readings.shape[0]}")
    for (ox, oy, a), r in zip(sensor_frames(pose, profile)[0], readings, strict=True):
        hit = bool(np.isfinite(r))
        length = min(float(r), profile.sensor_range) if hit else profile.sensor_range
        ex, ey = ox + length * np.cos(a), oy + length * np.sin(a)
        color = RAY_HIT_COLOR if hit else RAY_FREE_COLOR
        ax.plot([ox, ex], [oy, ey], color=color, lw=1.0, ls="-" if hit else "--", zorder=4)
        if hit:
            ax.plot([ex], [ey], marker="o", color=color, ms=3, zorder=4)
