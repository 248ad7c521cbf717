"""XOR benchmark: the fitness and solved criteria, a short seeded run solves XOR, the CLI."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from mentor_core.cli.xor import (
    XOR_TARGETS,
    benchmark,
    main,
    run_xor,
    summarize,
    xor_fitness,
    xor_outputs,
    xor_solved,
)
from mentor_core.evolution.config import EvolutionConfig
from mentor_core.evolution.genome import ConnectionGene, Genome, NodeGene


def hand_made_xor() -> Genome:
    """x0 XOR x1 = AND(OR, NAND) with steep sigmoids (slope 4.9): 2 hidden nodes."""
    nodes = (
        NodeGene(0, "input", "identity"),
        NodeGene(1, "input", "identity"),
        NodeGene(2, "bias", "identity"),
        NodeGene(3, "output", "sigmoid"),
        NodeGene(4, "hidden", "sigmoid"),  # OR
        NodeGene(5, "hidden", "sigmoid"),  # NAND
    )
    w = 5.0
    conns = (
        ConnectionGene(0, 0, 4, w),
        ConnectionGene(1, 1, 4, w),
        ConnectionGene(2, 2, 4, -0.5 * w),
        ConnectionGene(3, 0, 5, -w),
        ConnectionGene(4, 1, 5, -w),
        ConnectionGene(5, 2, 5, 1.5 * w),
        ConnectionGene(6, 4, 3, w),
        ConnectionGene(7, 5, 3, w),
        ConnectionGene(8, 2, 3, -1.5 * w),
    )
    return Genome(2, 1, nodes, conns)


def test_criteria() -> None:
    assert xor_fitness(XOR_TARGETS.copy()) == 4.0
    assert xor_fitness(np.full(4, 0.5)) == 3.0
    assert xor_solved(np.array([0.4, 0.6, 0.9, 0.1]))
    assert not xor_solved(np.array([0.4, 0.6, 0.9, 0.5]))  # 0.5 is not on the right side
    out = xor_outputs(hand_made_xor())
    assert xor_solved(out)
    assert xor_fitness(out) > 3.9


def test_short_runs_solve_xor() -> None:
    config = EvolutionConfig.packaged("xor")
    results = benchmark(config, runs=2, seed=0, max_generations=100)
    assert [r.seed for r in results] == [0, 1]
    for r in results:
        assert r.solved
        assert r.evaluations == r.generations * config.population_size
        assert r.fitness > 3.0
    summary = summarize(results)
    assert summary["solved"] == 2
    assert summary["evaluations"]["max"] == max(r.evaluations for r in results)


def test_unsolved_run_is_counted_as_unsolved() -> None:
    config = EvolutionConfig.packaged("xor")
    r = run_xor(config, seed=0, max_generations=1)
    assert not r.solved and r.generations == 1 and r.evaluations == 150
    summary = summarize([r])
    assert summary == {**summary, "runs": 1, "solved": 0, "unsolved_seeds": [0]}
    assert summary["evaluations"]["mean"] is None


def test_same_seed_same_result() -> None:
    config = EvolutionConfig.from_dict({**EvolutionConfig.packaged("xor").to_dict(),
                                        "population_size": 40})
    assert run_xor(config, 5, 8) == run_xor(config, 5, 8)


@pytest.mark.slow
def test_workers_give_the_serial_result() -> None:
    config = EvolutionConfig.packaged("xor")
    assert benchmark(config, 3, seed=10, workers=2) == benchmark(config, 3, seed=10)


def test_cli_prints_json(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["--runs", "1", "--seed", "0", "--generations", "2"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["runs"] == 1
    assert set(out) >= {"runs", "solved", "evaluations", "hidden_nodes_mean"}
    assert set(out["evaluations"]) >= {"mean", "median", "max"}


def test_cli_bad_input(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["--runs", "0"]) == 2
    bad = tmp_path / "x.yaml"
    bad.write_text("populaton_size: 3\n")
    assert main(["--runs", "1", "--config", str(bad)]) == 2
    err = capsys.readouterr().err
    assert str(bad) in err and "populaton_size" in err
