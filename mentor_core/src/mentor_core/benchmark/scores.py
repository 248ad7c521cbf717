"""Scores of a planner on the benchmark: success, collision and timeout rates, time to goal,
and SPL, per family and overall, under a time limit.

SPL (Anderson et al. 2018, "On evaluation of embodied navigation agents"), the mean over the
``N`` pairs of

    SPL = (1 / N) sum_i S_i l_i / max(p_i, l_i)

with ``S_i`` success, ``l_i`` the shortest path length and ``p_i`` the length of the path
taken. Here ``l_i`` is the shortest path for the body's circumscribed disc INTO THE GOAL
RADIUS, where an episode ends (``BenchPair.shortest``); Anderson et al. measure to the goal
point because their agent must stop near it, which with the UGV's 1 m goal radius would
forgive a detour of up to 1 m. ``p_i`` is the arc length driven: the sum of the steps ``ds``,
the arriving one counted up to the sample that reached the goal.

A run is made once with the longer of the two limits; its outcome under a limit ``L``
is that of a run with ``L``: an episode is cut after ``ceil(L / dt)`` decisions (as
``mentor_core.sim.episode`` cuts at ``ceil(T_tot / dt)``), so one that reached the goal or
collided later counts as timed out.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from mentor_core.objectives.performance import path_credit
from mentor_core.sim.episode import EpisodeBatch
from mentor_core.sim.robots import RobotProfile

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]
IntArray = NDArray[np.int64]
#: the score names of :func:`summarise`, in table order
SCORE_KEYS = ("success", "collision", "timeout", "time_to_goal", "spl")


@dataclass(frozen=True)
class Outcomes:
    """How each episode of one planner ended, with the longest limit, arrays per pair."""

    reached: BoolArray
    collided: BoolArray
    steps: IntArray
    time: FloatArray  # s
    path_length: FloatArray  # m, up to the end of the episode
    final_distance: FloatArray  # m
    trajectories: tuple[FloatArray, ...]  # per pair (steps + 1, 3)


def outcomes(batch: EpisodeBatch, profile: RobotProfile) -> Outcomes:
    """The :class:`Outcomes` of an episode batch (``profile`` the planner's own)."""
    return Outcomes(
        reached=batch.reached.copy(), collided=batch.collided.copy(), steps=batch.steps.copy(),
        time=batch.time_used.copy(), path_length=batch.path_length(profile),
        final_distance=batch.final_distance.copy(),
        trajectories=tuple(batch.trajectories[i, : int(s) + 1].copy()
                           for i, s in enumerate(batch.steps)),
    )  # fmt: skip


def under_limit(
    result: Outcomes, limits: Sequence[float] | FloatArray, control_period: float
) -> tuple[BoolArray, BoolArray]:
    """``(success, collision)`` per pair under per-pair time limits (s): an episode still
    running after ``ceil(L / dt)`` decisions timed out (module docstring)."""
    within = result.steps <= decisions_allowed(limits, control_period)
    return result.reached & within, result.collided & within


def decisions_allowed(limits: Sequence[float] | FloatArray, control_period: float) -> IntArray:
    """Decisions within each per-pair time limit (s): ``ceil(L / dt)`` (module docstring)."""
    allowed: IntArray = np.ceil(np.asarray(limits, dtype=np.float64) / control_period).astype(
        np.int64)
    return allowed


def spl(success: BoolArray, shortest: FloatArray, taken: FloatArray) -> FloatArray:
    """Per-pair ``S_i l_i / max(p_i, l_i)`` (module docstring); 1 for a success with
    ``l = 0``."""
    return np.where(success, path_credit(shortest, taken), 0.0)


def summarise(success: BoolArray, collision: BoolArray, time: FloatArray,
              spl_values: FloatArray) -> dict[str, float]:
    """The scores of some pairs: success, collision and timeout rates, mean time to goal of
    the successes (s; NaN when none) and mean SPL; all NaN for no pairs."""
    n = len(success)
    if n == 0:
        return {key: math.nan for key in SCORE_KEYS}
    reached_times = np.asarray(time)[success]
    return {
        "success": float(np.mean(success)),
        "collision": float(np.mean(collision)),
        "timeout": float(np.mean(~(success | collision))),
        "time_to_goal": float(reached_times.mean()) if reached_times.size else math.nan,
        "spl": float(np.mean(spl_values)),
    }


def score_table(
    result: Outcomes, families: Sequence[str], shortest: FloatArray,
    limits: Mapping[str, FloatArray], control_period: float,
) -> dict[str, dict[str, dict[str, float]]]:
    """``{limit name: {"overall" | family: scores}}`` of one planner: ``families`` and
    ``shortest`` per pair, ``limits`` per limit name the per-pair limits (s)."""
    fam = np.asarray(families)
    table: dict[str, dict[str, dict[str, float]]] = {}
    for name, limit in limits.items():
        ok, hit = under_limit(result, limit, control_period)
        values = spl(ok, shortest, result.path_length)
        rows = {"overall": summarise(ok, hit, result.time, values)}
        for f in dict.fromkeys(families):  # first-seen order
            m = fam == f
            rows[f] = summarise(ok[m], hit[m], result.time[m], values[m])
        table[name] = rows
    return table
