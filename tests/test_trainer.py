"""The trainer: run directory, dual-stage switch, resume, backends, bad configs."""

from __future__ import annotations

import csv
import dataclasses
import json
from pathlib import Path

import numpy as np
import pytest

from mentor_core.errors import ConfigError, FileFormatError
from mentor_core.files.genome_file import load_genome_and_metadata
from mentor_core.sim.robots import get_profile, sensor_record
from mentor_core.training.config import TrainerConfig
from mentor_core.training.evaluators import InProcessEvaluator, PoolEvaluator
from mentor_core.training.run_files import load_population
from mentor_core.training.trainer import make_problem, train

TINY = {
    "robot": "swarm",
    "framework": "dual",
    "generations": 4,
    "stage1_generations": 2,
    "n_scenarios": 3,
    "evolution": {"population_size": 8},
}


def tiny(**changes: object) -> TrainerConfig:
    return TrainerConfig.from_dict({**TINY, **changes})


def history_rows(run: Path) -> list[dict[str, str]]:
    with (run / "history.csv").open() as handle:
        return list(csv.DictReader(handle))


def without_seconds(rows: list[dict[str, str]]) -> list[dict[str, str]]:
    return [{k: v for k, v in r.items() if k != "seconds"} for r in rows]


@pytest.fixture(scope="module")
def dual_run(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("dual")
    train(tiny(), out, seed=3)
    return out


def test_run_directory_holds_what_the_brief_lists(dual_run: Path) -> None:
    for name in ("config.yaml", "checkpoint.json", "history.csv", "population.json",
                 "pareto.json", "best_genome.json"):
        assert (dual_run / name).is_file(), name
    rows = history_rows(dual_run)
    assert [r["mode"] for r in rows] == ["multi", "multi", "single", "single"]
    assert [int(r["evaluations"]) for r in rows] == [8, 16, 24, 32]
    members = load_population(dual_run / "population.json")
    assert len(members) == 8
    genome, meta = load_genome_and_metadata(dual_run / "best_genome.json")
    assert genome.n_inputs == 6 and genome.n_outputs == 2
    # the planner node and mentor-eval feed the network as in training
    assert meta["input_encoding"] == "egocentric" == make_problem(tiny()).profile.input_encoding
    assert make_problem(tiny(input_encoding="paper")).profile.input_encoding == "paper"
    assert meta["heading_change_max"] == make_problem(tiny()).profile.heading_change_max
    narrow = make_problem(tiny(heading_change_max_deg=45)).profile
    assert narrow.heading_change_max == pytest.approx(np.pi / 4)
    assert meta["step_max"] == make_problem(tiny()).profile.step_max
    assert meta["sensors"] == sensor_record(make_problem(tiny()).profile)
    assert make_problem(tiny(step_max=0.04)).profile.step_max == 0.04
    assert (meta["step_min"], meta["clearance_margin"]) == (get_profile("swarm").step_min, None)
    guarded = make_problem(tiny(step_min=0.0, clearance_margin=0.05)).profile
    assert (guarded.step_min, guarded.clearance_margin) == (0.0, 0.05)
    with pytest.raises(ConfigError, match="step_min"):  # above the robot's step_max
        make_problem(tiny(step_min=0.5))
    with pytest.raises(ConfigError, match="step_max"):  # beyond the robot's own
        make_problem(tiny(step_max=1.0))
    spread = make_problem(tiny(training_worlds=2)).scenarios
    assert len({sc.world.name for sc in spread}) == 2
    with pytest.raises(ConfigError, match="training_worlds"):  # the Swarm-Robot's 20 scenarios
        make_problem(tiny(n_scenarios=None, training_worlds=21))
    plain = make_problem(tiny()).scenarios[0].world
    walled = TrainerConfig.from_dict({**tiny().to_dict(), "doe": {"wall_count": [2, 2]}})
    world = make_problem(walled).scenarios[0].world
    long_side = np.maximum(*(world.obstacles[:, 2:] - world.obstacles[:, :2]).T)
    assert (long_side >= 0.35 * world.size).sum() == 2 and world != plain
    pareto = json.loads((dual_run / "pareto.json").read_text())
    assert pareto["front"] and len(pareto["points"]) == 8


def test_single_and_dual_get_the_same_evaluations(dual_run: Path, tmp_path: Path) -> None:
    train(tiny(framework="single"), tmp_path, seed=3)
    single = history_rows(tmp_path)
    assert [r["evaluations"] for r in single] == [r["evaluations"] for r in history_rows(dual_run)]
    assert {r["mode"] for r in single} == {"single"}


def test_resume_ends_identical_to_an_unbroken_run(dual_run: Path, tmp_path: Path) -> None:
    train(tiny(), tmp_path, seed=3, stop_after=1)  # "killed" in stage 1
    train(tiny(), tmp_path, seed=3, resume=True, stop_after=2)  # killed again in stage 2
    train(tiny(), tmp_path, seed=3, resume=True)
    assert without_seconds(history_rows(tmp_path)) == without_seconds(history_rows(dual_run))
    assert (tmp_path / "best_genome.json").read_text() == (
        dual_run / "best_genome.json"
    ).read_text()


def test_existing_run_is_not_overwritten_without_resume(dual_run: Path) -> None:
    before = (dual_run / "history.csv").read_text()
    with pytest.raises(FileFormatError, match="already holds a finished run"):
        train(tiny(), dual_run, seed=3)
    assert (dual_run / "history.csv").read_text() == before


def test_resume_with_another_seed_is_refused(dual_run: Path) -> None:
    with pytest.raises(FileFormatError, match="different config or seed"):
        train(tiny(), dual_run, seed=4, resume=True)


def test_resume_checks_the_sensors_and_takes_older_checkpoints(
    dual_run: Path, tmp_path: Path
) -> None:
    train(tiny(), tmp_path, seed=3, stop_after=1)
    checkpoint = tmp_path / "checkpoint.json"
    state = json.loads(checkpoint.read_text())
    assert state["sensors"] == sensor_record(make_problem(tiny()).profile)
    state["sensors"]["sensors"][0][2] += 0.1  # a mount turned since
    checkpoint.write_text(json.dumps(state))
    with pytest.raises(FileFormatError, match="other robot sensors"):
        train(tiny(), tmp_path, seed=3, resume=True)
    # written before the sensor record and the newer config keys: resumed as it was meant
    del state["sensors"]
    for key in ("training_worlds", "step_max", "step_min", "clearance_margin", "doe",
                "novelty_neighbours", "novelty_archive_growth", "success_credit", "guide",
                "refinement"):
        del state["config"][key]
    del state["config"]["evolution"]["mutation"]["recurrent_rate"]
    checkpoint.write_text(json.dumps(state))
    train(tiny(), tmp_path, seed=3, resume=True)
    assert without_seconds(history_rows(tmp_path)) == without_seconds(history_rows(dual_run))


@pytest.mark.parametrize("extra", [{}, {"goal_distance": "geodesic", "turn_commitment": True},
                                   {"success_credit": "path"}, {"guide": "waypoint"}])
def test_pool_backend_is_bit_identical_to_in_process(extra: dict[str, object]) -> None:
    config = dataclasses.replace(tiny(), **extra) if extra else tiny()
    problem = make_problem(config)
    from mentor_core.evolution.loop import Evolution

    evo = Evolution(config.evolution, problem.n_inputs, 2, seed=0, objectives=2)
    genomes = evo.ask()
    serial = InProcessEvaluator(problem).evaluate(genomes)
    with PoolEvaluator(problem, workers=2) as pool:
        parallel = pool.evaluate(genomes)
    assert np.array_equal(serial.objectives, parallel.objectives)
    assert np.array_equal(serial.success_rate, parallel.success_rate)


@pytest.mark.parametrize(
    ("changes", "key"),
    [
        ({"framework": "triple"}, "framework"),
        ({"stage1_generations": 4}, "stage1_generations"),
        ({"generations": 0}, "generations"),
        ({"stage2_seed_fraction": 0.0}, "stage2_seed_fraction"),
        ({"bogus": 1}, "bogus"),
        ({"input_encoding": "polar"}, "input_encoding"),
        ({"heading_change_max_deg": 270}, "heading_change_max_deg"),
        ({"step_max": 0}, "step_max"),
        ({"step_max": True}, "step_max"),
        ({"step_min": -0.01}, "step_min"),
        ({"clearance_margin": "wide"}, "clearance_margin"),
        ({"clearance_margin": -1}, "clearance_margin"),
        ({"training_worlds": 0}, "training_worlds"),
        ({"n_scenarios": 2, "training_worlds": 3}, "training_worlds"),
        ({"doe": {"wall_count": [3, 1]}}, "doe.wall_count"),
        ({"doe": [1, 2]}, "doe"),
        ({"refinement": {"worlds": 9, "scenarios": 8}}, "refinement.worlds"),
        ({"refinement": {"iterations": -1}}, "refinement.iterations"),
        ({"refinement": {"weight_rate": 1.5}}, "refinement.weight_rate"),
        ({"refinement": {"bogus": 1}}, "refinement.bogus"),
        ({"refinement": {"families": ["caves"]}}, "refinement.families"),
    ],
)
def test_bad_config_names_the_key(changes: dict[str, object], key: str) -> None:
    with pytest.raises(ConfigError, match=key):
        tiny(**changes)


def test_config_file_round_trip_and_errors(tmp_path: Path) -> None:
    import yaml

    path = tmp_path / "cfg.yaml"
    path.write_text(yaml.safe_dump(tiny().to_dict()))
    assert TrainerConfig.from_yaml(path) == tiny()
    path.write_text("robot: [unclosed\n")
    with pytest.raises(FileFormatError, match=r"cfg\.yaml"):
        TrainerConfig.from_yaml(path)
    with pytest.raises(FileFormatError, match="no such file"):
        TrainerConfig.from_yaml(tmp_path / "missing.yaml")


def test_mentor_train_names_the_config_file_of_a_step_outside_the_robots(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    import yaml

    from mentor_core.cli import train as train_cli

    path = tmp_path / "steps.yaml"
    path.write_text(yaml.safe_dump(tiny(step_min=0.5).to_dict()))  # the robot steps <= 0.08 m
    argv = ["--robot", "swarm", "--framework", "dual", "--config", str(path)]
    assert train_cli.main([*argv, "--out", str(tmp_path / "run")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "steps.yaml: step_min" in err[0]
    assert not (tmp_path / "run").exists()


def test_a_runs_config_yaml_trains_the_run_again(
    dual_run: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A run directory's config.yaml (the resolved config plus the run's seed) is a config
    file for mentor-train: the same config and seed give the same run; --seed overrides."""
    from mentor_core.cli import train as train_cli

    argv = ["--robot", "swarm", "--framework", "dual", "--config",
            str(dual_run / "config.yaml"), "--quiet"]
    assert train_cli.main([*argv, "--out", str(tmp_path / "again")]) == 0
    assert "seed 3 ->" in capsys.readouterr().err
    assert without_seconds(history_rows(tmp_path / "again")) == without_seconds(
        history_rows(dual_run)
    )
    assert train_cli.main([*argv, "--seed", "4", "--out", str(tmp_path / "other")]) == 0
    assert "seed 4 ->" in capsys.readouterr().err
    bad = tmp_path / "bad.yaml"
    bad.write_text((dual_run / "config.yaml").read_text().replace("seed: 3", "seed: three"))
    assert train_cli.main([*argv[:-2], str(bad), "--out", str(tmp_path / "bad")]) == 2
    assert "bad.yaml: seed: expected a whole number" in capsys.readouterr().err


def test_train_in_a_directory_the_caller_opened(dual_run: Path, tmp_path: Path) -> None:
    """mentor-train opens (locks) the run directory before its workers start and hands it to
    train; the directory then says whether it is a resume."""
    from mentor_core.training.run_directory import open_run

    with pytest.raises(FileFormatError, match="nothing to resume: no such directory"):
        train(tiny(), tmp_path / "none", seed=3, resume=True)
    with open_run(tmp_path / "run", resume=False) as run_dir:
        with pytest.raises(ValueError, match="resume"):
            train(tiny(), run_dir, seed=3, resume=True)
        result = train(tiny(), run_dir, seed=3)
        assert (tmp_path / "run" / "train.lock").exists()
    assert not (tmp_path / "run" / "train.lock").exists()
    assert result.generations_run == 4 and result.rebuilt == ()
    assert without_seconds(history_rows(tmp_path / "run")) == without_seconds(
        history_rows(dual_run)
    )


class _EveryGain(InProcessEvaluator):
    """Computes every G, whatever the trainer asks (the trainer before G was skipped)."""

    def evaluate(self, genomes, gains="all"):  # type: ignore[no-untyped-def]
        return self.problem.evaluate(genomes, "all")


def test_g_is_computed_where_it_is_ranked_or_written_and_nothing_else_changes(
    dual_run: Path, tmp_path: Path
) -> None:
    rows = history_rows(dual_run)
    last = len(rows) - 1
    for k, row in enumerate(rows):
        computed = row["mode"] == "multi" or k == last
        assert (row["best_G"] != "" and row["mean_G"] != "") == computed, row
    # with every G computed, the run selects and writes the same: only the history gains G
    config = tiny()
    train(config, tmp_path, seed=3, evaluator=_EveryGain(make_problem(config)))
    for name in ("best_genome.json", "population.json", "pareto.json"):
        assert (tmp_path / name).read_bytes() == (dual_run / name).read_bytes()
    full = history_rows(tmp_path)
    assert all(r["best_G"] != "" for r in full)
    for a, b in zip(without_seconds(full), without_seconds(rows), strict=True):
        assert {k: v for k, v in a.items() if k not in ("best_G", "mean_G")} == {
            k: v for k, v in b.items() if k not in ("best_G", "mean_G")
        }
    # the best genome's G is the one every-G evaluation gives it
    genome, metadata = load_genome_and_metadata(dual_run / "best_genome.json")
    g = make_problem(config).evaluate([genome]).objectives[0, 1]
    assert metadata["objectives"]["experience_gain"] == g


def test_only_the_best_gets_its_g_alike_in_process_and_in_a_pool() -> None:
    config = tiny()
    problem = make_problem(config)
    from mentor_core.evolution.loop import Evolution

    genomes = Evolution(config.evolution, problem.n_inputs, 2, seed=1, objectives=2).ask()
    every = problem.evaluate(genomes)
    serial = InProcessEvaluator(problem).evaluate(genomes, "best")
    with PoolEvaluator(problem, workers=2) as pool:
        parallel = pool.evaluate(genomes, "best")
    best = int(np.argmax(every.objectives[:, 0]))
    expected = np.full(len(genomes), np.nan)
    expected[best] = every.objectives[best, 1]
    for got in (serial, parallel):
        np.testing.assert_array_equal(got.objectives[:, 0], every.objectives[:, 0])
        np.testing.assert_array_equal(got.objectives[:, 1], expected)
    with pytest.raises(ValueError, match="gains"):
        problem.evaluate(genomes, "some")  # type: ignore[arg-type]


def test_simplicity_in_place_of_the_experience_gain_is_what_stage_one_ranks(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The experience gain's ablation (second_objective: simplicity): the first stage ranks F
    beside the negated FLOPs complexity of each genome asked; the second ranks F as before."""
    from mentor_core.evolution.loop import Evolution
    from mentor_core.objectives.complexity import flops_ratio

    told: list[tuple[str, np.ndarray, list[float]]] = []
    ask, tell = Evolution.ask, Evolution.tell
    asked: list[list[float]] = []

    def spy_ask(self: Evolution) -> list:  # type: ignore[type-arg]
        genomes = ask(self)
        asked.append([flops_ratio(g) for g in genomes])
        return genomes

    def spy_tell(self: Evolution, objectives: np.ndarray, mode: str = "multi") -> object:
        told.append((mode, objectives.copy(), asked[-1]))
        return tell(self, objectives, mode=mode)  # type: ignore[arg-type]

    monkeypatch.setattr(Evolution, "ask", spy_ask)
    monkeypatch.setattr(Evolution, "tell", spy_tell)
    train(tiny(second_objective="simplicity"), tmp_path / "run", seed=3)
    assert [mode for mode, _, _ in told] == ["multi", "multi", "single", "single"]
    for mode, objectives, complexity in told:
        if mode == "multi":
            assert objectives[:, 1].tolist() == [-c for c in complexity]
    # G is still computed and recorded in the first stage
    assert all(row["best_G"] for row in history_rows(tmp_path / "run")[:2])
    with pytest.raises(ConfigError, match="second_objective"):
        tiny(second_objective="novelty")
