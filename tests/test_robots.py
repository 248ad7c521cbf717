"""Robot profiles: shipped defaults match the design brief; bad robot files fail loudly."""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml

from mentor_core.errors import ConfigError, FileFormatError
from mentor_core.sim.robots import (
    ROBOTS_ENV,
    body_corners,
    default_profiles_path,
    get_profile,
    load_profiles,
    shipped_profiles_path,
)


def test_default_profiles_follow_the_design_brief() -> None:
    profiles = load_profiles()
    assert sorted(profiles) == ["swarm", "ugv"]
    ugv, swarm = profiles["ugv"], profiles["swarm"]
    assert (ugv.length, ugv.width, ugv.n_sensors, ugv.n_inputs) == (0.30, 0.25, 8, 11)
    assert (swarm.length, swarm.width, swarm.n_sensors, swarm.n_inputs) == (0.08, 0.06, 3, 6)
    assert (ugv.sensor_range, swarm.sensor_range) == (4.0, 0.6)
    assert ugv.heading_change_max == swarm.heading_change_max == math.pi
    assert (ugv.step_min, ugv.step_max, swarm.step_min, swarm.step_max) == (0.1, 2.0, 0.01, 0.08)
    assert (ugv.train_arena, ugv.train_scenarios, ugv.test_arena) == (12.0, 80, 12.0)
    assert (swarm.train_arena, swarm.train_scenarios, swarm.test_arena) == (5.0, 20, 4.0)
    assert ugv.goal_radius == 1.0
    assert swarm.goal_radius == pytest.approx(1.0 * 4.0 / 12.0)
    assert ugv.control_period == swarm.control_period == 1.0


def test_ugv_sensors_are_pairs_on_each_edge_facing_out_every_45_degrees() -> None:
    ugv = get_profile("ugv")
    hl, hw = ugv.length / 2, ugv.width / 2
    for i in range(0, 8, 2):
        a, b = ugv.sensors[i], ugv.sensors[i + 1]
        assert math.hypot(a.x - b.x, a.y - b.y) == pytest.approx(0.075)
        edge = i * math.pi / 4  # outward normal of the edge: front, left, rear, right
        normal = (math.cos(edge), math.sin(edge))
        for s, splay in ((a, -math.pi / 8), (b, math.pi / 8)):
            # on that edge, facing out of it, splayed 22.5 deg about its normal
            assert s.x * normal[0] + s.y * normal[1] == pytest.approx(hl if i % 4 == 0 else hw)
            assert s.angle == pytest.approx(edge + splay)
    bearings = np.unwrap([math.atan2(s.y, s.x) for s in ugv.sensors])
    assert np.all(np.diff(bearings) > 0)  # counter-clockwise order, one full turn
    assert bearings[-1] - bearings[0] < 2 * math.pi
    np.testing.assert_allclose(np.diff([s.angle for s in ugv.sensors]), math.pi / 4)
    # the front pair reads 45 deg beams of 5 rays, the other six single rays
    assert ugv.beam_width == pytest.approx(math.radians(45.0)) and ugv.beam_rays == 5
    assert ugv.beam_sensors == (0, 1)
    np.testing.assert_array_equal(ugv.ray_counts, [5, 5, 1, 1, 1, 1, 1, 1])
    beam = np.radians([-22.5, -11.25, 0.0, 11.25, 22.5])
    np.testing.assert_allclose(ugv.ray_offsets[:2], [beam, beam])
    assert not ugv.ray_offsets[2:].any()


def test_swarm_sensors_on_the_front_edge() -> None:
    swarm = get_profile("swarm")
    assert [s.x for s in swarm.sensors] == [0.04] * 3
    assert [round(math.degrees(s.angle)) for s in swarm.sensors] == [-45, 0, 45]
    assert swarm.sensors[1].y == 0.0


def test_time_budget_and_cap() -> None:
    ugv, swarm = get_profile("ugv"), get_profile("swarm")
    assert ugv.time_budget((0, 0), (6, 8)) == pytest.approx(20.0)  # 2 * 10 m / 1 m/s
    assert swarm.time_budget((0, 0), (1.0, 0)) == pytest.approx(25.0)
    assert swarm.time_budget((0, 0), (3.0, 4.0)) == 50.0  # capped
    assert swarm.uncapped_distance == pytest.approx(2.0)
    # a straight run at top pace fits the budget
    for p in (ugv, swarm):
        top_pace = p.step_max / p.control_period
        assert p.time_budget((0, 0), (p.uncapped_distance, 0)) > p.uncapped_distance / top_pace


