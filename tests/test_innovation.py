"""InnovationTracker: run-wide connection numbers, per-generation split cache, state round trip."""

from __future__ import annotations

import json

import pytest

from mentor_core.errors import FileFormatError
from mentor_core.evolution.innovation import InnovationTracker


def test_same_pair_same_number_new_pairs_count_up() -> None:
    tracker = InnovationTracker(next_node_id=5, next_innovation=10)
    first = tracker.connection(0, 3)
    assert first == 10
    assert tracker.connection(1, 3) == 11
    assert tracker.connection(0, 3) == first
    assert tracker.connection(3, 0) == 12  # direction matters
    assert tracker.next_innovation == 13


def test_connection_numbers_survive_new_generation() -> None:
    tracker = InnovationTracker(5)
    before = tracker.connection(2, 4)
    tracker.new_generation()
    assert tracker.connection(2, 4) == before


def test_same_split_in_one_generation_gets_same_node() -> None:
    tracker = InnovationTracker(5)
    node = tracker.split(7, taken_nodes={0, 1, 2, 3, 4})
    assert node == 5
    assert tracker.split(7, taken_nodes={0, 1, 2, 3, 4}) == node
    assert tracker.split(8, taken_nodes=set()) == 6  # another edge: fresh node


def test_split_after_new_generation_gets_fresh_node() -> None:
    tracker = InnovationTracker(5)
    node = tracker.split(7, taken_nodes=set())
    tracker.new_generation()
    assert tracker.split(7, taken_nodes=set()) == node + 1


def test_split_of_taken_node_is_fresh_and_cache_kept() -> None:
    tracker = InnovationTracker(5)
    node = tracker.split(7, taken_nodes=set())
    fresh = tracker.split(7, taken_nodes={node})
    assert fresh != node
    # a third genome without either node still gets the first id of this generation
    assert tracker.split(7, taken_nodes=set()) == node


def test_fresh_node_skips_ids_the_caller_holds() -> None:
    tracker = InnovationTracker(5)
    assert tracker.split(0, taken_nodes={5, 6}) == 7
    assert tracker.next_node_id == 8


def test_state_round_trip_through_json() -> None:
    tracker = InnovationTracker(5, 3)
    for pair in [(0, 3), (1, 3), (0, 4)]:
        tracker.connection(*pair)
    split_node = tracker.split(4, taken_nodes=set())
    state = json.loads(json.dumps(tracker.to_state()))
    again = InnovationTracker.from_state(state)
    assert again.to_state() == tracker.to_state()
    assert again.connection(1, 3) == tracker.connection(1, 3)
    assert again.split(4, taken_nodes=set()) == split_node
    assert again.connection(9, 9) == tracker.connection(9, 9)  # same next number


@pytest.mark.parametrize(
    ("change", "fault"),
    [
        ({"version": 2}, "version"),
        ({"format": "other"}, "format"),
        ({"next_node_id": "5"}, "bad innovation state"),
        ({"connections": [[0, 1]]}, "bad innovation state"),
        ({"connections": [[0, 1, 0], [1, 1, 0]]}, "repeat"),
        ({"connections": [[0, 1, 99]]}, "next_innovation"),
        ({"splits": [[0, 99]]}, "next_node_id"),
    ],
)
def test_from_state_rejects_bad_state(change: dict[str, object], fault: str) -> None:
    tracker = InnovationTracker(5)
    tracker.connection(0, 1)
    state = {**tracker.to_state(), **change}
    with pytest.raises(FileFormatError, match=fault) as err:
        InnovationTracker.from_state(state, source="ckpt.json")
    assert "ckpt.json" in str(err.value)


def test_negative_counters_are_rejected() -> None:
    with pytest.raises(ValueError, match="next_node_id"):
        InnovationTracker(-1)
