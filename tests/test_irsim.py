"""mentor_core.irsim (issue 59): the adapter's conversions against hand-computed cases, world
files and their faults, and closed-loop episodes in IR-SIM (skipped where the extra
``mentor-core[irsim]`` is not installed; the lock installs it, so CI runs them)."""

from __future__ import annotations

import builtins
import copy
import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from mentor_core.controller.deployment import load_deployment
from mentor_core.errors import ConfigError, FileFormatError
from mentor_core.irsim.adapter import irsim_action, lidar_mount, scan_data, velocity_command
from mentor_core.irsim.dependency import MISSING, IrsimMissing, load_irsim
from mentor_core.irsim.world_file import WorldPair, load_world, parse_world, world_document
from mentor_core.irsim.worlds import SETUPS, make_world, robot_block, walls
from mentor_core.sim.robots import get_profile
from mentor_core.sim.scan_adapter import readings_from_scan

ROOT = Path(__file__).resolve().parents[1]
WORLDS = ROOT / "benchmarks" / "irsim_worlds"
UGV = ROOT / "planners" / "ugv-paper-dual-s1.json"
SWARM = ROOT / "planners" / "swarm-paper-dual-s1.json"


def _scan(ranges: list[float], valid: list[bool], low: float = 0.05, high: float = 4.0,
          n: int | None = None) -> dict[str, Any]:  # fmt: skip
    count = n or len(ranges)
    return {"angle_min": -math.pi / 2, "angle_increment": math.pi / max(count - 1, 1),
            "range_min": low, "range_max": high, "ranges": np.array(ranges),
            "valid": np.array(valid)}  # fmt: skip


# --- the conversions, by hand -----------------------------------------------------------------

def test_a_scan_is_written_as_rep_117_says() -> None:
    """valid: as measured; a hit under range_min (IR-SIM clips it to range_min): -inf;
    nothing hit (IR-SIM writes range_max) or beyond range_max: +inf."""
    data = scan_data(_scan([1.0, 4.0, 0.05, 2.5, 4.0], [True, False, False, True, False]))
    assert data.ranges.tolist() == [1.0, math.inf, -math.inf, 2.5, math.inf]
    assert (data.angle_min, data.range_min, data.range_max) == (-math.pi / 2, 0.05, 4.0)
    assert data.angle_increment == pytest.approx(math.pi / 4)


def test_a_scan_without_its_fields_is_refused() -> None:
    with pytest.raises(ValueError, match="not an IR-SIM lidar2d scan"):
        scan_data({"ranges": [1.0]})
    with pytest.raises(ValueError, match="2 valid flags for 3 ranges"):
        scan_data(_scan([1.0, 2.0, 3.0], [True, True]))


def test_a_decision_is_its_twist_over_the_period() -> None:
    """(dtheta, ds) = (pi / 8 rad, 0.25 m) held for 0.25 s: 1 m/s and pi / 2 rad/s."""
    v, w = velocity_command(math.pi / 8, 0.25, 0.25)
    assert (v, w) == pytest.approx((1.0, math.pi / 2))
    assert velocity_command(-0.1, -0.02, 0.5) == pytest.approx((-0.04, -0.2))
    assert irsim_action((1.0, 0.5)).tolist() == [[1.0], [0.5]]


def test_the_lidar_offset_is_its_mount() -> None:
    mount = lidar_mount([0.1, -0.02, 0.5])
    assert (mount.pose.x, mount.pose.y, mount.pose.yaw, mount.inverted) == (0.1, -0.02, 0.5,
                                                                            False)
    assert lidar_mount(None).pose.x == 0.0


def test_a_wall_ahead_is_read_by_the_front_sensors() -> None:
    """A flat wall 1 m ahead of the lidar, seen by 360 rays: the UGV's front pair (mounts at
    x = 0.15 m, beams of 45 deg reaching straight ahead) read 0.85 m, the rear ones nothing."""
    n = 360
    angles = -math.pi + np.arange(n) * 2 * math.pi / n
    ahead = np.abs(angles) < math.radians(75)
    ranges = np.where(ahead, 1.0 / np.cos(angles), 4.0)
    scan = {"angle_min": -math.pi, "angle_increment": 2 * math.pi / n, "range_min": 0.05,
            "range_max": 4.0, "ranges": ranges, "valid": ahead & (ranges <= 4.0)}  # fmt: skip
    read = readings_from_scan(scan_data(scan), lidar_mount([0, 0, 0]), get_profile("ugv"))
    assert read.readings[:2] == pytest.approx([0.85, 0.85], abs=1e-6)
    assert np.isinf(read.readings[4:6]).all()


# --- world files ------------------------------------------------------------------------------

def test_a_committed_world_is_what_its_seed_draws() -> None:
    path = WORLDS / "validation" / "ugv-stopper-0.yaml"
    drawn = parse_world(make_world("ugv", "stopper", "validation", 0), path)
    assert load_world(path) == drawn
    assert len(drawn.pairs) == 5 and drawn.kind == "dynamic" and drawn.split == "validation"


