"""The scores of IR-SIM episodes, as the benchmark's table gives them, with collisions with
static obstacles and with moving agents counted apart.

Per group of episodes: success (reached within the limit), collisions with a static obstacle,
collisions with a moving agent, timeouts (shares of the episodes), mean SPL, and the mean
time of the successes (s; NaN when none).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from typing import Any

import numpy as np

from mentor_core.irsim.episode import EpisodeResult

KEYS = ("n", "success", "collision_static", "collision_agent", "timeout", "spl", "time")


def scores(results: Sequence[EpisodeResult]) -> dict[str, float]:
    """The scores of ``results`` (module docstring); ``n`` their number."""
    n = len(results)
    if n == 0:
        return {key: math.nan for key in KEYS} | {"n": 0}
    outcome = np.array([r.outcome for r in results])
    reached = outcome == "reached"
    times = np.array([r.time for r in results])[reached]
    return {
        "n": n,
        "success": float(reached.mean()),
        "collision_static": float((outcome == "collision_static").mean()),
        "collision_agent": float((outcome == "collision_agent").mean()),
        "timeout": float((outcome == "timeout").mean()),
        "spl": float(np.mean([r.spl for r in results])),
        "time": float(times.mean()) if times.size else math.nan,
    }


def row(label: str, values: dict[str, float]) -> str:
    """One Markdown table row: label, n, success, collisions (static, agent), SPL, time."""
    def pct(key: str) -> str:
        return f"{100 * values[key]:.1f} %"

    time = "-" if math.isnan(values["time"]) else f"{values['time']:.1f} s"
    return (f"| {label} | {int(values['n'])} | {pct('success')} | {pct('collision_static')} | "
            f"{pct('collision_agent')} | {values['spl']:.3f} | {time} |")


HEADER = ("| planner | episodes | success | collision: static | collision: agent | SPL | "
          "time to goal |\n| --- | --- | --- | --- | --- | --- | --- |")


def as_rows(results: Iterable[EpisodeResult]) -> list[dict[str, Any]]:
    """The episodes as plain rows (for JSON): everything but the recorded poses."""
    keys = ("world", "pair", "driver", "seed", "outcome", "time", "path_length", "shortest",
            "spl", "decisions", "refused", "agent_speed")
    out = []
    for r in results:
        values = {key: getattr(r, key) for key in keys}
        if isinstance(values["agent_speed"], float) and math.isnan(values["agent_speed"]):
            values["agent_speed"] = None
        out.append(values)
    return out


__all__ = ["HEADER", "KEYS", "as_rows", "row", "scores"]
