"""Evaluation backends: in-process, a local process pool, and Ray.

All three split the genomes into contiguous chunks, evaluate each chunk with the same
:class:`~mentor_core.training.problem.NavigationProblem` and concatenate in order. Evaluation is
deterministic and a genome's result does not depend on its chunk, so every backend gives
bit-identical objectives for the same genomes.
"""

from __future__ import annotations

import itertools
import logging
import multiprocessing
import os
import socket
from collections.abc import Sequence
from concurrent.futures import Executor, ProcessPoolExecutor
from typing import Any

import numpy as np

from mentor_core.errors import ConfigError, MentorError
from mentor_core.evolution.genome import Genome
from mentor_core.training.problem import Evaluation, NavigationProblem


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


class BackendError(MentorError, RuntimeError):
    """An evaluation backend cannot be used (Ray missing, cluster unreachable)."""


# how long the reachability check of a cluster address waits before giving up
RAY_CONNECT_TIMEOUT_S = 5.0


def _ray_host_port(address: str) -> tuple[str, int]:
    """``host:port`` (or ``[ipv6]:port``) of a Ray cluster address, BackendError otherwise."""
    host, sep, port = address.rpartition(":")
    host = host.strip("[]")
    if not sep or not host or not port.isdigit():
        raise BackendError(
            f"Ray address {address!r} is not 'auto' or HOST:PORT (the head node's GCS port, "
            "e.g. 10.0.0.5:6379)"
        )
    return host, int(port)


def _check_reachable(address: str, timeout: float) -> None:
    """Fail fast on an address nobody listens on (ray.init would wait for minutes)."""
    host, port = _ray_host_port(address)
    try:
        with socket.create_connection((host, port), timeout=timeout):
            pass
    except OSError as err:
        reason = err.strerror or type(err).__name__
        raise BackendError(f"Ray cluster at {address} is unreachable ({reason})") from None


class RayEvaluator(Evaluator):
    """Evaluate on Ray: ``address="auto"`` (or ``"local"``) starts a local Ray, else joins it.

    Args:
        problem: what every genome is evaluated on (put in Ray's object store once).
        address: ``"auto"``/``"local"``: start a fresh single-machine Ray with ``workers``
            CPUs (all cores when None), no dashboard, Ray's own logging at ERROR and worker
            output not forwarded (the tasks print nothing; their exceptions still reach the
            caller). ``HOST:PORT``: join the running cluster whose head listens there.
            If Ray is already initialised in this process, that runtime is used as it is.
        workers: number of chunks a population is split into (one Ray task each); default
            the CPUs of the Ray runtime.

    :meth:`close` calls ``ray.shutdown()`` only if this evaluator called ``ray.init`` (a local
    Ray it started stops; a joined cluster keeps running, this process disconnects).
    Ray is an optional extra (``pip install 'mentor-core[ray]'``). Raises
    :class:`BackendError` (one line) when Ray is missing or the cluster cannot be reached.
    """

    def __init__(
        self, problem: NavigationProblem, address: str = "auto", workers: int | None = None
    ) -> None:
        super().__init__(problem)
        if workers is not None and workers < 1:
            raise ValueError(f"workers must be at least 1, got {workers}")
        try:
            import ray
        except ImportError:
            raise BackendError(
                "the Ray backend needs Ray: pip install 'mentor-core[ray]'"
            ) from None
        self._ray: Any = ray
        self._owns_ray = False
        if not self._ray.is_initialized():
            self._init_ray(address, workers)
        try:
            cpus = int(self._ray.cluster_resources().get("CPU", 1))
            self.workers = workers or max(1, cpus)
            self._problem_ref = self._ray.put(problem)
            self._remote = self._ray.remote(_ray_evaluate)
        except BaseException:
            self.close()
            raise

    def _init_ray(self, address: str, workers: int | None) -> None:
        ray: Any = self._ray
        quiet: dict[str, Any] = {
            "include_dashboard": False,
            "logging_level": logging.ERROR,
            "log_to_driver": False,
        }
        if address.startswith("ray://"):
            raise BackendError(
                f"Ray address {address}: Ray Client addresses need ray[client]; "
                "pass the head node's HOST:PORT (GCS port, default 6379) instead"
            )
        try:
            if address in ("auto", "local"):
                # "local", not Ray's "auto": always a fresh runtime of our own, never a
                # cluster found through RAY_ADDRESS or /tmp/ray
                ray.init(address="local", num_cpus=workers or os.cpu_count(), **quiet)
            else:
                _check_reachable(address, RAY_CONNECT_TIMEOUT_S)
                ray.init(address=address, **quiet)
        except BackendError:
            raise
        except Exception as err:  # ConnectionError, ValueError, RuntimeError from ray.init
            first = str(err).strip().splitlines()[0] if str(err).strip() else type(err).__name__
            raise BackendError(f"cannot start or join Ray at {address}: {first}") from None
        self._owns_ray = True

    def evaluate(self, genomes: Sequence[Genome]) -> Evaluation:
        """Evaluate contiguous chunks as Ray tasks and concatenate them in order."""
        chunks = _chunks(len(genomes), self.workers)
        if not chunks:
            return self.problem.evaluate(genomes)
        refs = [self._remote.remote(self._problem_ref, list(genomes[lo:hi])) for lo, hi in chunks]
        return _concat(self._ray.get(refs))

    def close(self) -> None:
        """``ray.shutdown()`` if this evaluator called ``ray.init``; idempotent."""
        if self._owns_ray:
            self._owns_ray = False
            self._ray.shutdown()


def _ray_evaluate(problem: NavigationProblem, genomes: Sequence[Genome]) -> Evaluation:
    return problem.evaluate(genomes)


def make_evaluator(
    problem: NavigationProblem, workers: int | None = None, ray_address: str | None = None
) -> Evaluator:
    """The backend a command line asks for: Ray if an address is given, else a pool or not.

    ``workers``: pool processes, or for Ray the CPUs of a local runtime and the number of
    chunks (default: in process; all of Ray's CPUs). ConfigError when it is below 1.
    """
    if workers is not None and workers < 1:
        raise ConfigError(f"must be at least 1, got {workers}", key="workers")
    if ray_address:
        return RayEvaluator(problem, ray_address, workers)
    if workers is not None and workers > 1:
        return PoolEvaluator(problem, workers)
    return InProcessEvaluator(problem)
