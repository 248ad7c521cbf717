"""mentor-bench (cli/bench.py) end to end on a small suite, its result file
(benchmark/document.py), mentor-report --bench, and bad input: one line, exit 2."""

from __future__ import annotations

import copy
import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from mentor_core.benchmark.document import load_bench
from mentor_core.cli.bench import main as bench_main
from mentor_core.cli.report import main as report_main
from mentor_core.errors import FileFormatError
from mentor_core.report.bench import bench_markdown, seed_groups
from mentor_core.training.config import shipped_config

ROOT = Path(__file__).resolve().parents[1]
UGV_GENOME = ROOT / "bags" / "regression" / "ugv_reference_genome.json"
SWARM_PLANNER = ROOT / "planners" / "swarm-paper-dual-s1.json"


@pytest.fixture(scope="module")
def bench_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("bench") / "ugv"
    code = bench_main([str(UGV_GENOME), "--label", "ref", "--robot", "ugv", "--families",
                       "slalom,traps", "--pairs-per-family", "2", "--baseline-limits",
                       "reference", "--out", str(out)])  # fmt: skip
    assert code == 0
    return out


def test_bench_writes_the_table_json_and_markdown(
    bench_dir: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    doc = load_bench(bench_dir / "bench.json")
    assert [c["name"] for c in doc["contenders"]] == ["ref", "vfh", "bug", "oracle"]
    assert [c["kind"] for c in doc["contenders"]] == ["evolved", "baseline", "baseline",
                                                      "oracle"]
    assert doc["families"] == ["slalom", "traps"] and len(doc["pairs"]) == 4
    assert doc["contenders"][0]["settings"]["step_max"] == 0.5  # the genome's own metadata
    for c in doc["contenders"]:
        for limit in ("paper", "scaled"):
            overall = c["scores"][limit]["overall"]
            assert 0.0 <= overall["success"] <= 1.0
            assert overall["success"] + overall["collision"] + overall["timeout"] == (
                pytest.approx(1.0))
            per_pair = [r["reached"] for r in c["results"]]
            if limit == "paper":
                assert overall["success"] <= sum(per_pair) / 4
    md = (bench_dir / "bench.md").read_text()
    assert "| slalom |" in md and "| **overall** |" in md
    # the evolved planner head to head with the best of vfh and bug in each family
    ref, vfh, bug = doc["contenders"][:3]
    for family in ("slalom", "traps"):
        best = max(vfh["scores"]["paper"][family]["success"],
                   bug["scores"]["paper"][family]["success"])
        mine = ref["scores"]["paper"][family]["success"]
        assert f"| {family} | {100 * mine:.1f} % / " in md
        assert f"| {100 * best:.1f} % (" in md
    assert "`ref` leads or ties the best baseline on success in" in md
    # where its SPL goes: its paths and the best baseline's on the pairs both reached
    assert "Where SPL goes" in md
    assert "| family | pairs both reached | `ref` | baseline of the highest SPL |" in md
    for png in ("bench_success.png", "bench_success_scaled.png", "bench_trajectories.png"):
        assert (bench_dir / png).stat().st_size > 1000
        assert f"({png})" in md


def test_report_includes_a_benchmark(bench_dir: Path, tmp_path: Path) -> None:
    assert report_main(["--bench", str(bench_dir / "bench.json"), "--out",
                        str(tmp_path / "rep")]) == 0  # fmt: skip
    text = (tmp_path / "rep" / "report.md").read_text()
    assert "## Benchmark: ugv, validation split" in text
    assert (tmp_path / "rep" / "bench0-bench_success.png").exists()


def test_corrupt_result_files_are_named(bench_dir: Path, tmp_path: Path) -> None:
    doc = json.loads((bench_dir / "bench.json").read_text())
    doc["contenders"][1]["results"] = doc["contenders"][1]["results"][:-1]
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps(doc))
    with pytest.raises(FileFormatError, match=r"bad\.json: contenders\[1\] must have one"):
        load_bench(bad)
    bad.write_text("{not json")
    with pytest.raises(FileFormatError, match="not valid JSON"):
        load_bench(bad)
    assert report_main(["--bench", str(bad), "--out", str(tmp_path / "r")]) == 2