def test_the_committed_worlds_hold_the_pairs_the_issue_asks_for() -> None:
    for robot in ("ugv", "swarm"):
        test = [load_world(p, robot) for p in sorted((WORLDS / "test").glob(f"{robot}-*.yaml"))]
        static = sum(len(w.pairs) for w in test if w.kind == "static")
        dynamic = sum(len(w.pairs) for w in test if w.kind == "dynamic")
        assert (static, dynamic) == (60, 90)
        agents = [len(p.agents) for w in test for p in w.pairs if w.kind == "dynamic"]
        assert min(agents) >= 3 and max(agents) == 15


@pytest.mark.parametrize(("change", "fault"), [
    (lambda d: d.pop("custom"), "no custom.mentor block"),
    (lambda d: d.update(robots=[]), "unknown top-level key 'robots'"),
    (lambda d: d["custom"]["mentor"].update(robot="rover"), "'rover' is no known robot"),
    (lambda d: d["world"].update(width=5.0), "width and height must be one positive side"),
    (lambda d: d["custom"]["mentor"]["pairs"][0].update(goal=[1.0]), "goal \\[x, y\\]"),
    (lambda d: d["custom"]["mentor"]["pairs"][0].update(start=[99.0, 1.0, 0.0]),
     "outside the 12 m arena"),
    (lambda d: d["robot"][0].update(sensors=[]), "no lidar2d"),
])  # fmt: skip
def test_a_malformed_world_is_one_line_naming_the_file(change: Any, fault: str) -> None:
    document = copy.deepcopy(make_world("ugv", "pillar_hall", "validation", 0))
    change(document)
    with pytest.raises(FileFormatError, match=fault) as err:
        parse_world(document, "bad.yaml")
    assert "bad.yaml" in str(err.value) and "\n" not in str(err.value)


def test_a_world_of_another_robot_or_no_file_is_refused(tmp_path: Path) -> None:
    with pytest.raises(ConfigError, match="for robot 'ugv', not 'swarm'"):
        load_world(WORLDS / "validation" / "ugv-stopper-0.yaml", "swarm")
    with pytest.raises(FileFormatError, match="no such file"):
        load_world(tmp_path / "none.yaml")
    (tmp_path / "bad.yaml").write_text("world: [unclosed\n")
    with pytest.raises(FileFormatError):
        load_world(tmp_path / "bad.yaml")


