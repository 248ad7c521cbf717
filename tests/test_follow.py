"""Following a global path by a lookahead point."""

from __future__ import annotations

import numpy as np
import pytest

from mentor_core.navigation.follow import (
    cumulative_length,
    lookahead_point,
    point_at,
    progress,
)

L_PATH = [(0.0, 0.0), (4.0, 0.0), (4.0, 3.0)]


def test_cumulative_length_sums_segment_lengths() -> None:
    np.testing.assert_allclose(cumulative_length(L_PATH), [0.0, 4.0, 7.0])


def test_progress_is_the_arc_length_of_the_nearest_point() -> None:
    assert progress(L_PATH, (1.5, 0.7)) == pytest.approx(1.5)
    assert progress(L_PATH, (5.0, 2.0)) == pytest.approx(6.0)
    assert progress(L_PATH, (-3.0, -1.0)) == 0.0


def test_carrot_lies_lookahead_ahead_and_stops_at_the_end() -> None:
    carrot, s = lookahead_point(L_PATH, (1.0, 0.2), 1.0)
    assert s == pytest.approx(1.0) and carrot == pytest.approx((2.0, 0.0))
    carrot, _ = lookahead_point(L_PATH, (3.5, 0.0), 1.0)  # round the corner
    assert carrot == pytest.approx((4.0, 0.5))
    assert lookahead_point(L_PATH, (4.0, 2.9), 2.0)[0] == pytest.approx((4.0, 3.0))
    assert point_at(L_PATH, 99.0) == pytest.approx((4.0, 3.0))


def test_progress_never_goes_back_past_from_s() -> None:
    # a U: the end comes back near the start; from the start the U's far leg must not win
    u = [(0.0, 0.0), (5.0, 0.0), (5.0, 1.0), (0.0, 1.0)]
    assert progress(u, (0.5, 0.6)) == pytest.approx(10.5)  # nearest overall: the return leg
    assert progress(u, (0.5, 0.6), from_s=0.0) == pytest.approx(10.5)
    assert progress(u, (1.0, 0.4), from_s=0.0) == pytest.approx(1.0)
    assert progress(u, (1.0, 0.4), from_s=6.0) == pytest.approx(10.0)


def test_bad_paths_and_lookaheads_are_refused() -> None:
    with pytest.raises(ValueError, match="shape"):
        progress([[1.0, 2.0, 3.0]], (0.0, 0.0))
    with pytest.raises(ValueError, match="finite"):
        progress([(0.0, 0.0), (np.nan, 1.0)], (0.0, 0.0))
    with pytest.raises(ValueError, match="lookahead"):
        lookahead_point(L_PATH, (0.0, 0.0), 0.0)
