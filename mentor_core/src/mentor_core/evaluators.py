"""Evaluation backends: in-process, a local process pool, and Ray.

All three split the genomes into contiguous chunks, evaluate each chunk with the same
:class:`~mentor_core.problem.NavigationProblem` and concatenate in order. Evaluation is
deterministic and a genome's result does not depend on its chunk, so every backend gives
bit-identical objectives for the same genomes.
"""

from __future__ import annotations

import itertools
import multiprocessing
import os
from collections.abc import Sequence
from concurrent.futures import Executor, ProcessPoolExecutor
from typing import Any

import numpy as np

from mentor_core.genome import Genome
from mentor_core.problem import Evaluation, NavigationProblem


def _chunks(n: int, parts: int) -> list[tuple[int, int]]:
    """Split range(n) into at most ``parts`` contiguous, near-equal (lo, hi) slices."""
    parts = max(1, min(parts, n))
    bounds = np.linspace(0, n, parts + 1).round().astype(int)
    return [(int(lo), int(hi)) for lo, hi in itertools.pairwise(bounds) if hi > lo]


def _concat(parts: Sequence[Evaluation]) -> Evaluation:
    return Evaluation(
        objectives=np.concatenate([p.objectives for p in parts], axis=0),
        success_rate=np.concatenate([p.success_rate for p in parts]),
        collision_rate=np.concatenate([p.collision_rate for p in parts]),
    )


class Evaluator:
    """Base class: evaluate a list of genomes on the problem, in order."""

    def __init__(self, problem: NavigationProblem) -> None:
        self.problem = problem

    def evaluate(self, genomes: Sequence[Genome]) -> Evaluation:
        """Objectives and outcome rates for ``genomes``, row i for genome i."""
        return self.problem.evaluate(genomes)

    def close(self) -> None:
        """Release workers (no-op in process)."""

    def __enter__(self) -> Evaluator:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


class InProcessEvaluator(Evaluator):
    """Evaluate in the calling process (the default)."""


class PoolEvaluator(Evaluator):
    """Evaluate on a local process pool of ``workers`` processes."""

    def __init__(self, problem: NavigationProblem, workers: int) -> None:
        super().__init__(problem)
        if workers < 1:
            raise ValueError(f"workers must be at least 1, got {workers}")
        self.workers = workers
        # spawn, not fork: numba's OpenMP threads (parallel MST kernel) do not survive a fork
        self._pool: Executor = ProcessPoolExecutor(
            max_workers=workers, mp_context=multiprocessing.get_context("spawn")
        )

    def evaluate(self, genomes: Sequence[Genome]) -> Evaluation:
        """Evaluate contiguous chunks in parallel and concatenate them in order."""
        chunks = _chunks(len(genomes), self.workers)
        if len(chunks) <= 1:
            return self.problem.evaluate(genomes)
        # the problem (a world and its scenarios) is small, so it travels with each chunk
        futures = [self._pool.submit(self.problem.evaluate, genomes[lo:hi]) for lo, hi in chunks]
        return _concat([f.result() for f in futures])

    def close(self) -> None:
        """Shut the pool down."""
        self._pool.shutdown(wait=True, cancel_futures=True)


class RayEvaluator(Evaluator):
    """Evaluate on Ray: ``address="auto"`` starts a local Ray, otherwise joins that cluster.

    Ray is an optional extra (``pip install mentor-core[ray]``).
    """

    def __init__(self, problem: NavigationProblem, address: str, workers: int | None = None):
        super().__init__(problem)
        try:
            import ray
        except ImportError as exc:  # pragma: no cover - depends on the optional extra
            raise RuntimeError(
                "the Ray backend needs the optional extra: pip install 'mentor-core[ray]'"
            ) from exc
        self._ray: Any = ray
        if not ray.is_initialized():
            if address == "auto":
                ray.init(num_cpus=workers or os.cpu_count(), include_dashboard=False)
            else:
                ray.init(address=address)
        self.workers = workers or int(ray.available_resources().get("CPU", 1))
        self._problem_ref = ray.put(problem)
        self._remote = ray.remote(_ray_evaluate)

    def evaluate(self, genomes: Sequence[Genome]) -> Evaluation:
        """Evaluate contiguous chunks as Ray tasks and concatenate them in order."""
        chunks = _chunks(len(genomes), self.workers)
        refs = [self._remote.remote(self._problem_ref, list(genomes[lo:hi])) for lo, hi in chunks]
        return _concat(self._ray.get(refs))

    def close(self) -> None:
        """Leave the Ray runtime running for the caller; nothing to release here."""


def _ray_evaluate(problem: NavigationProblem, genomes: Sequence[Genome]) -> Evaluation:
    return problem.evaluate(genomes)


def make_evaluator(
    problem: NavigationProblem, workers: int = 1, ray_address: str | None = None
) -> Evaluator:
    """The backend a command line asks for: Ray if an address is given, else a pool or not."""
    if ray_address:
        return RayEvaluator(problem, ray_address, workers if workers > 1 else None)
    if workers > 1:
        return PoolEvaluator(problem, workers)
    return InProcessEvaluator(problem)