def test_without_irsim_the_error_names_the_extra(monkeypatch: pytest.MonkeyPatch) -> None:
    real = builtins.__import__

    def no_irsim(name: str, *args: Any, **kwargs: Any) -> Any:
        if name == "irsim" or name.startswith("irsim."):
            raise ImportError(name)
        return real(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", no_irsim)
    monkeypatch.delitem(__import__("sys").modules, "irsim", raising=False)
    with pytest.raises(IrsimMissing, match=r"install mentor-core\[irsim\]") as err:
        load_irsim()
    assert str(err.value) == MISSING


# --- closed loop in IR-SIM ----------------------------------------------------------------------

def _world(robot: str, tmp_path: Path, start: tuple[float, float, float],
           goal: tuple[float, float], statics: list[dict[str, Any]],
           agents: list[dict[str, Any]]) -> Path:  # fmt: skip
    """A hand-made world file of one pair (its shortest path: the straight line)."""
    profile = get_profile(robot)
    size, k = profile.test_arena, profile.test_arena / 12.0
    block = robot_block(profile, SETUPS[robot])
    config = {"world": {"height": size, "width": size, "step_time": SETUPS[robot].step_time,
                        "collision_mode": "unobstructed_obstacles"},
              "robot": [block], "obstacle": [*walls(size, k), *statics]}  # fmt: skip
    pair = WorldPair(start, goal, math.dist(start[:2], goal) - profile.goal_radius,
                     tuple(agents))  # fmt: skip
    meta = {"robot": robot, "family": "hand", "kind": "dynamic" if agents else "static",
            "split": "validation", "seed": 0}  # fmt: skip
    path = tmp_path / f"{robot}-hand.yaml"
    path.write_text(json.dumps(world_document(config, meta, [pair])))  # JSON is YAML
    return path


def _stopper(xy: tuple[float, float], stop: tuple[float, float], speed: float,
             radius: float) -> dict[str, Any]:  # fmt: skip
    return {"name": "agent_0", "shape": {"name": "circle", "radius": radius},
            "kinematics": {"name": "omni"}, "state": [*xy, 0.0], "goal": [[*stop, 0.0]],
            "goal_threshold": 0.02, "vel_max": [speed, speed], "vel_min": [-speed, -speed],
            "behavior": {"name": "dash"}}  # fmt: skip


def test_a_shipped_planner_reaches_its_goal_in_a_static_world(tmp_path: Path) -> None:
    pytest.importorskip("irsim")
    from mentor_core.irsim.drivers import genome_driver
    from mentor_core.irsim.episode import run_episode

    pillar = {"shape": {"name": "circle", "radius": 0.4}, "state": [6.0, 6.1, 0.0]}
    world = load_world(_world("ugv", tmp_path, (2.0, 6.0, 0.0), (10.0, 6.0), [pillar], []))
    spec = genome_driver(UGV, "ugv", world.size, load_deployment("shipped", "ugv")[0])
    result = run_episode(world, 0, spec, seed=1, record=True)
    assert result.outcome == "reached", result
    assert result.time < 20.0 and 0.5 < result.spl <= 1.0
    assert result.trajectory is not None and result.trajectory.shape[1] == 3


@pytest.mark.parametrize(("robot", "genome"), [("ugv", UGV), ("swarm", SWARM)])
def test_an_agent_that_stops_in_the_path_is_not_driven_into(
    robot: str, genome: Path, tmp_path: Path
) -> None:
    """An agent walks onto the straight line ahead of the robot and stands there: the
    shipped planner goes round it (or stops short), never into it."""
    pytest.importorskip("irsim")
    from mentor_core.irsim.drivers import genome_driver
    from mentor_core.irsim.episode import run_episode

    k = get_profile(robot).test_arena / 12.0
    pace = get_profile(robot).rated_speed
    agent = _stopper((6.0 * k, 7.5 * k), (6.0 * k, 6.0 * k), 0.8 * pace, 0.3 * k)
    path = _world(robot, tmp_path, (2.0 * k, 6.0 * k, 0.0), (10.5 * k, 6.0 * k), [], [agent])
    world = load_world(path)
    spec = genome_driver(genome, robot, world.size, load_deployment("shipped", robot)[0])
    result = run_episode(world, 0, spec, seed=2, record=True)
    assert result.outcome != "collision_agent", result
    assert result.agents is not None
    assert np.allclose(result.agents[-1, 0], (6.0 * k, 6.0 * k), atol=0.1 * k)  # it stood
    assert result.outcome == "reached", result


def test_the_same_seed_gives_the_same_episode() -> None:
    pytest.importorskip("irsim")
    from mentor_core.irsim.drivers import genome_driver
    from mentor_core.irsim.episode import run_episode

    world = load_world(WORLDS / "validation" / "ugv-crowd-0.yaml")
    spec = genome_driver(UGV, "ugv", world.size, load_deployment("shipped", "ugv")[0])
    first, second = (run_episode(world, 1, spec, seed=3, limit=8.0) for _ in range(2))
    assert first == second


def test_the_command_runs_a_static_and_a_dynamic_world(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """CI's closed loop: one pair of a committed static and of a dynamic world, a planner, a
    baseline and a pursuit, each episode a few seconds of sim time."""
    pytest.importorskip("irsim")
    from mentor_core.irsim.cli import main

    out = tmp_path / "episodes.json"
    figure = tmp_path / "paths.png"
    code = main([str(WORLDS / "validation" / "swarm-pillar_hall-0.yaml"),
                 str(WORLDS / "validation" / "swarm-crossing-0.yaml"), "--pairs", "1",
                 "--genome", str(SWARM), "--baseline", "mapped-guard-vfh",
                 "--pursuit", str(SWARM), "--limit", "6", "--out", str(out),
                 "--figure", str(figure)])  # fmt: skip
    printed = capsys.readouterr().out
    assert code == 0, printed
    episodes = json.loads(out.read_text())["episodes"]
    assert len(episodes) == 6 and {e["driver"] for e in episodes} == {
        "swarm-paper-dual-s1", "mapped-guard-vfh", "pursuit-swarm-paper-dual-s1"}
    assert all(e["outcome"] != "collision_agent" for e in episodes)
    assert "| swarm-paper-dual-s1 | 2 |" in printed and figure.stat().st_size > 1000


@pytest.mark.parametrize(("argv", "fault"), [
    (["none.yaml", "--genome", str(UGV)], "none.yaml: no such file"),
    ([str(WORLDS / "validation" / "ugv-stopper-0.yaml"), "--genome", str(SWARM)],
     "trained for robot 'swarm', not 'ugv'"),
    ([str(WORLDS / "validation" / "ugv-stopper-0.yaml")], "nothing to drive"),
    ([str(WORLDS / "validation" / "ugv-stopper-0.yaml"), "--baseline", "astar"],
     "unknown baseline 'astar'"),
    ([str(WORLDS / "validation" / "ugv-stopper-0.yaml"), "--genome", str(UGV), "--pairs", "7"],
     "has pairs 0..4, not 7"),
])  # fmt: skip
def test_bad_input_is_one_line_and_status_2(
    argv: list[str], fault: str, capsys: pytest.CaptureFixture[str]
) -> None:
    pytest.importorskip("irsim")
    from mentor_core.irsim.cli import main

    assert main(argv) == 2
    err = capsys.readouterr().err
    assert fault in err and err.count("\n") == 1
