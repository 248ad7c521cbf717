"""mentor-eval --global-plan (each genome also along a global plan, beside its plain run),
--map (the world from a ROS map), --deployment and --set (a rotation shim, a collision guard, a
scan map, the shipped deployment), and their bad input."""

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


#: the sources mentor-eval names in a deployment's errors
NONE = "deployment none with --set"
SHIPPED = "the shipped deployment of ugv with --set"


@pytest.mark.parametrize(
    ("args", "fault"),
    [
        (["--robot", "ugv", "--map", "{tmp}/missing.yaml"], "missing.yaml: no such file"),
        (["--robot", "ugv", "--map", "{tmp}/bad.yaml"], "bad.yaml: missing key 'image'"),
        (["--robot", "ugv", "--world", "{tmp}/w.yaml", "--seed", "3"], "not with --bag"),
        (["--robot", "ugv"], "give --bag, --world, --map or --seed"),
        (["--robot", "ugv", "--seed", "1", "--lookahead", "-1"], "--lookahead must be"),
        (["--robot", "ugv", "--seed", "1", "--lookahead", "1"], "--lookahead: only with --global"),
        (["--robot", "ugv", "--seed", "1", "--set", "stages.rotation_shim.threshold_deg=0"],
         f"mentor-eval: {NONE}: stages.rotation_shim.threshold_deg: must be > 0"),
        (["--robot", "ugv", "--seed", "1", "--deployment", "shipped", "--set",
          "stages.turn_gain.gain=2"],
         f"mentor-eval: {SHIPPED}: stages.turn_gain.gain: must be <= 1"),
        (["--robot", "ugv", "--seed", "1", "--set", "scan_map.clearance_cost=.nan"],
         f"mentor-eval: {NONE}: scan_map.clearance_cost: expected a finite number"),
        (["--robot", "ugv", "--seed", "1", "--set", "stages.warp.speed=2"],
         "stages.warp: no such stage"),
        (["--robot", "ugv", "--seed", "1", "--deployment", "{tmp}/missing.yaml"],
         "missing.yaml: no such file"),
        (["--robot", "ugv", "--seed", "1", "--deployment", "{tmp}/w.yaml"],
         "w.yaml: format: unknown key (known: decisions_per_period, scan_map, stages)"),
        (["--robot", "ugv", "--seed", "1", "--deployment", "{tmp}/list.yaml"],
         "list.yaml: expected a mapping of deployment keys"),
    ],
)
def test_bad_arguments_and_map_files_exit_2_with_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], args: list[str], fault: str
) -> None:
    (tmp_path / "bad.yaml").write_text("resolution: 0.05\n")
    (tmp_path / "list.yaml").write_text("- scan_map\n")
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
    for extra in ([], ["--set", "stages.rotation_shim.threshold_deg=45"]):
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
    guard = ["--set", "stages.collision_guard.memory=3", "--record", str(tmp_path / "bag")]
    for extra in ([], guard):
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


#: the benchmark's headline mode but for the decision split: a plan on the map of its own
#: readings, behind the shim and the guard
MAPPED_SHIM_GUARD = """\
scan_map: {}
stages:
  rotation_shim: {threshold_deg: 45}
  collision_guard: {memory: 3}
"""


