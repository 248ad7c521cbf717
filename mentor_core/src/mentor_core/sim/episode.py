"""Episodes' outcomes: what :func:`mentor_core.controller.episodes.run_episodes` returns, and
the bookkeeping of running many robots in several worlds.

Time: a decision takes one control period, except the one that reaches the goal, which takes
the share of the period spent on the arc up to the arriving sample; ``time_used`` sums these.

Experience (paper, "Experience-Gain"): every decision gives the point
``V = [U(t), A(t), U(t + 1)]`` of dimension ``2 k + 2``, with ``U`` the k range readings
clipped to the sensor range and ``A = (dtheta, ds)``.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from mentor_core.sim.robots import RobotProfile
from mentor_core.sim.world import Scenario, World

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
BoolArray = NDArray[np.bool_]
Policy = Callable[[FloatArray, IntArray], ArrayLike]
#: ``input_goals(poses (m, 3), robots (m,)) -> (m, 2)``: the goal each robot's network sees
InputGoals = Callable[[FloatArray, IntArray], ArrayLike]


@dataclass(frozen=True)
class EpisodeBatch:
    """Outcome of ``n`` episodes (one robot each), arrays indexed by robot.

    Attributes:
        reached, collided, timed_out: how each episode ended (exactly one is True).
        time_used: time spent, s (fractional on the arriving decision).
        time_budget: T_tot of the episode, s.
        final_distance: S_f, distance from the final position to the goal, m.
        steps: number of decisions taken.
        trajectories: ``(n, T + 1, 3)`` pose after each decision (row 0 the start), padded with
            the final pose; ``T = steps.max()``.
        experience: per robot a ``(steps_i, 2 k + 2)`` array of experience points.
        experience_rows: all of them in robot order, when ``experience`` are its consecutive
            slices (a batch run in one world); else None. :meth:`packed_experience` reads it.
    """

    reached: BoolArray
    collided: BoolArray
    timed_out: BoolArray
    time_used: FloatArray
    time_budget: FloatArray
    final_distance: FloatArray
    steps: IntArray
    trajectories: FloatArray
    experience: tuple[FloatArray, ...]
    experience_rows: FloatArray | None = field(default=None, repr=False, compare=False)

    def packed_experience(self) -> tuple[FloatArray, IntArray]:
        """All robots' experience points in one array, robot by robot, and the ``(n + 1,)``
        offsets of each robot's rows: ``experience[i] == rows[at[i]:at[i + 1]]``. No copy
        when the batch holds them so (``experience_rows``)."""
        at = np.zeros(len(self.experience) + 1, dtype=np.int64)
        at[1:] = np.cumsum([len(rows) for rows in self.experience])
        if self.experience_rows is not None:
            return self.experience_rows, at
        if not self.experience:
            return np.zeros((0, 0), dtype=np.float64), at
        return np.concatenate(self.experience, axis=0), at

    @property
    def time_remaining(self) -> FloatArray:
        """T_rem: budget left on arrival (s), clipped to ``[0, T_tot]``; 0 for a failure."""
        left = np.clip(self.time_budget - self.time_used, 0.0, self.time_budget)
        return np.where(self.reached, left, 0.0)

    def path_length(self, profile: RobotProfile) -> FloatArray:
        """``(n,)`` arc length each robot drove, m: the sum of its steps ``|ds|`` (read from
        its experience points, ``profile`` the planner's; a step back of the collision guard
        counts), the arriving one counted up to the sample that reached the goal."""
        k = profile.n_sensors
        dt = profile.control_period
        lengths = np.empty(len(self.reached), dtype=np.float64)
        for i, points in enumerate(self.experience):
            ds = np.abs(points[:, k + 1])
            if self.reached[i] and len(ds):
                ds[-1] *= (self.time_used[i] - (len(ds) - 1) * dt) / dt
            lengths[i] = float(ds.sum())
        return lengths

    @property
    def final_position(self) -> FloatArray:
        """``(n, 2)`` where each robot stood after its last decision, m."""
        return self.trajectories[np.arange(len(self.steps)), self.steps, :2]


def world_groups(scenarios: Sequence[Scenario]) -> list[IntArray]:
    """Indices of the scenarios of each distinct world, in order of first appearance;
    ValueError for none."""
    if not scenarios:
        raise ValueError("run_episodes needs at least one scenario")
    worlds = [sc.world for sc in scenarios]
    if all(w is worlds[0] for w in worlds):  # the common case: one world object
        return [np.arange(len(worlds), dtype=np.int64)]
    distinct: list[World] = []
    group_of: dict[int, int] = {}  # id of a world object -> its group (equal worlds share one)
    label = np.empty(len(worlds), dtype=np.int64)
    for i, w in enumerate(worlds):
        if id(w) not in group_of:
            same = [j for j, d in enumerate(distinct) if d == w]
            group_of[id(w)] = same[0] if same else len(distinct)
            if not same:
                distinct.append(w)
        label[i] = group_of[id(w)]
    order = np.argsort(label, kind="stable")
    bounds = np.cumsum(np.bincount(label))[:-1]
    return np.split(order, bounds)


def decision_limits(
    starts: FloatArray, goals: FloatArray, profile: RobotProfile,
    time_budgets: ArrayLike | None, max_steps: int | None,
) -> tuple[FloatArray, IntArray]:
    """Budgets T_tot ``(n,)`` (s) and decisions allowed ``ceil(T_tot / dt)``, capped."""
    if time_budgets is None:
        budget = profile.time_budgets(starts, goals)
    else:
        budget = np.broadcast_to(np.asarray(time_budgets, dtype=np.float64), starts.shape[:1])
        budget = budget.copy()
    if not (np.isfinite(budget).all() and (budget >= 0.0).all()):
        raise ValueError("time budgets must be finite and non-negative")
    allowed = np.ceil(budget / profile.control_period).astype(np.int64)
    if max_steps is not None:
        if max_steps < 0:
            raise ValueError(f"max_steps must be >= 0, got {max_steps}")
        allowed = np.minimum(allowed, max_steps)
    return budget, allowed


def group_experience(
    chunks: list[FloatArray], owners: list[IntArray], steps: IntArray, width: int
) -> tuple[FloatArray, tuple[FloatArray, ...]]:
    """Split the per-decision experience rows into one array per robot, in decision order:
    one array of all robots' rows, robot by robot, and its slices.

    Chunk ``t`` holds decision ``t`` of the robots ``owners[t]``: a robot decides once in
    every period from the first until it stops, so robot ``i``'s decision ``t`` is row
    ``start[i] + t`` of one array with ``steps[i]`` rows per robot, filled without a sort.
    """
    ends = np.cumsum(steps)
    starts = ends - steps
    rows = np.empty((int(ends[-1]) if ends.size else 0, width), dtype=np.float64)
    for t, (chunk, idx) in enumerate(zip(chunks, owners, strict=True)):
        if _scatter_rows_numba is None:  # pragma: no cover - numba is in the lock file
            rows[starts[idx] + t] = chunk
        else:  # numpy's row scatter is several times slower than the loop
            _scatter_rows_numba(rows, np.ascontiguousarray(chunk), starts[idx] + t)
    return rows, tuple(rows[lo:hi] for lo, hi in zip(starts.tolist(), ends.tolist(), strict=True))


def _scatter_rows(rows: FloatArray, chunk: FloatArray, dest: IntArray) -> None:
    """``rows[dest] = chunk`` row by row (compiled by numba)."""
    for i in range(dest.shape[0]):
        rows[dest[i], :] = chunk[i, :]


_scatter_rows_numba: Callable[..., None] | None
try:
    from numba import njit

    _scatter_rows_numba = njit(cache=True)(_scatter_rows)
except ImportError:  # pragma: no cover - numba is in the lock file; numpy stays the fallback
    _scatter_rows_numba = None


def merge_batches(
    parts: Sequence[EpisodeBatch], groups: Sequence[IntArray], n: int
) -> EpisodeBatch:
    """One batch of ``n`` robots from per-world batches of the robots ``groups[j]``."""
    fields: dict[str, Any] = {}
    for name in ("reached", "collided", "timed_out", "time_used", "time_budget",
                 "final_distance", "steps"):  # fmt: skip
        out = np.empty(n, dtype=getattr(parts[0], name).dtype)
        for part, idx in zip(parts, groups, strict=True):
            out[idx] = getattr(part, name)
        fields[name] = out
    length = max(part.trajectories.shape[1] for part in parts)
    trajectories = np.empty((n, length, 3), dtype=np.float64)
    experience: list[FloatArray] = [np.empty(0)] * n
    for part, idx in zip(parts, groups, strict=True):
        t = part.trajectories
        trajectories[idx, : t.shape[1]] = t
        trajectories[idx, t.shape[1] :] = t[:, -1:]  # padded with the final pose
        for i, rows in zip(idx.tolist(), part.experience, strict=True):
            experience[i] = rows
    return EpisodeBatch(**fields, trajectories=trajectories, experience=tuple(experience))