def test_body_corners_follow_the_pose() -> None:
    ugv = get_profile("ugv")
    corners = body_corners(ugv, [(1.0, 2.0, math.pi / 2)])
    expected = [(1.125, 1.85), (1.125, 2.15), (0.875, 2.15), (0.875, 1.85)]
    np.testing.assert_allclose(corners[0], expected, atol=1e-12)
    assert ugv.half_diagonal == pytest.approx(math.hypot(0.15, 0.125))


def test_get_profile_unknown_name() -> None:
    with pytest.raises(ConfigError, match=r"unknown robot 'tank'.*swarm, ugv"):
        get_profile("tank")


def _default_doc() -> dict[str, Any]:
    doc = yaml.safe_load(shipped_profiles_path().read_text())
    assert isinstance(doc, dict)
    return doc


def _mutate(doc: dict[str, Any], change: str) -> None:
    ugv = doc["robots"]["ugv"]
    if change == "unknown":
        ugv["lenght"] = 0.3
    elif change == "missing":
        del ugv["sensor_range"]
    elif change == "nonpositive":
        ugv["width"] = 0.0
    elif change == "steps":
        ugv["step_min"] = 3.0
    elif change == "mount":
        ugv["sensors"][0]["x"] = 0.2
    elif change == "bool":
        ugv["rated_speed"] = True
    elif change == "count":
        ugv["train_scenarios"] = 0
    elif change == "mount_key":
        ugv["sensors"][1]["angle"] = 0.0
    elif change == "beam_without_rays":
        ugv.update(beam_width_deg=30.0, beam_rays=1)
    elif change == "rays_without_beam":
        ugv.update(beam_width_deg=0.0, beam_rays=3)
    elif change == "beam_sensors_without_beam":
        ugv.update(beam_width_deg=0.0, beam_rays=1)
    elif change == "beam_sensors_out_of_range":
        ugv["beam_sensors"] = [0, 8]
    elif change == "beam_sensors_repeated":
        ugv["beam_sensors"] = [1, 1]
    elif change == "beam_sensors_empty":
        ugv["beam_sensors"] = []
    elif change == "beam_too_wide":
        ugv.update(beam_width_deg=180.0, beam_rays=5)
    elif change == "beam_rays_float":
        ugv.update(beam_width_deg=30.0, beam_rays=2.5)


@pytest.mark.parametrize(
    ("change", "key"),
    [
        ("unknown", "robots.ugv.lenght"),
        ("missing", "robots.ugv.sensor_range"),
        ("nonpositive", "robots.ugv.width"),
        ("steps", "robots.ugv.step_min"),
        ("mount", "robots.ugv.sensors[0]"),
        ("bool", "robots.ugv.rated_speed"),
        ("count", "robots.ugv.train_scenarios"),
        ("mount_key", "robots.ugv.sensors[1].angle"),
        ("beam_without_rays", "robots.ugv.beam_rays"),
        ("rays_without_beam", "robots.ugv.beam_rays"),
        ("beam_too_wide", "robots.ugv.beam_width_deg"),
        ("beam_rays_float", "robots.ugv.beam_rays"),
        ("beam_sensors_without_beam", "robots.ugv.beam_sensors"),
        ("beam_sensors_out_of_range", "robots.ugv.beam_sensors"),
        ("beam_sensors_repeated", "robots.ugv.beam_sensors"),
        ("beam_sensors_empty", "robots.ugv.beam_sensors"),
    ],
)
def test_bad_values_name_key_and_file(tmp_path: Path, change: str, key: str) -> None:
    doc = _default_doc()
    _mutate(doc, change)
    path = tmp_path / "robots.yaml"
    path.write_text(yaml.safe_dump(doc))
    with pytest.raises(ConfigError) as info:
        load_profiles(path)
    assert info.value.key == key
    assert str(path) in str(info.value)
    assert "\n" not in str(info.value)


