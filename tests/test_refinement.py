"""The refinement of a trained genome's weights after evolution (training/refinement.py)."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest
from run_support import TINY

import mentor_core.training.trainer as trainer_module
from mentor_core.errors import ConfigError
from mentor_core.files.genome_file import load_genome_and_metadata
from mentor_core.objectives.performance import path_credit
from mentor_core.sim.robots import get_profile
from mentor_core.training.config import TrainerConfig, shipped_config
from mentor_core.training.evaluators import InProcessEvaluator, PoolEvaluator
from mentor_core.training.problem import NavigationProblem, shortest_lengths
from mentor_core.training.refinement import RefinementConfig, chosen, refine
from mentor_core.training.trainer import make_problem, train

PLANNERS = Path(__file__).resolve().parents[1] / "planners"
SMALL = {"iterations": 6, "offspring": 4, "scenarios": 12, "worlds": 2}


def tiny(**changes: object) -> TrainerConfig:
    return TrainerConfig.from_dict({**TINY, **changes})


@pytest.fixture(scope="module")
def problem_and_genome():  # type: ignore[no-untyped-def]
    """A shipped planner on a few scenarios of its own config: one that reaches goals."""
    config = dataclasses.replace(shipped_config("swarm", "paper"), n_scenarios=12,
                                 training_worlds=2, time_budget=50.0, scenario_seed=3)  # fmt: skip
    genome, _ = load_genome_and_metadata(PLANNERS / "swarm-paper-dual-s1.json")
    return make_problem(config), genome


def refined_problems(monkeypatch: pytest.MonkeyPatch) -> list[NavigationProblem]:
    """The problems the trainer's refinements run on from now on, in order."""
    seen: list[NavigationProblem] = []

    def recording(  # type: ignore[no-untyped-def]
        genome, problem, cfg, rng, progress=None, mutation=None, chunk_map=None
    ):
        seen.append(problem)
        return refine(genome, problem, cfg, rng, progress, mutation, chunk_map)

    monkeypatch.setattr(trainer_module, "refine", recording)
    return seen


def credit_of(problem, genome) -> tuple[int, float]:  # type: ignore[no-untyped-def]
    """Goals reached and sum of SPL's terms, computed here from one simulation."""
    batch = problem.simulate([genome])
    terms = path_credit(shortest_lengths(problem.scenarios, problem.profile),
                        batch.path_length(problem.profile))  # fmt: skip
    return int(batch.reached.sum()), float(np.sum(np.where(batch.reached, terms, 0.0)))


def test_refinement_keeps_the_topology_and_never_loses_goals_or_credit(
    problem_and_genome,  # type: ignore[no-untyped-def]
) -> None:
    problem, genome = problem_and_genome
    before = credit_of(problem, genome)
    result = refine(genome, problem, RefinementConfig(**SMALL), np.random.default_rng(0))
    assert (result.reached_before, result.credit_before) == pytest.approx(before)
    # what it reports is what the refined genome does
    assert (result.reached, result.credit) == pytest.approx(credit_of(problem, result.genome))
    assert result.reached >= result.reached_before
    assert result.credit >= result.credit_before
    assert result.accepted > 0 and result.credit > result.credit_before  # it moved here
    assert [c.innovation for c in result.genome.connections] == [
        c.innovation for c in genome.connections]  # fmt: skip
    assert result.genome.nodes == genome.nodes


def test_a_copy_that_loses_a_goal_is_never_chosen_whatever_its_credit() -> None:
    reached, credit = np.array([9, 10, 11, 10]), np.array([9.5, 8.0, 7.0, 8.0])
    assert chosen(reached, credit, goals=10, score=6.0) == 1  # not 0: one goal fewer
    assert chosen(reached, credit, goals=10, score=8.0) is None  # none above the credit
    assert chosen(reached, credit, goals=12, score=0.0) is None  # none keeps the goals
    assert chosen(reached, credit, goals=0, score=0.0) == 0


def test_refinement_is_deterministic_and_off_at_zero_iterations(
    problem_and_genome,  # type: ignore[no-untyped-def]
) -> None:
    problem, genome = problem_and_genome
    runs = [refine(genome, problem, RefinementConfig(**SMALL), np.random.default_rng(7))
            for _ in range(2)]  # fmt: skip
    assert runs[0].genome == runs[1].genome
    off = refine(genome, problem, RefinementConfig(**{**SMALL, "iterations": 0}),
                 np.random.default_rng(7))  # fmt: skip
    assert off.genome is genome and off.accepted == 0


