"""Determinism: same seed same run; a run resumed from a checkpoint equals the unbroken run."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from mentor_core.evolution.config import EvolutionConfig
from mentor_core.evolution.genome import Genome
from mentor_core.evolution.loop import Evolution
from mentor_core.evolution.network import FeedForwardNetwork
from mentor_core.files.checkpoint import load_checkpoint, save_checkpoint

X = np.random.default_rng(1234).uniform(-1.0, 1.0, (8, 3))
GENERATIONS = 8
STAGE1 = 4  # generations in "multi" mode, then reseed and "single" mode (dual-stage shape)


def config() -> EvolutionConfig:
    return EvolutionConfig.from_dict(
        {
            "population_size": 24,
            "mutation": {"node_rate": 0.1, "edge_rate": 0.05, "weight_rate": 0.5},
            "speciation": {"target_species": 3},
        }
    )


def evaluate(genomes: list[Genome]) -> np.ndarray:
    """Two deterministic objectives: closeness to a target function, output spread."""
    rows = []
    for g in genomes:
        out = FeedForwardNetwork.from_genome(g).activate(X)
        target = (X[:, 0] * X[:, 1] > 0).astype(float)
        rows.append([4.0 - float(np.sum((out[:, 0] - target) ** 2)), float(out.std())])
    return np.array(rows)


def step(evo: Evolution, history: list[np.ndarray]) -> None:
    """One generation of a dual-stage-like run: multi, reseed at the stage end, single."""
    genomes = evo.ask()
    objectives = evaluate(genomes)
    history.append(objectives)
    mode = "multi" if evo.generation < STAGE1 else "single"
    evo.tell(objectives, mode=mode)
    if evo.generation == STAGE1:
        order = np.argsort(-objectives[:, 0], kind="stable")[:6]
        evo.reseed([genomes[int(i)] for i in order])


def unbroken(seed: int) -> tuple[Evolution, list[np.ndarray]]:
    evo = Evolution(config(), 3, 2, seed=seed, objectives=2)
    history: list[np.ndarray] = []
    for _ in range(GENERATIONS):
        step(evo, history)
    return evo, history


def assert_same(a: Evolution, b: Evolution, ha: list[np.ndarray], hb: list[np.ndarray]) -> None:
    assert len(ha) == len(hb)
    for x, y in zip(ha, hb, strict=True):
        assert np.array_equal(x, y)
    assert a.ask() == b.ask()
    assert a.history == b.history
    assert a.best()[0] == b.best()[0]
    assert a.to_state() == b.to_state()


def test_same_seed_same_run() -> None:
    a, ha = unbroken(7)
    b, hb = unbroken(7)
    assert_same(a, b, ha, hb)


def test_different_seeds_differ() -> None:
    a, ha = unbroken(7)
    b, hb = unbroken(8)
    assert a.ask() != b.ask()
    assert not np.array_equal(ha[-1], hb[-1])


def test_resume_after_kill_equals_unbroken_run(tmp_path: Path) -> None:
    reference, ref_history = unbroken(11)
    path = tmp_path / "checkpoint.json"
    for kill_after in (2, STAGE1, 6):  # before, at and after the stage change
        evo = Evolution(config(), 3, 2, seed=11, objectives=2)
        history: list[np.ndarray] = []
        for _ in range(kill_after):
            step(evo, history)
            save_checkpoint(path, evo)
        # the process dies in the middle of the next generation: asked, evaluated, not told
        evaluate(evo.ask())
        del evo
        resumed = load_checkpoint(path)
        assert resumed.generation == kill_after
        while resumed.generation < GENERATIONS:
            step(resumed, history)
        assert_same(resumed, reference, history, ref_history)
