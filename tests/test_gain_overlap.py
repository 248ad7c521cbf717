"""Experience gains overlapped with the simulation: the same numbers as one after the other."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pytest
from run_support import TINY, snapshot

from mentor_core.evolution.config import EvolutionConfig
from mentor_core.evolution.genome import Genome
from mentor_core.evolution.mutation import mutated_genomes
from mentor_core.objectives.experience import experience_gains_packed, experience_gains_shared
from mentor_core.training import gain_overlap
from mentor_core.training.config import TrainerConfig
from mentor_core.training.evaluators import InProcessEvaluator
from mentor_core.training.gain_overlap import GainOverlap, default_chunks, split_evenly
from mentor_core.training.problem import Evaluation, NavigationProblem
from mentor_core.training.trainer import make_problem, train

FIELDS = ("objectives", "success_rate", "collision_rate", "behaviour")


@pytest.fixture(scope="module")
def problem() -> NavigationProblem:
    return make_problem(TrainerConfig.from_dict({**TINY, "n_scenarios": 4}))


@pytest.fixture(scope="module")
def genomes(problem: NavigationProblem) -> list[Genome]:
    mutation = EvolutionConfig.paper("swarm").mutation
    return mutated_genomes(7, problem.n_inputs, mutation, 6, np.random.default_rng(3))


def assert_identical(a: Evaluation, b: Evaluation) -> None:
    for field in FIELDS:
        assert np.array_equal(getattr(a, field), getattr(b, field), equal_nan=True), field


@pytest.mark.parametrize("chunks", [1, 2, 3, 7, 20])
@pytest.mark.parametrize("threads", [1, 2])
def test_overlapped_gains_equal_the_plain_evaluation(
    problem: NavigationProblem, genomes: list[Genome], chunks: int, threads: int
) -> None:
    plain = problem.evaluate(genomes)
    assert (plain.objectives[:, 1] > 0).all()  # G was computed
    assert len(set(plain.objectives[:, 1].tolist())) > 1
    overlap = GainOverlap(chunks, threads, min_part_robots=1)
    try:
        assert_identical(problem.evaluate(genomes, overlap=overlap), plain)
        # the best genome's G alone: one part, as without the overlap
        assert_identical(
            problem.evaluate(genomes, "best", overlap), problem.evaluate(genomes, "best")
        )
        assert problem.evaluate([], overlap=overlap).objectives.shape == (0, 2)
    finally:
        overlap.close()


def test_shared_gains_equal_the_packed_ones_bit_for_bit() -> None:
    rng = np.random.default_rng(0)
    points = np.round(rng.normal(size=(900, 6)), 1)  # rounding makes ties and repeats
    offsets = np.array([0, 1, 2, 150, 151, 600, 900])
    packed = experience_gains_packed(points, offsets)
    for reverse in (False, True):
        gains, claimed = np.zeros(6), np.zeros(6, dtype=np.int8)
        experience_gains_shared(points, offsets, gains, claimed, reverse=reverse)
        assert np.array_equal(gains, packed)
        assert (claimed == 1).all()
    # a claimed slice is left to whoever claimed it
    gains, claimed = np.full(6, -1.0), np.array([0, 1, 0, 1, 0, 0], dtype=np.int8)
    experience_gains_shared(points, offsets, gains, claimed)
    assert np.array_equal(gains == -1.0, [False, True, False, True, False, False])
    assert np.array_equal(gains[[0, 2, 4, 5]], packed[[0, 2, 4, 5]])
    with pytest.raises(ValueError, match="claimed"):
        experience_gains_shared(points, offsets, np.zeros(6), np.zeros(6, dtype=bool))
    with pytest.raises(ValueError, match="gains"):
        experience_gains_shared(points, offsets, np.zeros(5), np.zeros(6, dtype=np.int8))


def test_split_evenly_covers_the_range_in_order() -> None:
    assert split_evenly(10, 4) == [(0, 2), (2, 5), (5, 8), (8, 10)]
    assert split_evenly(3, 7) == [(0, 1), (1, 2), (2, 3)]
    assert split_evenly(0, 4) == []
    assert GainOverlap(3, 1, min_part_robots=1).parts(9) == [(0, 3), (3, 6), (6, 9)]


def test_parts_keep_enough_robots_to_pay() -> None:
    overlap = GainOverlap(4, 1, min_part_robots=1500)
    assert len(overlap.parts(100, 60)) == 4  # the shipped UGV config: 6,000 robots
    assert len(overlap.parts(100, 30)) == 2
    assert overlap.parts(100, 20) == [(0, 100)]  # the Swarm-Robot's 2,000: one part
    overlap.close()


def test_fewer_parts_where_more_threads_take_g(monkeypatch: pytest.MonkeyPatch) -> None:
    assert [default_chunks(t) for t in (1, 2, 3, 4, 16)] == [4, 4, 4, 2, 2]
    monkeypatch.setattr(gain_overlap, "thread_count", lambda: 8)
    overlap = GainOverlap()
    assert (overlap.chunks, overlap.threads) == (2, 7)
    overlap.close()


def test_bad_settings_are_refused() -> None:
    with pytest.raises(ValueError, match="chunks"):
        GainOverlap(0)
    with pytest.raises(ValueError, match="threads"):
        GainOverlap(2, 0)
    with pytest.raises(ValueError, match="min_part_robots"):
        GainOverlap(2, 1, min_part_robots=0)


def test_a_closed_overlap_takes_no_more_work() -> None:
    overlap = GainOverlap(2, 1)
    overlap.close(wait=False)
    with pytest.raises(RuntimeError):
        overlap.submit(np.zeros((4, 3)), np.array([0, 2, 4]))


def test_training_in_process_gives_the_same_run_with_and_without_the_overlap(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # where numba has one thread the evaluator would not overlap: force it, one thread
    monkeypatch.setattr(GainOverlap, "available", staticmethod(lambda: True))
    monkeypatch.setattr(gain_overlap, "thread_count", lambda: 2)
    monkeypatch.setattr(gain_overlap, "MIN_PART_ROBOTS", 1)  # the tiny run's 18 robots
    submitted: list[int] = []
    submit = GainOverlap.submit

    def counted(self: GainOverlap, points: Any, offsets: Any) -> Any:
        submitted.append(len(offsets) - 1)
        return submit(self, points, offsets)

    monkeypatch.setattr(GainOverlap, "submit", counted)
    config = TrainerConfig.from_dict(dict(TINY))
    problem = make_problem(config)
    overlapped = InProcessEvaluator(problem)
    assert overlapped.describe() == "in process (G on 1 background thread)"
    train(config, seed=4, out_dir=tmp_path / "a", evaluator=overlapped)
    overlapped.close()
    assert len(submitted) >= 4 and sum(submitted) >= 12  # parts of the 6 genomes went by it
    submitted.clear()
    plain = InProcessEvaluator(problem, overlap=False)
    assert plain.describe() == "in process"
    train(config, seed=4, out_dir=tmp_path / "b", evaluator=plain)
    assert not submitted
    # every file, the wall-clock seconds left out
    assert snapshot(tmp_path / "a") == snapshot(tmp_path / "b")
