"""The paired bootstrap interval (report/bootstrap.py) of head to head's margins."""

from __future__ import annotations

import numpy as np
import pytest

from mentor_core.report.bootstrap import paired_interval


def test_no_difference_and_a_constant_difference_have_no_spread() -> None:
    assert paired_interval([np.zeros(40), np.zeros(40)]) == (0.0, 0.0)
    assert paired_interval([np.ones(10)]) == (1.0, 1.0)


def test_the_interval_matches_the_normal_approximation_of_a_large_sample() -> None:
    rng = np.random.default_rng(7)
    d = rng.choice([-1.0, 0.0, 1.0], p=[0.1, 0.75, 0.15], size=2000)
    lo, hi = paired_interval([d])
    half = 1.96 * d.std(ddof=1) / np.sqrt(d.size)
    assert lo < d.mean() < hi
    assert (hi - lo) / 2 == pytest.approx(half, rel=0.1)


def test_strata_are_resampled_within_themselves() -> None:
    # one stratum always +1, one always -1: every resample keeps 10 of each, mean 0 exactly
    assert paired_interval([np.ones(10), -np.ones(10)]) == (0.0, 0.0)
    # pooled they would mix, and the mean would spread
    lo, hi = paired_interval([np.concatenate([np.ones(10), -np.ones(10)])])
    assert lo < 0.0 < hi


def test_same_seed_same_interval_and_bad_arguments() -> None:
    d = [np.array([1.0, 0.0, 0.0, -1.0, 1.0])]
    assert paired_interval(d, seed=3) == paired_interval(d, seed=3)
    with pytest.raises(ValueError, match="level"):
        paired_interval(d, level=1.0)
    with pytest.raises(ValueError, match="resamples"):
        paired_interval(d, resamples=0)
    with pytest.raises(ValueError, match="at least one pair"):
        paired_interval([np.zeros(0)])
