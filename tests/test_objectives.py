"""Paper eqs. 3-4: hand-computed values, clipping, and success always beating failure."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from mentor_core.objectives.performance import performance, scenario_performance
from mentor_core.sim.episode import EpisodeBatch


def test_hand_computed_values() -> None:
    f = scenario_performance(
        reached=[True, True, False, False, True],
        time_remaining=[5.0, 0.0, 3.0, 0.0, 12.0],
        time_budget=[10.0, 8.0, 10.0, 10.0, 10.0],
        final_distance=[0.5, 0.9, 1.0, 3.0, 0.2],
    )
    # 1 + 5/10; 1 + 0; 1/(1+1); 1/(1+3); remaining clipped to the budget: 1 + 1
    np.testing.assert_allclose(f, [1.5, 1.0, 0.5, 0.25, 2.0])


def test_zero_budget_and_bad_values() -> None:
    assert scenario_performance([True], [0.0], [0.0], [0.0])[0] == 1.0
    with pytest.raises(ValueError):
        scenario_performance([False], [0.0], [1.0], [-1.0])


@settings(derandomize=True, max_examples=300, deadline=None)
@given(
    st.floats(0.0, 60.0), st.floats(0.01, 60.0), st.floats(1e-6, 100.0), st.floats(0.0, 60.0)
)
def test_any_success_beats_any_failure(
    t_rem: float, t_tot: float, s_fail: float, s_win: float
) -> None:
    win, lose = scenario_performance([True, False], [t_rem, 60.0], [t_tot, t_tot],
                                     [s_win, s_fail])
    assert 1.0 <= win <= 2.0 and 0.0 < lose < 1.0 and win > lose


def _batch(reached: list[bool], used: list[float], budget: list[float],
           dist: list[float]) -> EpisodeBatch:
    n = len(reached)
    r = np.array(reached)
    return EpisodeBatch(
        reached=r, collided=~r, timed_out=np.zeros(n, dtype=bool),
        time_used=np.array(used), time_budget=np.array(budget),
        final_distance=np.array(dist), steps=np.ones(n, dtype=np.int64),
        trajectories=np.zeros((n, 2, 3)), experience=tuple(np.zeros((1, 4)) for _ in range(n)),
    )


def test_performance_sums_each_genomes_scenarios() -> None:
    batch = _batch([True, False, False, True], [2.0, 5.0, 5.0, 12.0],
                   [8.0, 10.0, 10.0, 10.0], [0.5, 1.0, 3.0, 0.9])
    # genome 0: (1 + 6/8) + 1/2; genome 1: 1/4 + (1 + 0): over-budget arrival keeps 1
    np.testing.assert_allclose(performance(batch, 2), [2.25, 1.25])
    np.testing.assert_allclose(performance(batch, 1), [3.5])
    with pytest.raises(ValueError):
        performance(batch, 3)