@pytest.mark.parametrize(
    ("text", "fault"),
    [
        (None, "no such file"),
        ("", "empty file"),
        ("robots: [unclosed", "not valid YAML"),
        ("format: mentor-robots\nversion: 2\nrobots: {}\n", "version 2"),
        ("format: other\nversion: 1\nrobots: {}\n", "format"),
        ("- a list\n", "mapping"),
    ],
)
def test_bad_files(tmp_path: Path, text: str | None, fault: str) -> None:
    path = tmp_path / "robots.yaml"
    if text is not None:
        path.write_text(text)
    with pytest.raises(FileFormatError, match=fault) as info:
        load_profiles(path)
    assert info.value.path == str(path)


def test_loaded_copy_equals_default(tmp_path: Path) -> None:
    path = tmp_path / "robots.yaml"
    path.write_text(yaml.safe_dump(_default_doc()))
    assert load_profiles(path) == load_profiles()


def test_a_robot_file_of_variants_lists_only_what_differs(tmp_path: Path) -> None:
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub/beams.yaml").write_text(
        "extends: shipped\nrobots:\n  swarm:\n    beam_width_deg: 30.0\n    beam_rays: 3\n"
    )
    (tmp_path / "slow.yaml").write_text(
        "extends: sub/beams.yaml\nrobots:\n  ugv:\n    step_max: 1.0\n"
        "  swarm:\n    sensors: [{x: 0.04, y: 0.0, angle_deg: 0.0}]\n"
    )
    shipped = load_profiles(shipped_profiles_path())
    variants = load_profiles(tmp_path / "slow.yaml")
    assert variants["ugv"] == dataclasses.replace(shipped["ugv"], step_max=1.0)
    swarm = variants["swarm"]  # the base's beams kept, its sensor list replaced whole
    assert swarm.beam_rays == 3 and swarm.n_sensors == 1
    assert swarm.goal_radius == shipped["swarm"].goal_radius


@pytest.mark.parametrize(
    ("text", "fault"),
    [
        ("extends: ugv\n", "extends: no robot file 'ugv' (shipped, or a file's path ending"),
        ("extends: robots.yaml\n", "extends: extends itself"),
        ("extends: shipped\nrobots:\n  ugv:\n    step_min: -1\n", "robots.ugv.step_min"),
    ],
)
def test_a_bad_extends_names_the_robot_file(tmp_path: Path, text: str, fault: str) -> None:
    path = tmp_path / "robots.yaml"
    path.write_text(text)
    with pytest.raises(ConfigError) as info:
        load_profiles(path)
    assert str(info.value).startswith(f"{path}: ") and fault in str(info.value)


def test_a_beam_is_read_from_the_file_and_sampled_evenly(tmp_path: Path) -> None:
    doc = _default_doc()
    doc["robots"]["ugv"].update(beam_width_deg=30.0, beam_rays=3)
    path = tmp_path / "robots.yaml"
    path.write_text(yaml.safe_dump(doc))
    ugv = load_profiles(path)["ugv"]
    assert ugv.beam_width == pytest.approx(math.radians(30.0)) and ugv.beam_rays == 3
    np.testing.assert_allclose(ugv.beam_offsets, np.radians([-15.0, 0.0, 15.0]))
    np.testing.assert_array_equal(get_profile("swarm").beam_offsets, [0.0])


def test_mentor_robots_names_the_robot_file_in_use(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    doc = _default_doc()
    for mount in doc["robots"]["ugv"]["sensors"]:  # the paper's pairs, facing straight out
        mount["angle_deg"] = 90.0 * round(mount["angle_deg"] / 90.0)
    path = tmp_path / "paper_robots.yaml"
    path.write_text(yaml.safe_dump(doc))
    monkeypatch.setenv(ROBOTS_ENV, str(path))
    assert default_profiles_path() == path
    assert [round(math.degrees(m.angle)) for m in get_profile("ugv").sensors] == [
        0, 0, 90, 90, 180, 180, 270, 270
    ]
    assert get_profile("swarm") == load_profiles(shipped_profiles_path())["swarm"]
    monkeypatch.setenv(ROBOTS_ENV, str(tmp_path / "missing.yaml"))
    with pytest.raises(FileFormatError, match=r"missing\.yaml: no such file"):
        get_profile("ugv")
    monkeypatch.delenv(ROBOTS_ENV)
    assert default_profiles_path() == shipped_profiles_path()
