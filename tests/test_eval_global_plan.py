"""mentor-eval --global-plan (each genome also along a global plan, beside its plain run),
--map (the world from a ROS map), --rotation-shim, --collision-guard, --scan-map, --deployed,
and their bad input."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from mentor_core.cli.evaluate import main as mentor_eval
from mentor_core.files.bags import read_episode_bag
from mentor_core.navigation.grid import world_grid
from mentor_core.navigation.map_file import save_map
from mentor_core.runtime.recording import recorded_episodes
from mentor_core.sim.world import Scenario, World, save_world

ROOT = Path(__file__).resolve().parents[1]
UGV_GENOME = ROOT / "bags" / "regression" / "ugv_reference_genome.json"
DEAD_END = World(
    12.0, np.array([[7.0, 3.5, 7.3, 8.5], [4.5, 3.5, 7.3, 3.8], [4.5, 8.2, 7.3, 8.5]]),
    name="dead-end",
)


def test_global_plan_runs_beside_the_plain_run_and_records_both(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    world_file = tmp_path / "dead_end.yaml"
    save_world(world_file, DEAD_END, [Scenario(DEAD_END, (2.0, 6.0, 0.0), (10.0, 6.0))])
    out, bag = tmp_path / "eval.json", tmp_path / "episodes"
    args = [str(UGV_GENOME), "--robot", "ugv", "--world", str(world_file), "--global-plan"]
    assert mentor_eval([*args, "--label", "ref", "--out", str(out), "--record", str(bag)]) == 0
    printed = capsys.readouterr()
    assert "ref +global-plan" in printed.out
    runs = json.loads(out.read_text())["runs"]
    assert [r["genome"] for r in runs] == ["ref", "ref +global-plan"]
    assert [r["summary"]["success_rate"] for r in runs] == [0.0, 1.0]
    # the recording: robot_0 the plain run, robot_1 along the plan, as in the table
    recorded = {(e.setup.name, e.outcome) for e in recorded_episodes(read_episode_bag(bag))}
    assert recorded == {("robot_0", "timed_out"), ("robot_1", "reached")}
    assert "in the recording" not in printed.err


def test_a_world_from_a_ros_map(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    save_map(tmp_path / "dead_end.yaml", world_grid(DEAD_END, 0.05))
    out = tmp_path / "eval.json"
    args = [str(UGV_GENOME), "--robot", "ugv", "--map", str(tmp_path / "dead_end.yaml")]
    assert mentor_eval([*args, "--n", "3", "--seed", "4", "--out", str(out)]) == 0
    doc = json.loads(out.read_text())
    assert doc["source"].endswith("dead_end.yaml seed 4")
    assert len(doc["scenarios"]) == 3 and doc["world"]["size"] == pytest.approx(12.0)
    assert len(doc["world"]["obstacles"]) == 3  # the U's cells merged back into 3 boxes
    capsys.readouterr()


@pytest.mark.parametrize(
    ("args", "fault"),
    [
        (["--robot", "ugv", "--map", "{tmp}/missing.yaml"], "missing.yaml: no such file"),
        (["--robot", "ugv", "--map", "{tmp}/bad.yaml"], "bad.yaml: missing key 'image'"),
        (["--robot", "ugv", "--world", "{tmp}/w.yaml", "--seed", "3"], "not with --bag"),
        (["--robot", "ugv"], "give --bag, --world, --map or --seed"),
        (["--robot", "ugv", "--seed", "1", "--lookahead", "-1"], "--lookahead must be"),
        (["--robot", "ugv", "--seed", "1", "--rotation-shim", "0"], "--rotation-shim must be"),
        (["--robot", "ugv", "--seed", "1", "--deployed", "--scan-map"], "--deployed: give none"),
        (["--robot", "ugv", "--seed", "1", "--clearance-cost", "1"], "only with --scan-map"),
        (["--robot", "ugv", "--seed", "1", "--scan-map", "--clearance-cost", "nan"],
         "--clearance-cost must be"),
    ],
)
def test_bad_arguments_and_map_files_exit_2_with_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], args: list[str], fault: str
) -> None:
    (tmp_path / "bad.yaml").write_text("resolution: 0.05\n")
    save_world(tmp_path / "w.yaml", DEAD_END, [Scenario(DEAD_END, (2.0, 6.0, 0.0), (10.0, 6.0))])
    argv = [str(UGV_GENOME), *(a.format(tmp=tmp_path) for a in args)]
    assert mentor_eval(argv) == 2
    err = capsys.readouterr().err.strip()
    assert fault in err and len(err.splitlines()) == 1


def test_behind_a_rotation_shim_a_robot_facing_away_turns_first(tmp_path: Path) -> None:
    empty = World(12.0, np.zeros((0, 4)), name="empty")
    world_file = tmp_path / "empty.yaml"
    save_world(world_file, empty, [Scenario(empty, (4.0, 6.0, np.pi), (10.0, 6.0))])
    runs = {}
    for extra in ([], ["--rotation-shim", "45"]):
        out = tmp_path / f"eval{len(extra)}.json"
        assert mentor_eval([str(UGV_GENOME), "--robot", "ugv", "--world", str(world_file),
                            "--out", str(out), *extra]) == 0  # fmt: skip
        runs[len(extra)] = json.loads(out.read_text())["runs"][0]["results"][0]["trajectory"]
    plain, shim = np.asarray(runs[0]), np.asarray(runs[2])
    # the goal straight behind: the shimmed robot turns on the spot (its smallest step, 0.1 m)
    assert np.hypot(*(shim[1, :2] - shim[0, :2])) <= 0.1 + 1e-9
    assert not np.allclose(plain[1], shim[1])


def test_behind_the_collision_guard_fewer_runs_end_in_a_collision(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    # a freshly sampled DoE world in which the reference genome collides on 3 pairs of 10
    collisions = []
    for extra in ([], ["--collision-guard", "--record", str(tmp_path / "bag")]):
        out = tmp_path / f"eval{len(extra)}.json"
        assert mentor_eval([str(UGV_GENOME), "--robot", "ugv", "--seed", "3", "--n", "10",
                            "--out", str(out), *extra]) == 0  # fmt: skip
        results = json.loads(out.read_text())["runs"][0]["results"]
        collisions.append(sum(r["collided"] for r in results))
    assert collisions[0] > 0
    assert collisions[1] < collisions[0]
    # the recording (the planner node's GenomePlanner and its guard, in the reference
    # simulator) ends every episode as the table does
    err = capsys.readouterr().err
    assert "recorded 10 episodes" in err and "in the recording" not in err


def test_on_a_scan_map_the_recording_ends_every_episode_as_the_table(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    # the benchmark's headline mode: a plan on the map of its own readings, behind the shim
    # and the guard; recorded through ScanGuidedPlanner, as the planner node's scan_map runs
    out = tmp_path / "eval.json"
    assert mentor_eval([str(UGV_GENOME), "--robot", "ugv", "--seed", "3", "--n", "10",
                        "--scan-map", "--rotation-shim", "45", "--collision-guard",
                        "--record", str(tmp_path / "bag"), "--out", str(out)]) == 0  # fmt: skip
    runs = json.loads(out.read_text())["runs"]
    assert [r["genome"].endswith(" +scan-map") for r in runs] == [False, True]
    assert runs[0]["results"] != runs[1]["results"]  # the map changes the runs
    err = capsys.readouterr().err
    assert "recorded 20 episodes" in err and "in the recording" not in err


def test_deployed_is_the_scan_map_run_behind_the_shim_and_the_guard_alone(
    tmp_path: Path,
) -> None:
    common = [str(UGV_GENOME), "--robot", "ugv", "--seed", "3", "--n", "4", "--label", "ref"]
    # the UGV decides twice per trained period as deployed; the reference genome's is 1 s
    flags = ["--scan-map", "--rotation-shim", "45", "--collision-guard", "--control-period",
             "0.5"]  # fmt: skip
    assert mentor_eval([*common, *flags, "--out", str(tmp_path / "all.json")]) == 0
    assert mentor_eval([*common, "--deployed", "--out", str(tmp_path / "d.json")]) == 0
    every = json.loads((tmp_path / "all.json").read_text())["runs"]
    deployed = json.loads((tmp_path / "d.json").read_text())["runs"]
    assert [r["genome"] for r in deployed] == ["ref +scan-map"]
    assert deployed[0]["results"] == every[1]["results"]


def test_deployed_gives_the_swarm_robot_its_turn_gain_and_view_corridor(tmp_path: Path) -> None:
    # a genome trained without the corridor (the shipped ones read through it as trained)
    genome = ROOT / "bags" / "regression" / "swarm_reference_genome.json"
    common = [str(genome), "--robot", "swarm", "--seed", "3", "--n", "4", "--label", "ref"]
    # the deployed period: twice per trained period, as --deployed decides
    flags = ["--scan-map", "--rotation-shim", "45", "--collision-guard", "--control-period", "0.5"]
    layers = {"both": ["--turn-gain", "0.75", "--view-margin", "0.1"],
              "gained": ["--turn-gain", "0.75"], "cornered": ["--view-margin", "0.1"],
              "plain": []}  # fmt: skip
    for name, extra in layers.items():
        out = tmp_path / f"{name}.json"
        assert mentor_eval([*common, *flags, *extra, "--out", str(out)]) == 0
    # --deployed as it is, and with each of its two layers left out
    deployments = {"d": [], "d_gain1": ["--turn-gain", "1"],
                   "d_nomargin": ["--view-margin", "none"]}  # fmt: skip
    for name, extra in deployments.items():
        out = tmp_path / f"{name}.json"
        assert mentor_eval([*common, "--deployed", *extra, "--out", str(out)]) == 0
    runs = {n: json.loads((tmp_path / f"{n}.json").read_text())["runs"]
            for n in (*layers, *deployments)}  # fmt: skip
    assert runs["d"][0]["results"] == runs["both"][1]["results"]
    assert runs["d_gain1"][0]["results"] == runs["cornered"][1]["results"]
    assert runs["d_nomargin"][0]["results"] == runs["gained"][1]["results"]
    # the corridor changes the runs, and so does the gain
    assert runs["both"][1]["results"] != runs["gained"][1]["results"]
    assert runs["both"][1]["results"] != runs["cornered"][1]["results"]
    assert runs["gained"][1]["results"] != runs["plain"][1]["results"]
