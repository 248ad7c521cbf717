"""Tests of mentor_core.evolution.ranking against pymoo 0.6.2 (fast non-dominated sort, "cd"
crowding)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays
from pymoo.operators.survival.rank_and_crowding.metrics import get_crowding_function
from pymoo.util.nds.fast_non_dominated_sort import fast_non_dominated_sort

from mentor_core.evolution.ranking import crowding_distance, non_dominated_ranks, scalar_fitness


def pymoo_ranks(objectives: np.ndarray) -> np.ndarray:
    """Fronts of pymoo's fast non-dominated sort on the negated (max -> min) objectives."""
    fronts = fast_non_dominated_sort(-np.asarray(objectives, dtype=float))
    ranks = np.full(len(objectives), -1, dtype=np.int64)
    for rank, front in enumerate(fronts):
        ranks[np.asarray(front, dtype=int)] = rank
    return ranks


def pymoo_crowding(front_costs: np.ndarray) -> np.ndarray:
    """Crowding of pymoo's NSGA-II survival ("cd": no duplicate filter, <= 2 points inf), on
    costs (pymoo minimises)."""
    result: np.ndarray = get_crowding_function("cd").do(front_costs)
    return result


def pymoo_scalar_fitness(objectives: np.ndarray) -> np.ndarray:
    ranks = pymoo_ranks(objectives)
    n_fronts = ranks.max() + 1
    fitness = np.empty(len(objectives))
    for rank in range(n_fronts):
        members = np.flatnonzero(ranks == rank)
        crowd = pymoo_crowding(-objectives[members])
        bonus = np.full(len(crowd), 0.5)
        finite = np.isfinite(crowd)
        bonus[finite] = 0.5 * crowd[finite] / (1.0 + crowd[finite])
        fitness[members] = n_fronts - rank + bonus
    return fitness


def assert_matches_pymoo(objectives: np.ndarray) -> None:
    ranks = non_dominated_ranks(objectives)
    np.testing.assert_array_equal(ranks, pymoo_ranks(objectives))
    for rank in np.unique(ranks):
        front = objectives[ranks == rank]
        np.testing.assert_array_equal(crowding_distance(front), pymoo_crowding(-front))
        np.testing.assert_array_equal(
            crowding_distance(-front, maximize=False), pymoo_crowding(-front)
        )
    np.testing.assert_array_equal(scalar_fitness(objectives), pymoo_scalar_fitness(objectives))


@pytest.mark.parametrize("m", [1, 2, 3])
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_random_float_data_matches_pymoo(m: int, seed: int) -> None:
    rng = np.random.default_rng(seed)
    assert_matches_pymoo(rng.normal(size=(60, m)))


@pytest.mark.parametrize("m", [1, 2, 3])
def test_integer_data_with_ties_and_duplicates_matches_pymoo(m: int) -> None:
    rng = np.random.default_rng(10 + m)
    objectives = rng.integers(0, 4, size=(80, m)).astype(float)
    objectives[40:50] = objectives[0]  # many exact duplicates of one point
    assert_matches_pymoo(objectives)


@settings(max_examples=60, deadline=None)
@given(
    arrays(
        np.float64,
        st.tuples(st.integers(0, 25), st.integers(1, 3)),
        elements=st.one_of(
            st.integers(-3, 3).map(float),
            st.floats(-1e3, 1e3, allow_nan=False, allow_infinity=False),
        ),
    )
)
def test_hypothesis_matrices_match_pymoo(objectives: np.ndarray) -> None:
    if len(objectives) == 0:
        assert non_dominated_ranks(objectives).shape == (0,)
        assert scalar_fitness(objectives).shape == (0,)
        return
    assert_matches_pymoo(objectives)


def test_known_fronts_max_max() -> None:
    objectives = np.array([[3.0, 1.0], [1.0, 3.0], [2.0, 2.0], [1.0, 1.0], [0.0, 0.0], [2.0, 2.0]])
    np.testing.assert_array_equal(non_dominated_ranks(objectives), [0, 0, 0, 1, 2, 0])
    np.testing.assert_array_equal(
        non_dominated_ranks(objectives, maximize=False), [2, 2, 2, 1, 0, 2]
    )
    np.testing.assert_array_equal(non_dominated_ranks(objectives[:, 0]), [0, 2, 1, 2, 3, 1])


