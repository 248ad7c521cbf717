"""Tests of mentor_core.evolution.selection: niche sizes (paper eq. 2), tournament,
rank-proportionate."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.stats import chisquare

from mentor_core.evolution.selection import niche_sizes, rank_proportionate, tournament


@settings(max_examples=80, deadline=None)
@given(
    st.lists(
        st.tuples(st.floats(1e-3, 1e3, allow_nan=False), st.integers(0, 6)),
        min_size=1,
        max_size=40,
    ),
    st.integers(0, 150),
)
def test_sizes_sum_to_total(members: list[tuple[float, int]], total: int) -> None:
    fitness = np.array([f for f, _ in members])
    labels = np.array([label for _, label in members])
    sizes = niche_sizes(fitness, labels, total)
    assert list(sizes) == sorted(set(labels.tolist()))
    assert sum(sizes.values()) == total
    assert all(size >= 0 for size in sizes.values())
    # rounding moves each niche by less than one place from its real-valued eq. 2 size
    means = {k: fitness[labels == k].mean() for k in sizes}
    grand = sum(means.values())
    for key, size in sizes.items():
        assert abs(size - total * means[key] / grand) < 1.0 + 1e-9


def test_equation_two_by_hand() -> None:
    fitness = np.array([1.0, 3.0, 2.0, 2.0, 2.0, 6.0])
    labels = np.array([4, 4, 7, 7, 7, 9])
    # niche means 2, 2, 6 -> shares 0.2, 0.2, 0.6 of n = 6 -> 1.2, 1.2, 3.6
    assert niche_sizes(fitness, labels, 6) == {4: 1, 7: 1, 9: 4}
    assert niche_sizes(fitness, labels, 10) == {4: 2, 7: 2, 9: 6}


def test_equal_fitness_shares_equally_whatever_the_niche_size() -> None:
    labels = np.array([0] * 70 + [1] * 20 + [2] * 10)
    sizes = niche_sizes(np.full(100, 1.7), labels, 99)
    assert sizes == {0: 33, 1: 33, 2: 33}
    # the big niche shrinks, the small ones grow; remainder ties go to the lower label
    assert niche_sizes(np.full(100, 0.1), labels, 100) == {0: 34, 1: 33, 2: 33}


def test_fitter_niche_grows() -> None:
    labels = np.array([0] * 50 + [1] * 50)
    fitness = np.concatenate([np.full(50, 1.0), np.full(50, 3.0)])
    sizes = niche_sizes(fitness, labels, 100)
    assert sizes == {0: 25, 1: 75}


def test_niche_sizes_bad_input() -> None:
    with pytest.raises(ValueError):
        niche_sizes([1.0, 0.0], [0, 1], 2)
    with pytest.raises(ValueError):
        niche_sizes([1.0, -1.0], [0, 1], 2)
    with pytest.raises(ValueError):
        niche_sizes([1.0, np.nan], [0, 1], 2)
    with pytest.raises(ValueError):
        niche_sizes([1.0, 2.0], [0], 2)
    with pytest.raises(ValueError):
        niche_sizes([1.0, 2.0], [0.0, 1.0], 2)
    with pytest.raises(ValueError):
        niche_sizes([1.0, 2.0], [0, 1], -1)
    with pytest.raises(ValueError):
        niche_sizes([], [], 0)


def test_tournament_is_deterministic_with_a_seed() -> None:
    fitness = np.random.default_rng(0).random(30)
    first = [tournament(fitness, np.random.default_rng(42), 3) for _ in range(5)]
    rng = np.random.default_rng(42)
    again = [tournament(fitness, rng, 3) for _ in range(5)]
    assert first == [first[0]] * 5
    rng = np.random.default_rng(42)
    assert again == [tournament(fitness, rng, 3) for _ in range(5)]


def test_tournament_large_size_finds_the_best_and_ties_go_low() -> None:
    fitness = np.array([0.1, 0.9, 0.3, 0.9, 0.2])
    rng = np.random.default_rng(1)
    # 200 draws from 5 genomes cover every index with overwhelming probability
    assert [tournament(fitness, rng, size=200) for _ in range(20)] == [1] * 20


def test_tournament_prefers_fitter_genomes() -> None:
    fitness = np.arange(10, dtype=float)
    rng = np.random.default_rng(3)
    picks = np.array([tournament(fitness, rng) for _ in range(4000)])
    # P(best of two = k) = (2k + 1) / 100: the mean is 6.15
    assert abs(picks.mean() - 6.15) < 0.15
    assert tournament(fitness, rng, size=1) in range(10)
    with pytest.raises(ValueError):
        tournament(fitness, rng, size=0)


def test_rank_proportionate_frequencies() -> None:
    fitness = np.array([0.5, 3.0, 1.0, 3.0, -2.0])
    rng = np.random.default_rng(7)
    draws = rank_proportionate(fitness, rng, 50_000)
    counts = np.bincount(draws, minlength=5)
    # order best first (stable): 1, 3, 2, 0, 4 -> weights 5, 4, 3, 2, 1
    expected_weight = np.zeros(5)
    expected_weight[[1, 3, 2, 0, 4]] = [5, 4, 3, 2, 1]
    expected = 50_000 * expected_weight / 15
    assert chisquare(counts, expected).pvalue > 1e-3
    np.testing.assert_allclose(counts / 50_000, expected_weight / 15, atol=0.01)


def test_rank_proportionate_is_deterministic_and_shaped() -> None:
    fitness = np.random.default_rng(0).random(8)
    a = rank_proportionate(fitness, np.random.default_rng(9), 12)
    b = rank_proportionate(fitness, np.random.default_rng(9), 12)
    np.testing.assert_array_equal(a, b)
    assert a.shape == (12,) and a.dtype == np.int64
    assert rank_proportionate(fitness, np.random.default_rng(9), 0).shape == (0,)
    with pytest.raises(ValueError):
        rank_proportionate(fitness, np.random.default_rng(9), -1)
    with pytest.raises(ValueError):
        rank_proportionate([], np.random.default_rng(9), 1)
