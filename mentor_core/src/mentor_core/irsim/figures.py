"""Trajectories of IR-SIM episodes: the static obstacles, the pair's start and goal (its goal
radius), the robot's path, and each agent's track (faint) with where it stood at the end."""

from __future__ import annotations

import io
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from matplotlib.figure import Figure
from matplotlib.patches import Circle, Polygon

from mentor_core.atomic import write_bytes_atomic
from mentor_core.irsim.episode import EpisodeResult
from mentor_core.irsim.world_file import IrsimWorld
from mentor_core.sim.robots import get_profile

COLOURS = {"reached": "tab:green", "collision_static": "tab:red",
           "collision_agent": "tab:orange", "timeout": "tab:purple"}  # fmt: skip


def draw_episode(ax: Any, world: IrsimWorld, result: EpisodeResult) -> None:
    """One recorded episode (module docstring) on ``ax``."""
    for entry in world.config.get("obstacle", []):
        shape = entry["shape"]
        if shape["name"] == "circle":
            x, y = entry["state"][:2]
            ax.add_patch(Circle((x, y), shape["radius"], color="0.35"))
        elif shape["name"] == "polygon":
            ax.add_patch(Polygon(shape["vertices"], closed=True, color="0.35"))
    pair = world.pairs[result.pair]
    if result.agents is not None and result.agents.size:
        for j in range(result.agents.shape[1]):
            track = result.agents[:, j]
            ax.plot(track[:, 0], track[:, 1], color="tab:blue", lw=0.6, alpha=0.35)
            radius = pair.agents[j]["shape"]["radius"] if j < len(pair.agents) else 0.2
            ax.add_patch(Circle(tuple(track[-1]), radius, color="tab:blue", alpha=0.6))
    ax.add_patch(Circle(pair.goal, get_profile(world.robot).goal_radius, fill=False,
                        ls="--", color="tab:green"))  # fmt: skip
    if result.trajectory is not None:
        path = result.trajectory
        ax.plot(path[:, 0], path[:, 1], color=COLOURS[result.outcome], lw=1.6)
    ax.plot(*pair.start[:2], "k^", ms=6)
    ax.plot(*pair.goal, "g*", ms=9)
    ax.set_xlim(0, world.size)
    ax.set_ylim(0, world.size)
    ax.set_aspect("equal")
    ax.set_xticks([])
    ax.set_yticks([])
    ax.set_title(f"{world.name} #{result.pair}: {result.outcome} ({result.time:.1f} s)",
                 fontsize=7)  # fmt: skip


def save_episodes(path: str | Path, episodes: Sequence[tuple[IrsimWorld, EpisodeResult]],
                  columns: int = 3) -> None:  # fmt: skip
    """The recorded ``episodes`` side by side in one small PNG at ``path`` (written whole or
    not at all)."""
    rows = -(-len(episodes) // columns)
    fig = Figure(figsize=(2.6 * columns, 2.7 * rows))
    axes = fig.subplots(rows, columns, squeeze=False)
    for ax, (world, result) in zip(axes.flat, episodes, strict=False):
        draw_episode(ax, world, result)
    for ax in list(axes.flat)[len(episodes):]:
        ax.axis("off")
    fig.tight_layout()
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=80)
    write_bytes_atomic(path, buffer.getvalue())


__all__ = ["COLOURS", "draw_episode", "save_episodes"]