def test_empty_and_single() -> None:
    assert non_dominated_ranks(np.empty((0, 2))).dtype == np.int64
    np.testing.assert_array_equal(non_dominated_ranks([[1.0, 2.0]]), [0])
    np.testing.assert_array_equal(crowding_distance(np.empty((0, 2))), [])
    np.testing.assert_array_equal(scalar_fitness([[1.0, 2.0]]), [1.5])


def test_fronts_of_one_and_two_points_are_infinite() -> None:
    np.testing.assert_array_equal(crowding_distance([[1.0, 2.0]]), [np.inf])
    np.testing.assert_array_equal(crowding_distance([[1.0, 2.0], [2.0, 1.0]]), [np.inf] * 2)


def test_crowding_known_values_and_zero_range() -> None:
    front = np.array([[0.0, 5.0], [1.0, 5.0], [4.0, 5.0]])
    # objective 1 has zero range: contributes 0, even to its boundary points
    np.testing.assert_array_equal(crowding_distance(front), [np.inf, 0.5, np.inf])
    np.testing.assert_array_equal(crowding_distance(np.ones((4, 2))), np.zeros(4))


def test_crowding_ties_follow_pymoo() -> None:
    # pymoo sorts the costs (stable): of equal best values the first is the boundary point,
    # of equal worst values the last
    np.testing.assert_array_equal(crowding_distance([[1.0], [1.0], [0.0]]), [np.inf, 1.0, np.inf])
    np.testing.assert_array_equal(crowding_distance([[1.0], [0.0], [0.0]]), [np.inf, 1.0, np.inf])
    np.testing.assert_array_equal(crowding_distance([[0.0], [0.0], [1.0]]), [1.0, np.inf, np.inf])
    # as costs (minimised) the same rule, the other way round
    costs = np.array([[0.0], [0.0], [1.0]])
    np.testing.assert_array_equal(crowding_distance(costs, maximize=False), [np.inf, 1.0, np.inf])
    np.testing.assert_array_equal(crowding_distance(-costs), crowding_distance(costs, False))


def test_crowding_of_random_integer_fronts_matches_pymoo() -> None:
    """400 random integer fronts full of ties: every distance equals pymoo's on the negated
    objectives (the promise of docs/architecture.md), in the max frame and as costs."""
    rng = np.random.default_rng(2024)
    tie_order_matters = 0
    for _ in range(400):
        n, m, top = int(rng.integers(3, 30)), int(rng.integers(1, 4)), int(rng.integers(1, 5))
        front = rng.integers(0, top + 1, size=(n, m)).astype(float)
        ours, as_costs = crowding_distance(front), crowding_distance(front, maximize=False)
        np.testing.assert_array_equal(ours, pymoo_crowding(-front))
        np.testing.assert_array_equal(as_costs, pymoo_crowding(front))
        # the same matrix read as costs sorts its ties the other way
        tie_order_matters += not np.array_equal(ours, as_costs)
    # most fronts have duplicates whose order decides which one is the boundary point
    assert tie_order_matters > 300


def test_scalar_fitness_orders_rank_before_crowding() -> None:
    rng = np.random.default_rng(5)
    objectives = rng.normal(size=(200, 2))
    fitness = scalar_fitness(objectives)
    ranks = non_dominated_ranks(objectives)
    assert np.all(fitness >= 1.0)
    for rank in range(ranks.max()):
        assert fitness[ranks == rank].min() > fitness[ranks == rank + 1].max()
    n_fronts = ranks.max() + 1
    np.testing.assert_array_less(fitness - (n_fronts - ranks), 0.5 + 1e-15)


def test_single_objective_fitness_follows_value() -> None:
    values = np.array([0.3, 2.0, -1.0, 2.0, 0.5])
    fitness = scalar_fitness(values)
    np.testing.assert_array_equal(np.argsort(-fitness, kind="stable"), [1, 3, 4, 0, 2])
    assert fitness[1] == fitness[3]


@pytest.mark.parametrize("bad", [[[np.nan, 1.0]], np.zeros((2, 0)), np.zeros((2, 2, 2))])
def test_bad_input_raises(bad: object) -> None:
    for function in (non_dominated_ranks, crowding_distance, scalar_fitness):
        with pytest.raises(ValueError):
            function(bad)  # type: ignore[operator]
