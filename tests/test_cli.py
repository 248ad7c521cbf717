"""The commands' arguments, inputs and outputs (issue 17, failures 4, 6 and 7).

Bad arguments and values give one line and exit status 2, never a traceback; an output never
replaces an input nor, without --force, an existing file, and is checked before any work; a
start whose body overlaps a box is skipped alike by mentor-eval and the simulator node.
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest
import yaml
from cli_support import one_line, run

from mentor_core.cli import draw, evaluate, train, xor
from mentor_core.evolution.genome import Genome, genome_from_edges
from mentor_core.files.genome_file import save_genome
from mentor_core.runtime.scenario_plan import ScenarioPlan, load_scenario_source
from mentor_core.sim.robots import get_profile
from mentor_core.sim.world import Scenario, World, save_world

SWARM = get_profile("swarm")
WORLD = World(4.0, np.array([[2.0, 0.0, 2.5, 1.5], [0.0, 3.0, 1.0, 4.0]]), name="test")
# scenario 0: the centre is free, the body's front (0.04 m ahead) is inside box 0
OVERLAPPING = Scenario(WORLD, (1.98, 0.5, 0.0), (3.5, 3.5))
SCENARIOS = [OVERLAPPING, Scenario(WORLD, (3.0, 2.5, math.pi), (0.5, 1.5))]
TINY = {
    "generations": 2, "stage1_generations": 1, "n_scenarios": 3,
    "evolution": {"population_size": 8},
}  # fmt: skip

@pytest.fixture
def no_training(monkeypatch: pytest.MonkeyPatch) -> None:
    """A refused command must not train (an accepted bad config could run for hours)."""

    def refuse(*args: object, **kwargs: object) -> None:
        raise AssertionError("mentor-train started training")

    monkeypatch.setattr(train, "train", refuse)




def homing_genome() -> Genome:
    """Swarm-Robot planner: turn towards sin(bearing) (input 4), full step (bias 6)."""
    return genome_from_edges(6, 2, [(4, 7, 2.0), (6, 8, 1.0)])


@pytest.fixture
def files(tmp_path: Path) -> dict[str, Path]:
    genome = tmp_path / "d" / "g.json"
    save_genome(homing_genome(), genome, metadata={"input_encoding": "egocentric"})
    world = tmp_path / "w.yaml"
    save_world(world, WORLD, SCENARIOS)
    config = tmp_path / "tiny.yaml"
    config.write_text(yaml.safe_dump(TINY))
    return {"genome": genome, "world": world, "config": config}


# ---------------------------------------------------------------- failure 6: one line, exit 2


@pytest.mark.parametrize(
    ("command", "argv", "fault"),
    [
        (train.main, ["--robot", "swarm", "--framework", "dual", "--out", "{tmp}/r",
                      "--seed", "-1"], "argument --seed: expected a whole number >= 0, got -1"),
        (evaluate.main, ["{genome}", "--robot", "swarm", "--seed", "-1"], "--seed"),
        (evaluate.main, ["{genome}", "--robot", "swarm", "--seed", "1", "--n", "-2"],
         "argument --n: expected a whole number >= 1, got -2"),
        (evaluate.main, ["{genome}", "--world", "{world}", "--time-limit", "nan"],
         "--time-limit"),
        (xor.main, ["--seed", "-1"], "--seed"),
        (draw.main, ["--robot", "swarm", "--seed", "-3", "--out", "{tmp}/x.png"], "--seed"),
        (train.main, ["--robot", "swarm", "--framework", "dual"], "required: --out"),
    ],
)  # fmt: skip
@pytest.mark.usefixtures("no_training")
def test_bad_arguments_are_one_line_and_exit_2(
    tmp_path: Path,
    files: dict[str, Path],
    capsys: pytest.CaptureFixture[str],
    command: Callable[..., int],
    argv: list[str],
    fault: str,
) -> None:
    subst = {"{tmp}": str(tmp_path), "{genome}": str(files["genome"]),
             "{world}": str(files["world"])}  # fmt: skip
    for key, value in subst.items():
        argv = [a.replace(key, value) for a in argv]
    assert run(command, argv) == 2
    assert fault in one_line(capsys)
    assert not (tmp_path / "r").exists() and not (tmp_path / "x.png").exists()


def test_a_checkpoint_holding_a_json_list_is_one_line(
    tmp_path: Path, files: dict[str, Path], capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "run"
    out.mkdir()
    (out / "checkpoint.json").write_text("[1, 2]\n")
    argv = ["--robot", "swarm", "--framework", "dual", "--config", str(files["config"]),
            "--out", str(out), "--resume", "--quiet"]  # fmt: skip
    assert run(train.main, argv) == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err
    last = err.strip().splitlines()[-1]  # after the line that says what would run
    assert last == f"mentor-train: {out / 'checkpoint.json'}: expected a JSON object, got an array"


@pytest.mark.usefixtures("no_training")
def test_an_empty_config_file_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    empty = tmp_path / "empty.yaml"
    empty.write_text("# nothing set yet\n")
    argv = ["--robot", "swarm", "--framework", "dual", "--config", str(empty),
            "--out", str(tmp_path / "r"), "--quiet"]  # fmt: skip
    assert run(train.main, argv) == 2
    assert f"{empty}: empty file" in one_line(capsys)
    assert not (tmp_path / "r").exists()


@pytest.mark.parametrize(
    ("text", "fault"),
    [
        ("generations: 12.5\n", "generations: expected a whole number, got 12.5"),
        ("generations: '12'\n", "generations: expected a whole number, got '12'"),
        ("generations: true\n", "generations: expected a whole number, got True"),
        ("n_scenarios: 10.7\n", "n_scenarios: expected a whole number, got 10.7"),
    ],
)
@pytest.mark.usefixtures("no_training")
def test_mentor_train_names_file_and_key_of_a_value_of_the_wrong_type(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], text: str, fault: str
) -> None:
    path = tmp_path / "cfg.yaml"
    path.write_text(text)
    argv = ["--robot", "swarm", "--framework", "single", "--config", str(path),
            "--out", str(tmp_path / "r"), "--quiet"]  # fmt: skip
    assert run(train.main, argv) == 2
    assert f"{path}: {fault}" in one_line(capsys)
    assert not (tmp_path / "r").exists()


# ------------------------------------------- failure 7: a start overlapping a box, skipped alike


def test_a_start_overlapping_a_box_is_skipped_by_mentor_eval_as_by_the_simulator_node(
    tmp_path: Path, files: dict[str, Path], capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "eval.json"
    argv = [str(files["genome"]), "--robot", "swarm", "--world", str(files["world"]),
            "--out", str(out)]  # fmt: skip
    assert run(evaluate.main, argv) == 0
    warnings = [line for line in capsys.readouterr().err.splitlines() if "warning" in line]
    assert len(warnings) == 1
    assert f"{files['world']}: scenario 0 skipped: its body at the start" in warnings[0]
    doc = json.loads(out.read_text())
    assert [r["scenario"] for r in doc["runs"][0]["results"]] == [1]  # numbers kept
    assert [s["scenario"] for s in doc["skipped"]] == [0]
    # the simulator node's plan skips the same scenario, for the same reason
    plan = ScenarioPlan(load_scenario_source(world_file=files["world"]), [("robot_0", SWARM)])
    assert plan.runnable == ((1,),)
    assert len(plan.skipped) == 1 and doc["skipped"][0]["reason"] in plan.skipped[0]


# ------------------------------------------------------- failure 4: outputs never replace inputs


def test_mentor_eval_never_replaces_its_genome_and_checks_outputs_first(
    tmp_path: Path,
    files: dict[str, Path],
    capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    genome = files["genome"]
    before = genome.read_bytes()
    base = [str(genome), "--robot", "swarm", "--world", str(files["world"])]
    for option in ("--out", "--record"):
        for force in ([], ["--force"]):
            assert run(evaluate.main, [*base, option, str(genome), *force]) == 2
            assert f"{option} {genome}: is an input" in one_line(capsys)
    assert genome.read_bytes() == before
    # an existing file: refused before any episode runs, replaced with --force
    out = tmp_path / "eval.json"
    out.write_text("mine\n")

    def no_work(*args: object, **kwargs: object) -> None:
        raise AssertionError("the evaluation ran before the outputs were checked")

    monkeypatch.setattr(evaluate, "assess", no_work)
    assert run(evaluate.main, [*base, "--out", str(out)]) == 2
    assert f"--out {out}: already exists; pass --force" in one_line(capsys)
    assert out.read_text() == "mine\n"
    monkeypatch.undo()
    assert run(evaluate.main, [*base, "--out", str(out), "--force"]) == 0
    assert json.loads(out.read_text())["format"] == "mentor-eval"
    capsys.readouterr()
    assert run(evaluate.main, [*base, "--out", str(tmp_path / "x"), "--record",
                               str(tmp_path / "x")]) == 2  # fmt: skip
    assert "is also the --out output" in one_line(capsys)


def test_mentor_draw_never_replaces_its_world_nor_a_file_without_force(
    tmp_path: Path, files: dict[str, Path], capsys: pytest.CaptureFixture[str]
) -> None:
    world = files["world"]
    before = world.read_bytes()
    for force in ([], ["--force"]):
        argv = ["--robot", "swarm", "--world", str(world), "--out", str(world), *force]
        assert run(draw.main, argv) == 2
        assert f"--out {world}: is an input" in one_line(capsys)
    assert world.read_bytes() == before
    png = tmp_path / "w.png"
    png.write_bytes(b"mine")
    argv = ["--robot", "swarm", "--world", str(world), "--out", str(png)]
    assert run(draw.main, argv) == 2
    assert "already exists; pass --force" in one_line(capsys)
    assert png.read_bytes() == b"mine"
    assert run(draw.main, [*argv, "--force"]) == 0
    assert png.read_bytes()[:4] == b"\x89PNG"


# ------------------------------------------------------- --set: one config key on the command line


@pytest.mark.parametrize(
    ("overrides", "fault"),
    [
        (["n_scenarios"], "--set: expected KEY=VALUE (a dotted key path), got 'n_scenarios'"),
        (["=3"], "--set: expected KEY=VALUE"),
        (["evolution..x=1"], "--set: expected KEY=VALUE"),
        (["robot=ugv"], "--set: robot: set with --robot, not --set"),
        (["seed=4"], "--set: seed: set with --seed, not --set"),
        (["families=[rooms"], "--set: families: '[rooms' is not a YAML value"),
        (["n_scenarios=0"], "tiny.yaml with --set: n_scenarios: must be >= 1, got 0"),
        (["evolution.populaton_size=3"], "with --set: evolution.populaton_size: unknown key"),
        (["n_scenarios=4", "generations=2.5"], "generations: expected a whole number, got 2.5"),
    ],
)
@pytest.mark.usefixtures("no_training")
def test_a_bad_set_is_one_line_and_trains_nothing(
    tmp_path: Path, files: dict[str, Path], capsys: pytest.CaptureFixture[str],
    overrides: list[str], fault: str,
) -> None:  # fmt: skip
    argv = ["--robot", "swarm", "--framework", "dual", "--config", str(files["config"]),
            "--out", str(tmp_path / "r"), "--quiet"]  # fmt: skip
    for item in overrides:
        argv += ["--set", item]
    assert run(train.main, argv) == 2
    assert fault in one_line(capsys)
    assert not (tmp_path / "r").exists()


def test_set_changes_keys_on_top_of_the_config_and_the_run_records_them(
    tmp_path: Path, files: dict[str, Path], capsys: pytest.CaptureFixture[str]
) -> None:
    sets = ["n_scenarios=2", "evolution.mutation.recurrent_rate=0.05", "doe.wall_count=[0, 1]"]
    config = train.resolve_config("swarm", "dual", str(files["config"]), sets)
    assert (config.n_scenarios, config.generations) == (2, TINY["generations"])
    assert config.evolution.population_size == 8  # the file's, beside the new mutation key
    assert config.evolution.mutation.recurrent_rate == 0.05
    assert config.doe.wall_count == (0, 1)
    out = tmp_path / "run"
    argv = ["--robot", "swarm", "--framework", "dual", "--config", str(files["config"]),
            "--out", str(out), "--quiet", "--seed", "3"]  # fmt: skip
    for item in sets:
        argv += ["--set", item]
    assert run(train.main, argv) == 0
    recorded = yaml.safe_load((out / "config.yaml").read_text())
    assert recorded["n_scenarios"] == 2 and recorded["seed"] == 3
    assert recorded["evolution"]["mutation"]["recurrent_rate"] == 0.05
    capsys.readouterr()
    # resuming with other settings than the run's is refused
    assert run(train.main, [*argv[:-6], "--resume", "--set", "n_scenarios=3"]) == 2
    assert "different config" in capsys.readouterr().err.strip().splitlines()[-1]
    # the run's config.yaml holds what --set changed: no --set needed to resume from it
    again = ["--robot", "swarm", "--framework", "dual", "--config", str(out / "config.yaml"),
             "--out", str(out), "--quiet", "--resume"]  # fmt: skip
    assert run(train.main, again) == 0
    assert "holds a finished run" in capsys.readouterr().err
