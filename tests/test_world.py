"""Worlds, scenarios and world files: invariants, free-space queries, round trip, bad files."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from mentor_core.errors import FileFormatError
from mentor_core.sim.world import Scenario, World, load_world, save_world

BOXES = np.array([[1.0, 1.0, 2.0, 3.0], [2.0, 1.0, 4.0, 2.0]])  # touching, not overlapping


def test_world_obstacles_are_a_read_only_copy() -> None:
    source = BOXES.copy()
    world = World(10.0, source, name="w")
    source[0, 0] = 0.5
    assert world.obstacles[0, 0] == 1.0
    assert world.obstacles.dtype == np.float64
    with pytest.raises(ValueError):
        world.obstacles[0, 0] = 0.0
    assert World(10.0).obstacles.shape == (0, 4)


def test_world_equality_and_hash_compare_values() -> None:
    a = World(10.0, BOXES, name="w")
    b = World(10.0, BOXES.copy(), name="w")
    assert a == b and hash(a) == hash(b)
    assert a != World(10.0, BOXES[:1], name="w")
    assert a != World(10.0, BOXES, name="other")
    assert len({a, b}) == 1
    assert "2 boxes" in repr(a)


@pytest.mark.parametrize(
    ("boxes", "fault"),
    [
        ([[2.0, 1.0, 1.0, 3.0]], "xmax <= xmin"),
        ([[1.0, 1.0, 2.0, 1.0]], "xmax <= xmin"),
        ([[9.5, 1.0, 10.5, 2.0]], "outside the arena"),
        ([[-0.1, 1.0, 1.0, 2.0]], "outside the arena"),
        ([[1.0, 1.0, math.nan, 3.0]], "not finite"),
    ],
)
def test_invalid_obstacles(boxes: list[list[float]], fault: str) -> None:
    with pytest.raises(ValueError, match=fault):
        World(10.0, np.array(boxes))


def test_overlapping_obstacles_are_allowed_and_round_trip(tmp_path: Path) -> None:
    # an L of two walls sharing their corner square, as real layouts overlap at every corner
    boxes = np.array([[1.0, 1.0, 3.0, 3.0], [2.0, 2.0, 4.0, 4.0]])
    world = World(10.0, boxes)
    scenario = Scenario(world, (5.0, 8.0, 0.0), (8.0, 8.0))
    save_world(tmp_path / "w.yaml", world, [scenario])
    assert load_world(tmp_path / "w.yaml") == (world, [scenario])
    with pytest.raises(ValueError, match=r"inside obstacles\[0\]"):
        Scenario(world, (2.5, 2.5, 0.0), (8.0, 8.0))  # in both boxes
    # the signed distance inside the union is negative (the deeper box's depth)
    assert world.signed_distance([(2.5, 2.5)])[0] == pytest.approx(-0.5)


def test_signed_distance_and_free_at() -> None:
    world = World(10.0, np.array([[4.0, 4.0, 6.0, 6.0]]))
    pts = [(5.0, 5.0), (7.0, 5.0), (7.0, 7.0), (0.5, 5.0), (5.0, 4.0)]
    expected = [-1.0, 1.0, math.sqrt(2.0), 0.5, 0.0]
    np.testing.assert_allclose(world.signed_distance(pts), expected)
    assert world.free_at(pts, 0.6).tolist() == [False, True, True, False, False]
    assert world.free_at(pts).tolist() == [False, True, True, True, True]


def test_scenario_wraps_heading_and_rejects_bad_points() -> None:
    world = World(10.0, BOXES)
    sc = Scenario(world, (5.0, 5.0, 3 * math.pi / 2), (8.0, 8.0))
    assert sc.start[2] == pytest.approx(-math.pi / 2)
    assert Scenario(world, (5.0, 5.0, -math.pi), (8.0, 8.0)).start[2] == math.pi
    with pytest.raises(ValueError, match="inside obstacles"):
        Scenario(world, (1.5, 2.0, 0.0), (8.0, 8.0))
    with pytest.raises(ValueError, match="outside the arena"):
        Scenario(world, (5.0, 5.0, 0.0), (10.5, 8.0))
    with pytest.raises(ValueError, match="not finite"):
        Scenario(world, (5.0, math.nan, 0.0), (8.0, 8.0))


def test_round_trip_is_exact_and_atomic(tmp_path: Path) -> None:
    world = World(12.0, BOXES / 3.0, name="thirds")
    scenarios = [Scenario(world, (5.1 / 3, 7.0, 0.1), (11.0, 11.0 / 7))]
    path = tmp_path / "w.yaml"
    save_world(path, world, scenarios)
    loaded, loaded_scenarios = load_world(path)
    assert loaded == world
    assert loaded_scenarios == scenarios
    assert [p.name for p in tmp_path.iterdir()] == ["w.yaml"]
    text = path.read_text()
    assert "format: mentor-world" in text and "version: 1" in text
    other = World(12.0)
    with pytest.raises(ValueError, match="belong"):
        save_world(tmp_path / "x.yaml", other, scenarios)


def test_minimal_file_loads(tmp_path: Path) -> None:
    path = tmp_path / "w.yaml"
    path.write_text("format: mentor-world\nversion: 1\nsize: 5\n")
    world, scenarios = load_world(path)
    assert world == World(5.0) and scenarios == []


GOOD = "format: mentor-world\nversion: 1\nsize: 10\n"


@pytest.mark.parametrize(
    ("text", "fault"),
    [
        (None, "no such file"),
        ("", "empty file"),
        ("size: [unclosed", "not valid YAML"),
        ("format: mentor-world\nversion: 2\nsize: 10\n", "version 2"),
        ("format: mentor-genome\nversion: 1\nsize: 10\n", "format"),
        (GOOD + "colour: red\n", "colour: unknown key"),
        (GOOD + "units: ft\n", "units"),
        ("format: mentor-world\nversion: 1\n", "size: missing key"),
        (GOOD + "map: office.yaml\n", "map: give 'size' or 'map', not both"),
        ("format: mentor-world\nversion: 1\nmap: office.yaml\n", "needs a map reader"),
        ("format: mentor-world\nversion: 1\nmap: 3\n", "map: expected text, got 3"),
        ("format: mentor-world\nversion: 1\nmap: ' '\n", "map: must name a map YAML"),
        (GOOD + "obstacles: [[2, 1, 1, 3]]\n", "xmax <= xmin"),
        (GOOD + "obstacles: [[9, 1, 11, 3]]\n", "outside the arena"),
        (GOOD + "obstacles: [[1, 1, .nan, 3]]\n", r"obstacles\[0\]\[2\]: expected a finite"),
        (GOOD + "obstacles: [[1, 1, 3]]\n", r"obstacles\[0\]: expected 4 values"),
        (GOOD + "obstacles: [[1, 1, 3, 3]]\nscenarios: [{start: [2, 2, 0], goal: [8, 8]}]\n",
         r"scenarios\[0\]: start .* inside obstacles\[0\]"),
        (GOOD + "scenarios: [{start: [5, 5, 0], goal: [11, 8]}]\n", "goal .* outside the arena"),
        (GOOD + "scenarios: [{start: [5, 5], goal: [8, 8]}]\n", "start: expected 3 values"),
        (GOOD + "scenarios: [{start: [5, 5, .nan], goal: [8, 8]}]\n", "finite number"),
        (GOOD + "scenarios: [{start: [5, 5, 0]}]\n", r"scenarios\[0\]\.goal: missing key"),
        ("format: mentor-world\nversion: 1\nsize: -3\n", "size"),
        ("format: mentor-world\nversion: 1\nsize: '12'\n", "size: expected a number, got '12'"),
        # YAML 1.2 numbers: 1e12 is a number (too large an arena), not text
        ("format: mentor-world\nversion: 1\nsize: 1e12\n", "size: arena size 1e\\+12 m is beyond"),
    ],
)
def test_bad_world_files(tmp_path: Path, text: str | None, fault: str) -> None:
    path = tmp_path / "bad.yaml"
    if text is not None:
        path.write_text(text)
    with pytest.raises(FileFormatError, match=fault) as info:
        load_world(path)
    assert str(info.value).startswith(f"{path}: ")
    assert "\n" not in str(info.value)