#: a deployment file that is not a mapping of deployment keys
NOT_A_MAPPING = "- decisions_per_period\n"
#: mentor-bench's sources of a deployment's errors
SHIPPED = "the shipped deployment of ugv with --set"
NONE = "deployment none with --set"


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--robot", "ugv", "--families", "caves"], "unknown world family 'caves'"),
        (["--robot", "ugv", "--pairs-per-family", "0"], "--pairs-per-family must be in 1..100000"),
        (["--robot", "tank"], "unknown robot 'tank'"),
        (["--robot", "ugv", "--baselines", "astar"], "unknown baseline 'astar'"),
        (["missing.json", "--robot", "ugv"], "missing.json"),
        ([str(UGV_GENOME), "--robot", "swarm"], "ugv_reference_genome.json"),
        ([str(UGV_GENOME), str(UGV_GENOME), "--robot", "ugv"], "same label"),
        (["--robot", "ugv", "--baseline-limits", "fast"], "--baseline-limits: expected"),
        (["--robot", "ugv", "--baseline-limits", "shipped,shipped"], "--baseline-limits"),
        # a deployment's bad value: one line naming its source and the key
        (["--robot", "ugv", "--set", "scan_map.lookahead=-1"],
         f"{NONE}: scan_map.lookahead: must be > 0"),
        (["--robot", "ugv", "--deployment", "shipped", "--set", "scan_map.clearance_cost=-1"],
         f"{SHIPPED}: scan_map.clearance_cost: must be >= 0"),
        (["--robot", "ugv", "--deployment", "shipped", "--set", "stages.turn_gain.gain=2"],
         f"{SHIPPED}: stages.turn_gain.gain: must be <= 1"),
        (["--robot", "ugv", "--set", "stages.rotation_shim.threshold_deg=0"],
         f"{NONE}: stages.rotation_shim.threshold_deg: must be > 0"),
        (["--robot", "ugv", "--set", "stages.collision_guard.memory=0"],
         f"{NONE}: stages.collision_guard.memory: must be >= 1"),
        (["--robot", "ugv", "--deployment", "shipped", "--set", "decisions_per_period=0"],
         f"{SHIPPED}: decisions_per_period: must be >= 1"),
        (["--robot", "ugv", "--set", "stages.warp.speed=2"], "stages.warp: no such stage"),
        (["--robot", "ugv", "--set", "warp=1"], "warp: unknown key"),
        (["--robot", "ugv", "--set", "stages.turn_gain"], "--set: expected KEY=VALUE"),
        (["--robot", "ugv", "--deployment", "{tmp}/missing.yaml"], "missing.yaml: no such file"),
        (["--robot", "ugv", "--deployment", "{tmp}/list.yaml"],
         "list.yaml: expected a mapping of deployment keys"),
        # the plan's least margin lies within its whole margin (a footprint radius)
        (["--robot", "swarm", "--families", "doe", "--pairs-per-family", "1", "--no-oracle",
          "--deployment", "shipped", "--set", "scan_map.least_margin=0.5"],
         "scan_map.least_margin: must be at most the plan's whole margin"),
        (["--robot", "ugv", "--deployment", "shipped", "--set", "scan_map.least_margin=0.5"],
         "scan_map.least_margin: must be at most the plan's whole margin"),
        (["--robot", "ugv", "--workers", "0"], "--workers must be >= 1"),
    ],
)
def test_bad_input_is_one_line_and_exit_2(
    args: list[str], message: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    (tmp_path / "list.yaml").write_text(NOT_A_MAPPING)
    assert bench_main([a.format(tmp=tmp_path) for a in args]) == 2
    err = capsys.readouterr().err.strip()
    assert message in err and len(err.splitlines()) == 1


def _without_seconds(doc: Any) -> Any:
    if isinstance(doc, dict):
        return {k: _without_seconds(v) for k, v in doc.items() if k != "seconds"}
    if isinstance(doc, list):
        return [_without_seconds(v) for v in doc]
    return doc


def test_workers_give_the_same_results_as_one_process(
    bench_dir: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    capsys.readouterr()
    out = tmp_path / "two"
    assert bench_main([str(UGV_GENOME), "--label", "ref", "--robot", "ugv", "--families",
                       "slalom,traps", "--pairs-per-family", "2", "--baseline-limits",
                       "reference", "--workers", "2", "--out", str(out)]) == 0  # fmt: skip
    assert "on 2 worker processes" in capsys.readouterr().err
    one = json.loads((bench_dir / "bench.json").read_text())
    two = json.loads((out / "bench.json").read_text())
    assert _without_seconds(two) == _without_seconds(one)  # trajectories included
    assert (out / "bench.md").read_text() == (bench_dir / "bench.md").read_text()


def test_baselines_chosen_on_another_run_add_a_second_head_to_head(
    bench_dir: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    capsys.readouterr()
    chooser = bench_dir / "bench.json"
    out = tmp_path / "chosen"
    args = [str(UGV_GENOME), "--label", "ref", "--robot", "ugv", "--families", "slalom",
            "--pairs-per-family", "2", "--baseline-limits", "reference",
            "--baselines-chosen-on", str(chooser)]
    assert bench_main([*args, "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    assert f"head to head with the baseline best on the validation split ({chooser})" in printed
    doc = load_bench(out / "bench.json")
    choice = doc["baseline_choice"]
    assert choice["source"] == str(chooser) and choice["split"] == "validation"
    assert set(choice["choice"]) == {"slalom", "traps", "overall"}
    assert choice["choice"]["slalom"]["success"] in ("vfh", "bug")
    assert "chosen baseline: success" in (out / "bench.md").read_text()
    # a run that lacks a chosen variant, or of another robot, is refused before it starts
    capsys.readouterr()
    assert bench_main([*args, "--baselines", "none"]) == 2
    err = capsys.readouterr().err
    assert "is not in this run" in err and len(err.strip().splitlines()) == 1
    assert bench_main(["--robot", "swarm", "--baselines-chosen-on", str(chooser)]) == 2
    assert "a run of 'ugv', not 'swarm'" in capsys.readouterr().err
    doc["baseline_choice"] = {"choice": {"slalom": "vfh"}}
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps(doc))
    with pytest.raises(FileFormatError, match="baseline_choice must map"):
        load_bench(bad)


def test_out_must_not_be_a_file(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    target = tmp_path / "taken"
    target.write_text("keep me")
    assert bench_main(["--robot", "ugv", "--families", "doe", "--pairs-per-family", "1",
                       "--out", str(target)]) == 2  # fmt: skip
    assert target.read_text() == "keep me"
    assert "not a directory" in capsys.readouterr().err


def test_baselines_act_within_the_reference_or_the_shipped_limits(tmp_path: Path) -> None:
    out = tmp_path / "limits"
    code = bench_main(["--robot", "ugv", "--families", "doe", "--pairs-per-family", "1",
                       "--baselines", "vfh", "--no-oracle", "--baseline-limits",
                       "reference,shipped", "--out", str(out)])  # fmt: skip
    assert code == 0
    doc = load_bench(out / "bench.json")
    assert [c["name"] for c in doc["contenders"]] == ["vfh", "vfh-shipped"]
    reference, shipped = (c["settings"] for c in doc["contenders"])
    assert reference["step_max"] == doc["reference"]["step_max"] == 0.5
    assert shipped["step_max"] == shipped_config("ugv").step_max
    md = (out / "bench.md").read_text()
    assert "| `vfh` | baseline | 0.02-0.5 m, ±45° every 1 s | paper |" in md
    assert (f"| `vfh-shipped` | baseline | 0.02-{shipped['step_max']:.3g} m, ±45° every "
            f"{shipped['control_period']:.3g} s |") in md


@pytest.mark.parametrize(("robot", "names"), [("ugv", ["vfh", "vfh-shipped"]),
                                               ("swarm", ["vfh"])])
def test_by_default_baselines_also_act_as_the_shipped_planners_where_they_differ(
    tmp_path: Path, robot: str, names: list[str]
) -> None:
    """The shipped UGV planners decide every 0.5 s, the reference planner every 1 s: the
    baselines run within both; the Swarm-Robot's shipped limits are the reference's."""
    out = tmp_path / robot
    assert bench_main(["--robot", robot, "--families", "doe", "--pairs-per-family", "1",
                       "--baselines", "vfh", "--no-oracle", "--out", str(out)]) == 0
    doc = load_bench(out / "bench.json")
    assert [c["name"] for c in doc["contenders"]] == names
    assert doc["contenders"][-1]["settings"]["control_period"] == (
        shipped_config(robot).control_period or 1.0)


def test_seeds_of_a_planner_are_summarised_beside_the_baselines(
    bench_dir: Path, tmp_path: Path
) -> None:
    doc = load_bench(bench_dir / "bench.json")
    evolved = doc["contenders"][0]
    seeds = []
    for seed, success in ((1, 0.5), (2, 1.0), (3, 0.0)):
        c = copy.deepcopy(evolved)
        c["name"] = f"dual-s{seed}"
        for limit in ("paper", "scaled"):
            c["scores"][limit]["overall"].update(success=success, spl=success / 2)
        seeds.append(c)
    lone = copy.deepcopy(evolved) | {"name": "other-s4"}  # one seed: no group
    doc["contenders"] = [*seeds, lone, *doc["contenders"][1:]]
    assert seed_groups(doc["contenders"]) == {"dual": [0, 1, 2]}
    md = "\n".join(bench_markdown(doc, tmp_path))
    assert "| family | dual (3 seeds) | vfh (baseline) | bug (baseline) | oracle (oracle) |" in md
    # mean 50 %, sample sd 50 %; SPL 0.25 +- 0.25
    assert "| **overall** | 50 ± 50 % / 0.25 ± 0.25 |" in md


def test_a_scan_map_runs_each_genome_and_adds_each_baseline_on_the_map_of_what_it_read(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A deployment with a scan map: the genome steers only to the carrot of its plan (named
    by its label), each baseline plain and as ``mapped-<baseline>``."""
    common = [str(UGV_GENOME), "--label", "ref-s1", "--robot", "ugv", "--families", "rooms",
              "--pairs-per-family", "2", "--baselines", "vfh", "--no-oracle",
              "--baseline-limits", "reference"]  # fmt: skip
    deployment = tmp_path / "mapped.yaml"
    deployment.write_text("scan_map: {}\n")
    assert bench_main([*common, "--deployment", str(deployment), "--out",
                       str(tmp_path / "mapped")]) == 0  # fmt: skip
    doc = load_bench(tmp_path / "mapped" / "bench.json")
    names = [c["name"] for c in doc["contenders"]]
    assert names == ["ref-s1", "vfh", "mapped-vfh"]
    assert [c["kind"] for c in doc["contenders"]] == ["evolved", "baseline", "baseline"]
    # printed too: the evolved planner against the best of vfh and mapped-vfh
    printed = capsys.readouterr().out
    assert "head to head with the best baseline, ugv, validation split, limit 50 s" in printed
    assert "`ref-s1` leads or ties" in printed
    assert "paths on the pairs both reached with the baseline of the highest SPL" in printed
    assert "| family | pairs both reached | `ref-s1` |" in printed
    mapped = doc["contenders"][0]
    assert bench_main([*common, "--baselines", "none", "--out", str(tmp_path / "plain")]) == 0
    plain = load_bench(tmp_path / "plain" / "bench.json")["contenders"][0]
    # the same planner, steered elsewhere: its trajectories differ
    assert any(a["trajectory"] != b["trajectory"]
               for a, b in zip(plain["results"], mapped["results"], strict=True))  # fmt: skip
    # the guide is recorded: the carrot 1.5 goal radii (the UGV's: 1 m) along the plan,
    # cells of 5 cm
    assert "scan_map" not in plain and "scan_map" not in doc["contenders"][1]
    for c in (mapped, doc["contenders"][2]):
        assert c["scan_map"]["lookahead"] == pytest.approx(1.5)
        assert c["scan_map"]["resolution"] == pytest.approx(0.05)


def test_the_deployments_lookahead_moves_the_carrot_on_the_scan_map(tmp_path: Path) -> None:
    out = tmp_path / "near"
    assert bench_main([str(UGV_GENOME), "--robot", "ugv", "--families", "rooms",
                       "--pairs-per-family", "2", "--baselines", "none", "--no-oracle",
                       "--set", "scan_map.lookahead=0.75", "--out", str(out)]) == 0  # fmt: skip
    doc = load_bench(out / "bench.json")
    [mapped] = doc["contenders"]
    assert mapped["name"] == str(UGV_GENOME)  # its label: no prefix for a deployment's map
    assert mapped["scan_map"]["lookahead"] == mapped["scan_map"]["replan_distance"] == 0.75
    assert mapped["scan_map"]["clearance_cost"] == 0.0  # the UGV's plan keeps a hard disc


def test_clearance_cost_on_the_scan_map_is_the_deployments(tmp_path: Path) -> None:
    docs = {}
    for name, extra in (("default", []), ("given", ["--set", "scan_map.clearance_cost=2",
                                                    "--set", "scan_map.least_margin=0.01",
                                                    "--set", "stages.turn_gain=null"])):
        out = tmp_path / name
        assert bench_main([str(SWARM_PLANNER), "--robot", "swarm", "--families", "doe",
                           "--pairs-per-family", "2", "--baselines", "vfh", "--no-oracle",
                           "--deployment", "shipped", *extra, "--out", str(out)]) == 0
        docs[name] = load_bench(out / "bench.json")["contenders"]
    # the Swarm-Robot's: a weight of 1, half a footprint radius (0.025 m) kept at least; the
    # evolved planner and the baselines on their scan map plan alike
    mapped = [c for c in docs["default"] if "scan_map" in c]
    assert [c["name"] for c in mapped][:2] == [str(SWARM_PLANNER), "mapped-vfh"]
    for c in mapped:
        assert c["scan_map"]["clearance_cost"] == 1.0
        assert c["scan_map"]["least_margin"] == pytest.approx(0.025)
    given = [c["scan_map"] for c in docs["given"] if "scan_map" in c]
    assert len(given) == len(mapped)
    assert all(g["clearance_cost"] == 2.0 and g["least_margin"] == 0.01 for g in given)
    # --set stages.turn_gain=null leaves the shipped gain on the turn out, and nothing else
    shipped, without = docs["default"][0]["settings"], docs["given"][0]["settings"]
    assert shipped["turn_gain"] == 0.75 and "turn_gain" not in without
    assert {k: v for k, v in shipped.items() if k != "turn_gain"} == without


def test_a_rotation_shim_turns_each_genome_onto_its_goal_first(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    common = [str(UGV_GENOME), "--label", "ref-s1", "--robot", "ugv", "--families", "doe",
              "--pairs-per-family", "5", "--baselines", "vfh", "--no-oracle",
              "--baseline-limits", "reference"]  # fmt: skip
    docs = {}
    for name, extra in (("plain", []),
                        ("shim", ["--set", "stages.rotation_shim.threshold_deg=45"])):
        assert bench_main([*common, *extra, "--out", str(tmp_path / name)]) == 0
        docs[name] = load_bench(tmp_path / name / "bench.json")["contenders"]
    assert [c["name"] for c in docs["shim"]] == ["ref-s1", "vfh"]  # no variant of a baseline
    plain, shim = docs["plain"][0], docs["shim"][0]
    assert shim["settings"]["rotation_shim"] == pytest.approx(math.pi / 4)
    assert "rotation_shim" not in plain["settings"]
    assert docs["plain"][1] == docs["shim"][1] | {"seconds": docs["plain"][1]["seconds"]}
    smallest = shim["settings"]["step_min"]

    def first_step(result: dict[str, Any]) -> float:
        path = np.asarray(result["trajectory"], dtype=np.float64)
        return float(np.hypot(*(path[1, :2] - path[0, :2])))

    # a start facing away from the goal: the shimmed genome turns on the spot first
    turned = [first_step(b) <= smallest + 1e-9 < first_step(a)
              for a, b in zip(plain["results"], shim["results"], strict=True)]  # fmt: skip
    assert any(turned)
    capsys.readouterr()
    assert bench_main([str(UGV_GENOME), "--robot", "ugv", "--set",
                       "stages.rotation_shim.threshold_deg=181"]) == 2  # fmt: skip
    err = capsys.readouterr().err
    assert "stages.rotation_shim.threshold_deg" in err and len(err.strip().splitlines()) == 1


def test_a_collision_guard_runs_each_genome_and_adds_each_baseline_behind_the_guard(
    bench_dir: Path, tmp_path: Path
) -> None:
    deployment = tmp_path / "guard.yaml"
    deployment.write_text("stages:\n  collision_guard: {memory: 3}\n")
    out = tmp_path / "guard"
    code = bench_main([str(UGV_GENOME), "--label", "ref-s1", "--robot", "ugv", "--families",
                       "forest_dense", "--pairs-per-family", "5", "--baselines", "vfh",
                       "--baseline-limits", "reference", "--deployment", str(deployment),
                       "--out", str(out)])  # fmt: skip
    assert code == 0
    doc = load_bench(out / "bench.json")
    names = [c["name"] for c in doc["contenders"]]
    assert names == ["ref-s1", "vfh", "guard-vfh", "oracle"]  # never the oracle behind it
    by_name = {c["name"]: c for c in doc["contenders"]}
    for name in ("ref-s1", "guard-vfh"):
        assert by_name[name]["settings"]["collision_guard"] is True
        assert "guard_memory" not in by_name[name]["settings"]  # the default memory
    for name in ("vfh", "oracle"):
        assert "collision_guard" not in by_name[name]["settings"]
    # as trained (the default deployment, none): no guard
    assert "collision_guard" not in load_bench(bench_dir / "bench.json")["contenders"][0][
        "settings"]
    for c in doc["contenders"]:  # lengths driven, steps back included, are never negative
        assert all(r["path_length"] >= 0.0 for r in c["results"])
    # a guard of another memory is recorded as such
    memory = tmp_path / "memory"
    assert bench_main([str(UGV_GENOME), "--robot", "ugv", "--families", "doe",
                       "--pairs-per-family", "1", "--baselines", "none", "--no-oracle",
                       "--set", "stages.collision_guard.memory=5",
                       "--out", str(memory)]) == 0  # fmt: skip
    settings = load_bench(memory / "bench.json")["contenders"][0]["settings"]
    assert settings["collision_guard"] is True and settings["guard_memory"] == 5


#: the UGV's shipped deployment, key by key (mentor_core/data/deployments.yaml)
UGV_SHIPPED = ["--set", "decisions_per_period=2", "--set", "scan_map={}",
               "--set", "stages.rotation_shim.threshold_deg=45",
               "--set", "stages.collision_guard.memory=3"]  # fmt: skip


def test_the_shipped_deployment_runs_each_genome_only_as_deployed(tmp_path: Path) -> None:
    """--deployment shipped: the UGV genome deciding twice per trained period on its scan map
    behind the shim (45 deg) and the guard, and the baselines plain, guarded, on their scan
    map and both; each the same run as with its keys given one by one."""
    common = [str(UGV_GENOME), "--label", "ref-s1", "--robot", "ugv", "--families", "rooms",
              "--pairs-per-family", "2", "--baselines", "vfh", "--baseline-limits",
              "reference", "--no-oracle"]  # fmt: skip
    assert bench_main([*common, "--deployment", "shipped", "--out", str(tmp_path / "d")]) == 0
    assert bench_main([*common, *UGV_SHIPPED, "--out", str(tmp_path / "keys")]) == 0
    deployed = load_bench(tmp_path / "d" / "bench.json")["contenders"]
    keys = {c["name"]: c for c in load_bench(tmp_path / "keys" / "bench.json")["contenders"]}
    assert [c["name"] for c in deployed] == [
        "ref-s1", "vfh", "guard-vfh", "mapped-vfh", "mapped-guard-vfh"]
    assert list(keys) == [c["name"] for c in deployed]
    for c in deployed:
        assert c["results"] == keys[c["name"]]["results"], c["name"]
        assert c["settings"] == keys[c["name"]]["settings"], c["name"]
        assert c.get("scan_map") == keys[c["name"]].get("scan_map"), c["name"]
    # the reference genome was trained to decide every 1 s (the robot's period)
    settings = deployed[0]["settings"]
    assert settings["control_period"] == 0.5 and settings["collision_guard"] is True
    assert settings["rotation_shim"] == pytest.approx(math.pi / 4)
    assert deployed[0]["scan_map"]["lookahead"] == pytest.approx(1.5)
    assert deployed[1]["settings"]["control_period"] == 1.0  # the baselines' own period