def test_a_refining_run_writes_the_refined_genome_and_resumes_to_it(tmp_path: Path) -> None:
    config = tiny(refinement=SMALL)
    lines: list[tuple[int, int, int, float]] = []
    train(config, tmp_path / "a", seed=3, refine_progress=lambda *a: lines.append(a))
    genome, meta = load_genome_and_metadata(tmp_path / "a" / "best_genome.json")
    record = meta["refinement"]
    assert record["iterations"] == 6 and len(lines) == 6
    assert record["reached"][1] >= record["reached"][0]
    assert record["path_credit"][1] >= record["path_credit"][0]
    # the evolved best, whose weights it refined, is the one a run without refinement writes
    train(tiny(), tmp_path / "plain", seed=3)
    evolved, plain_meta = load_genome_and_metadata(tmp_path / "plain" / "best_genome.json")
    assert "refinement" not in plain_meta
    assert meta["objectives"] == plain_meta["objectives"]
    assert [c.innovation for c in genome.connections] == [
        c.innovation for c in evolved.connections]  # fmt: skip
    assert genome != evolved or record["accepted"] == 0
    # stopped in evolution and resumed: the same file, refinement and all
    train(config, tmp_path / "b", seed=3, stop_after=2)
    train(config, tmp_path / "b", seed=3, resume=True)
    assert (tmp_path / "b" / "best_genome.json").read_text() == (
        tmp_path / "a" / "best_genome.json").read_text()  # fmt: skip


def test_a_run_spreads_the_refinement_over_its_workers_to_the_same_genome(
    tmp_path: Path,
) -> None:
    config = tiny(refinement=SMALL)
    train(config, tmp_path / "a", seed=3)
    refining: list[int] = []
    with PoolEvaluator(make_problem(config), workers=2) as pool:
        spread = pool.map_chunks

        def recorded(fn, items):  # type: ignore[no-untyped-def]
            parts = spread(fn, items)
            if fn.func.__name__ == "_score":  # not a generation's evaluate
                refining.append(len(parts))
            return parts

        pool.map_chunks = recorded  # type: ignore[method-assign]
        train(config, tmp_path / "b", seed=3, evaluator=pool)
    assert refining == [2] * SMALL["iterations"]  # each iteration's copies on both workers
    assert (tmp_path / "b" / "best_genome.json").read_bytes() == (
        tmp_path / "a" / "best_genome.json").read_bytes()  # fmt: skip


def test_refinement_worlds_that_cannot_be_drawn_fail_before_the_first_generation(
    tmp_path: Path,
) -> None:
    # the Swarm-Robot's corridors world of the refinement seed holds fewer than 30 pairs
    config = tiny(refinement={**SMALL, "families": ["corridors"], "family_pairs": 30})
    with pytest.raises(ConfigError, match=r"refinement\.families: .*too few solvable"):
        train(config, tmp_path / "run", seed=1)
    assert not (tmp_path / "run").exists()  # nothing trained, nothing written


def test_mentor_train_names_the_config_file_whose_refinement_cannot_be_drawn(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    from mentor_core.cli.train import main

    config = tmp_path / "mine.yaml"
    config.write_text("extends: swarm/quick\n"
                      "refinement: {iterations: 2, families: [corridors], family_pairs: 30}\n")
    args = ["--robot", "swarm", "--framework", "dual", "--config", str(config),
            "--out", str(tmp_path / "run")]  # fmt: skip
    assert main(args) == 2
    assert f"{config}: refinement.families: " in capsys.readouterr().err
    assert not (tmp_path / "run").exists()


def test_a_run_refines_for_the_robot_profile_of_its_problem(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    config = tiny(refinement={**SMALL, "iterations": 1})
    wider = dataclasses.replace(get_profile("swarm"), sensor_range=1.0)
    with InProcessEvaluator(make_problem(config, profile=wider)) as evaluator:
        # not told the profile: refused before anything is written, not refined for another
        with pytest.raises(ValueError, match="not the evaluator's problem's"):
            train(config, tmp_path / "run", seed=1, evaluator=evaluator)
        assert not (tmp_path / "run").exists()
        refined = refined_problems(monkeypatch)
        train(config, tmp_path / "run", seed=1, evaluator=evaluator, profile=wider)
    assert [p.profile.sensor_range for p in refined] == [1.0]


def test_mentor_train_prints_the_refinement_and_records_it(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    from mentor_core.cli.train import main

    args = ["--robot", "swarm", "--framework", "single", "--config", "quick", "--seed", "2",
            "--set", "generations=2", "--set", "refinement={iterations: 10, offspring: 2, "
            "scenarios: 6, worlds: 1}", "--out", str(tmp_path / "run")]  # fmt: skip
    assert main(args) == 0
    err = capsys.readouterr().err
    assert "refine   10/10 | reached" in err and "refine    5/10" not in err
    assert "(G " in err and "as evolved, its weights refined since; genome" in err
    _, meta = load_genome_and_metadata(tmp_path / "run" / "best_genome.json")
    assert meta["refinement"]["iterations"] == 10
    assert main([*args, "--resume"]) == 0  # a finished run: nothing refined again
    assert "refine " not in capsys.readouterr().err


def test_refinement_worlds_of_the_named_families_are_added(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    refined = refined_problems(monkeypatch)
    config = tiny(refinement={**SMALL, "iterations": 1, "families": ["rooms", "slalom"],
                              "family_pairs": 2})  # fmt: skip
    train(config, tmp_path, seed=1)
    # a world of each family, 2 pairs each
    assert [len(p.scenarios) for p in refined] == [SMALL["scenarios"] + 2 * 2]
    _, meta = load_genome_and_metadata(tmp_path / "best_genome.json")
    assert (meta["refinement"]["families"], meta["refinement"]["family_pairs"]) == (
        ["rooms", "slalom"], 2)  # fmt: skip
