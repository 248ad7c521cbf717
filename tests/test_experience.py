"""Tests of mentor_core.objectives.experience against scipy's dense minimum spanning tree."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays
from scipy.sparse import coo_array
from scipy.sparse.csgraph import minimum_spanning_tree
from scipy.spatial.distance import pdist

from mentor_core.objectives.emst_prim import bounded_prim_length, prim_length
from mentor_core.objectives.experience import (
    METHODS,
    experience_gain,
    experience_gains,
    experience_gains_packed,
)

SENSOR_RANGE = 4.0


def scipy_mst_length(points: np.ndarray) -> float:
    """Reference: scipy's MST of the complete graph on the unique rows.

    Duplicates go first: zero distances would be missing edges. The graph is passed as sparse
    with every pair explicit, because scipy masks dense entries within 1e-8 of zero (tiny but
    real distances would be dropped too).
    """
    unique = np.unique(np.asarray(points, dtype=float) + 0.0, axis=0)
    if len(unique) < 2:
        return 0.0
    rows, cols = np.triu_indices(len(unique), k=1)
    graph = coo_array((pdist(unique), (rows, cols)), shape=(len(unique),) * 2)
    return float(minimum_spanning_tree(graph.tocsr()).sum())


def sensor_like(rng: np.random.Generator, n: int, n_sensors: int) -> np.ndarray:
    """[U(t), A(t), U(t+1)] with most readings at the clip value and repeated decisions."""
    readings = np.clip(rng.uniform(-2.0, 10.0, size=(n + 1, n_sensors)), 0.0, SENSOR_RANGE)
    actions = np.column_stack([rng.integers(-2, 3, n) * 0.5, rng.integers(1, 4, n) * 0.5])
    points = np.hstack([readings[:-1], actions, readings[1:]])
    points[n // 2 : n // 2 + 20] = points[:1]  # a robot stuck in one place repeats itself
    return points


def assert_all_methods_match(points: np.ndarray) -> None:
    expected = scipy_mst_length(points)
    for method in METHODS:
        assert experience_gain(points, method) == pytest.approx(expected, rel=1e-9, abs=1e-12)


@pytest.mark.parametrize(("n", "d"), [(2, 1), (3, 2), (40, 2), (300, 8), (600, 18)])
def test_random_points_match_scipy(n: int, d: int) -> None:
    assert_all_methods_match(np.random.default_rng(n + d).normal(size=(n, d)))


@pytest.mark.parametrize("n_sensors", [3, 8])
def test_clipped_sensor_points_match_scipy(n_sensors: int) -> None:
    assert_all_methods_match(sensor_like(np.random.default_rng(n_sensors), 500, n_sensors))


def test_integer_grid_with_ties_and_duplicates() -> None:
    grid = np.stack(np.meshgrid(*[np.arange(3.0)] * 4), axis=-1).reshape(-1, 4)
    rng = np.random.default_rng(4)
    points = np.vstack([grid, grid[rng.integers(0, 81, 300)]])
    rng.shuffle(points)
    # 81 distinct grid cells, all neighbours 1 apart: the MST has 80 unit edges
    assert_all_methods_match(points)
    for method in METHODS:
        assert experience_gain(points, method) == pytest.approx(80.0, rel=0, abs=1e-12)


@settings(max_examples=40, deadline=None)
@given(
    arrays(
        np.float64,
        st.tuples(st.integers(0, 40), st.integers(1, 5)),
        elements=st.one_of(st.integers(-2, 2).map(float), st.floats(-10, 10, width=32)),
    )
)
def test_hypothesis_points_match_scipy(points: np.ndarray) -> None:
    assert_all_methods_match(points)


def test_small_cases() -> None:
    for method in METHODS:
        assert experience_gain(np.empty((0, 18)), method) == 0.0
        assert experience_gain(np.ones((1, 18)), method) == 0.0
        assert experience_gain(np.ones((5, 3)), method) == 0.0  # one distinct point
        assert experience_gain([[0.0, 0.0], [3.0, 4.0]], method) == 5.0
        assert experience_gain([[0.0, -0.0], [0.0, 0.0], [1.0, 0.0]], method) == 1.0


def test_duplicates_do_not_change_the_gain() -> None:
    points = np.random.default_rng(1).random((200, 6))
    doubled = np.vstack([points, points[::3]])
    np.random.default_rng(2).shuffle(doubled)
    for method in METHODS:
        assert experience_gain(doubled, method) == pytest.approx(
            experience_gain(points, method), rel=1e-12
        )


def test_gain_grows_with_spread() -> None:
    points = np.random.default_rng(3).random((100, 5))
    assert experience_gain(2.0 * points) == pytest.approx(2.0 * experience_gain(points))


def test_batch_equals_single_calls() -> None:
    rng = np.random.default_rng(6)
    sets = [sensor_like(rng, n, 8) for n in (0, 1, 50, 300, 120)]
    for method in METHODS:
        single = np.array([experience_gain(points, method) for points in sets])
        np.testing.assert_array_equal(experience_gains(sets, method), single)
    mixed = [rng.random((30, 2)), rng.random((20, 5))]  # different dimensions
    np.testing.assert_array_equal(
        experience_gains(mixed), [experience_gain(points) for points in mixed]
    )
    assert experience_gains([]).shape == (0,)


def test_packed_slices_equal_the_sets() -> None:
    # the trainer's layout: every genome's points in a row of one array, read in place
    rng = np.random.default_rng(7)
    sets = [sensor_like(rng, n, 8) for n in (0, 1, 50, 300, 120)]
    sets[2][::3, 0] = -0.0  # a signed zero is the same coordinate
    rows = np.concatenate(sets)
    at = np.cumsum([0] + [len(points) for points in sets])
    for method in METHODS:
        np.testing.assert_array_equal(experience_gains_packed(rows, at, method),
                                      experience_gains(sets, method))  # fmt: skip
    # the rows outside the slices are not read
    spare = np.concatenate([np.full((3, 18), np.nan), rows, np.full((2, 18), np.nan)])
    np.testing.assert_array_equal(experience_gains_packed(spare, at + 3), experience_gains(sets))
    np.testing.assert_array_equal(experience_gains_packed(spare, at[2:4] + 3),
                                  experience_gains(sets[2:3]))  # fmt: skip
    for bad in ([-1, 5], [0, 9, 5], [0, len(rows) + 1], []):
        with pytest.raises(ValueError, match="offsets"):
            experience_gains_packed(rows, bad)
    with pytest.raises(ValueError, match="finite"):
        experience_gains_packed(spare, [0, len(spare)])


@pytest.mark.parametrize(
    "bad", [np.array([[0.0, np.nan]]), np.array([[np.inf, 0.0]]), np.zeros(5), np.zeros((2, 2, 2))]
)
def test_bad_points_raise(bad: np.ndarray) -> None:
    with pytest.raises(ValueError):
        experience_gain(bad)
    with pytest.raises(ValueError):
        experience_gains([np.zeros((3, 2)), bad])


def trajectories(rng: np.random.Generator, n_scenarios: int, steps: int, d: int) -> np.ndarray:
    """Experience-like points: smooth clipped walks; stuck robots repeat (or nearly) a point."""
    walks = np.cumsum(rng.normal(0.0, 0.3, size=(n_scenarios, steps, d)), axis=1)
    points = np.clip(walks + rng.uniform(-2.0, 6.0, size=(n_scenarios, 1, d)), 0.0, SENSOR_RANGE)
    points[::3, steps // 2 :] = points[::3, steps // 2 : steps // 2 + 1]  # stuck: exact repeats
    jitter = rng.normal(0.0, 1e-9, size=points[1::3, steps // 2 :].shape)
    points[1::3, steps // 2 :] = points[1::3, steps // 2 : steps // 2 + 1] + jitter  # near-repeats
    return points.reshape(-1, d)


BOUNDED_CASES = {
    "trajectories_18d": lambda rng: trajectories(rng, 12, 50, 18),
    "trajectories_8d": lambda rng: trajectories(rng, 20, 30, 8),
    "clipped_sensors": lambda rng: sensor_like(rng, 700, 8),
    "grid_ties": lambda rng: np.stack(np.meshgrid(*[np.arange(5.0)] * 3), -1).reshape(-1, 3)[
        rng.permutation(125)
    ],
    "one_dimension": lambda rng: rng.normal(size=(300, 1)),
    "far_from_origin": lambda rng: rng.normal(size=(300, 6)) + 1e6,
    "tiny_scale": lambda rng: rng.normal(size=(300, 5)) * 1e-30,
    "beyond_float32": lambda rng: rng.normal(size=(300, 5)) * 1e20,
    "just_above_small": lambda rng: rng.random((65, 4)),
}


@pytest.mark.parametrize("case", sorted(BOUNDED_CASES))
def test_bounded_prim_equals_plain_prim_bit_for_bit(case: str) -> None:
    # the bounded kernel adds the same edges in the same order: the very same float
    points = np.ascontiguousarray(BOUNDED_CASES[case](np.random.default_rng(7)), dtype=np.float64)
    assert bounded_prim_length(points) == prim_length(points)
    assert experience_gain(points, "bounded") == pytest.approx(
        scipy_mst_length(points), rel=1e-9, abs=1e-300
    )


@settings(max_examples=25, deadline=None)
@given(
    st.integers(64, 160),
    st.integers(1, 7),
    st.integers(0, 2**32 - 1),
    st.sampled_from([0.0, 1e-12, 0.5]),
)
def test_bounded_prim_equals_plain_prim_on_clusters(
    n: int, d: int, seed: int, spread: float
) -> None:
    # few centres, each repeated with a small (or no) jitter: ties and near-ties everywhere
    rng = np.random.default_rng(seed)
    centres = rng.integers(-3, 4, size=(max(2, n // 8), d)).astype(np.float64)
    points = centres[rng.integers(0, len(centres), n)] + spread * rng.normal(size=(n, d))
    assert bounded_prim_length(points) == prim_length(points)


def test_unknown_method_raises() -> None:
    with pytest.raises(ValueError):
        experience_gain(np.zeros((3, 2)), "kruskal")  # type: ignore[arg-type]