def test_on_a_scan_map_the_recording_ends_every_episode_as_the_table(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    # recorded through ScanGuidedPlanner, as the planner node's deployment with a scan map runs
    deployment = tmp_path / "mapped.yaml"
    deployment.write_text(MAPPED_SHIM_GUARD)
    common = [str(UGV_GENOME), "--robot", "ugv", "--seed", "3", "--n", "10", "--label", "ref"]
    out = tmp_path / "eval.json"
    assert mentor_eval([*common, "--deployment", str(deployment), "--record",
                        str(tmp_path / "bag"), "--out", str(out)]) == 0  # fmt: skip
    runs = json.loads(out.read_text())["runs"]
    assert [r["genome"] for r in runs] == ["ref"]  # the deployment's run alone
    err = capsys.readouterr().err
    assert "recorded 10 episodes" in err and "in the recording" not in err
    assert mentor_eval([*common, "--out", str(tmp_path / "plain.json")]) == 0
    plain = json.loads((tmp_path / "plain.json").read_text())["runs"]
    assert plain[0]["results"] != runs[0]["results"]  # the map changes the runs


#: the UGV's shipped deployment, key by key (mentor_core/data/deployments.yaml)
UGV_SHIPPED = ["--set", "decisions_per_period=2", "--set", "scan_map={}",
               "--set", "stages.rotation_shim.threshold_deg=45",
               "--set", "stages.collision_guard.memory=3"]  # fmt: skip


def test_the_shipped_deployment_is_its_keys_and_the_global_plan_runs_beside_it(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    common = [str(UGV_GENOME), "--robot", "ugv", "--seed", "3", "--n", "4", "--label", "ref"]
    assert mentor_eval([*common, *UGV_SHIPPED, "--out", str(tmp_path / "keys.json")]) == 0
    capsys.readouterr()
    shipped = ["--deployment", "shipped", "--global-plan", "--record", str(tmp_path / "bag")]
    assert mentor_eval([*common, *shipped, "--out", str(tmp_path / "d.json")]) == 0
    # recorded at the deployed period (0.5 s), each run ending as in the table
    err = capsys.readouterr().err
    assert "recorded 8 episodes" in err and "in the recording" not in err
    keys = json.loads((tmp_path / "keys.json").read_text())["runs"]
    deployed = json.loads((tmp_path / "d.json").read_text())["runs"]
    assert [r["genome"] for r in keys] == ["ref"]
    assert [r["genome"] for r in deployed] == ["ref", "ref +global-plan"]
    assert deployed[0]["results"] == keys[0]["results"]
    # along the world's grid instead of the scan map: other runs
    assert deployed[1]["results"] != deployed[0]["results"]


#: the Swarm-Robot's shipped deployment but for its two layers on the network, key by key
SWARM_LAYERS = ["--set", "decisions_per_period=2", "--set", "scan_map.clearance_cost=1.0",
                "--set", "stages.rotation_shim.threshold_deg=45",
                "--set", "stages.collision_guard.memory=3"]  # fmt: skip


def test_the_shipped_deployment_gives_the_swarm_robot_its_turn_gain_and_view_corridor(
    tmp_path: Path,
) -> None:
    # a genome trained without the corridor (the shipped ones read through it as trained)
    genome = ROOT / "bags" / "regression" / "swarm_reference_genome.json"
    common = [str(genome), "--robot", "swarm", "--seed", "3", "--n", "4", "--label", "ref"]
    # the view corridor reads the readings, the gain and the shim change the outputs: the
    # shipped order (view_corridor, turn_gain, rotation_shim, collision_guard)
    corridor = ["--set", "stages.view_corridor.margin=0.1"]
    gain = ["--set", "stages.turn_gain.gain=0.75"]
    layers = {"both": [*corridor, *gain], "gained": gain, "cornered": corridor, "plain": []}
    for name, extra in layers.items():
        out = tmp_path / f"{name}.json"
        assert mentor_eval([*common, *extra, *SWARM_LAYERS, "--out", str(out)]) == 0
    # the shipped deployment as it is, and with each of its two layers left out
    deployments = {"d": [], "d_gain1": ["--set", "stages.turn_gain=null"],
                   "d_nomargin": ["--set", "stages.view_corridor=null"]}  # fmt: skip
    for name, extra in deployments.items():
        out = tmp_path / f"{name}.json"
        assert mentor_eval([*common, "--deployment", "shipped", *extra, "--out", str(out)]) == 0
    runs = {n: json.loads((tmp_path / f"{n}.json").read_text())["runs"]
            for n in (*layers, *deployments)}  # fmt: skip
    assert all(len(r) == 1 for r in runs.values())
    assert runs["d"][0]["results"] == runs["both"][0]["results"]
    assert runs["d_gain1"][0]["results"] == runs["cornered"][0]["results"]
    assert runs["d_nomargin"][0]["results"] == runs["gained"][0]["results"]
    # the corridor changes the runs, and so does the gain
    assert runs["both"][0]["results"] != runs["gained"][0]["results"]
    assert runs["both"][0]["results"] != runs["cornered"][0]["results"]
    assert runs["gained"][0]["results"] != runs["plain"][0]["results"]
