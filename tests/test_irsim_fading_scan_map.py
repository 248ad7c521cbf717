"""The scan map that forgets what moved (mentor_core.navigation.fading_scan_map, issue 59,
E098): a hit in space seen free expires, a wall first read as a hit does not."""

from __future__ import annotations

import numpy as np
import pytest

from mentor_core.navigation.fading_scan_map import FadingScanMap


def test_what_appeared_in_free_space_fades_and_a_wall_stays() -> None:
    m = FadingScanMap(4.0, 0.1, memory=2)
    along = np.array([[0.05, 0.55, 0.0]])  # a ray along y = 0.55 m
    wall = np.array([[0.05, 1.55, 0.0]])  # one along y = 1.55 m
    m.update(along, [np.inf], 2.0)  # the row seen free up to 2 m
    m.update(np.vstack([along, wall]), [1.0, 1.0], 2.0)  # an agent, and a wall
    agent_cell, wall_cell = (5, 10), (15, 10)
    assert m.data[agent_cell] == 100 and m.data[wall_cell] == 100
    elsewhere = np.array([[0.05, 3.05, 0.0]])
    m.update(elsewhere, [np.inf], 2.0)
    assert m.data[agent_cell] == 100  # one update without a hit: kept
    m.update(elsewhere, [np.inf], 2.0)
    assert m.data[agent_cell] == 0 and m.data[wall_cell] == 100  # two: the agent's gone


def test_a_memory_below_one_is_refused() -> None:
    with pytest.raises(ValueError, match="at least one update"):
        FadingScanMap(4.0, 0.1, memory=0)
