"""Performance objective of the paper (section "Criteria Functions", eqs. 3 and 4).

Per scenario i (eq. 4)::

    F_i = delta_i (1 + T_rem,i / T_tot,i) + (1 - delta_i) / (1 + S_f,i)

with delta_i = 1 when the robot reached its goal, T_rem,i the time left on arrival, T_tot,i
the scenario's time budget and S_f,i the final distance to the goal (m). A success scores in
``[1, 2]``, a failure in ``(0, 1]``, so any success beats any failure that ends away from the
goal. Per genome (eq. 3): ``F = sum_i F_i`` over its scenarios.

Not in the paper: the success's credit ``T_rem,i / T_tot,i`` may be replaced by the path's
efficiency ``l_i / max(p_i, l_i)`` (:func:`path_credit`; ``l_i`` the shortest path's length,
``p_i`` the length driven), the per-episode term of SPL (Anderson et al. 2018), so that a
detour costs what it costs in the benchmark's score (``success_credit: path`` of the trainer
config). Both credits lie in ``[0, 1]``, so a success still scores in ``[1, 2]``.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

if TYPE_CHECKING:
    from mentor_core.sim.episode import EpisodeBatch

FloatArray = NDArray[np.float64]


def scenario_performance(
    reached: ArrayLike, time_remaining: ArrayLike, time_budget: ArrayLike,
    final_distance: ArrayLike,
) -> FloatArray:
    """F_i of paper eq. 4 for each scenario ``(n,)``.

    Args:
        reached: delta_i, bool ``(n,)``.
        time_remaining: T_rem,i (s); clipped to ``[0, T_tot,i]`` (ignored for failures).
        time_budget: T_tot,i (s, >= 0); a zero budget counts as no time left.
        final_distance: S_f,i (m, >= 0).
    """
    delta = np.asarray(reached, dtype=np.bool_)
    t_tot = np.asarray(time_budget, dtype=np.float64)
    t_rem = np.clip(np.asarray(time_remaining, dtype=np.float64), 0.0, t_tot)
    s_f = np.asarray(final_distance, dtype=np.float64)
    if (t_tot < 0.0).any() or (s_f < 0.0).any() or np.isnan(s_f).any():
        raise ValueError("time budgets and final distances must be non-negative")
    share = np.divide(t_rem, t_tot, out=np.zeros_like(t_rem), where=t_tot > 0.0)
    return credited_performance(delta, share, s_f)


def credited_performance(
    reached: ArrayLike, credit: ArrayLike, final_distance: ArrayLike
) -> FloatArray:
    """F_i of paper eq. 4 with the success's credit given: ``delta_i (1 + c_i) + (1 -
    delta_i) / (1 + S_f,i)``, ``c_i`` in ``[0, 1]`` (the paper's ``T_rem,i / T_tot,i``, or
    :func:`path_credit`); S_f,i (m) as in :func:`scenario_performance`."""
    delta = np.asarray(reached, dtype=np.bool_)
    s_f = np.asarray(final_distance, dtype=np.float64)
    if (s_f < 0.0).any() or np.isnan(s_f).any():
        raise ValueError("final distances must be non-negative")
    score: FloatArray = np.where(delta, 1.0 + np.asarray(credit, dtype=np.float64),
                                 1.0 / (1.0 + s_f))  # fmt: skip
    return score


def path_credit(shortest: ArrayLike, taken: ArrayLike) -> FloatArray:
    """``l_i / max(p_i, l_i)`` per episode (module docstring): the shortest path's length
    over the length driven, m / m; 1 when both are 0."""
    l_ = np.asarray(shortest, dtype=np.float64)
    p = np.asarray(taken, dtype=np.float64)
    denom = np.maximum(p, l_)
    ratio: FloatArray = np.divide(l_, denom, out=np.ones_like(l_), where=denom > 0.0)
    return ratio


def performance(batch: EpisodeBatch, n_genomes: int) -> FloatArray:
    """F of paper eq. 3 per genome ``(n_genomes,)``.

    The batch holds ``n_genomes * n_scenarios`` episodes, genome-major: robot
    ``g * n_scenarios + s`` is genome ``g`` on scenario ``s``.
    """
    n = batch.reached.shape[0]
    if n_genomes <= 0 or n % n_genomes:
        raise ValueError(f"{n} episodes do not split evenly over {n_genomes} genomes")
    per_scenario = scenario_performance(
        batch.reached, batch.time_remaining, batch.time_budget, batch.final_distance
    )
    total: FloatArray = per_scenario.reshape(n_genomes, -1).sum(axis=1)
    return total
