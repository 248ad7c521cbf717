"""Evaluation backends: in-process, a local process pool, and Ray.

All three split the genomes into contiguous chunks, evaluate each chunk with the same
:class:`~mentor_core.training.problem.NavigationProblem` and concatenate in order. Evaluation is
deterministic and a genome's result does not depend on its chunk, so every backend gives
bit-identical objectives for the same genomes.

Helpers die with the process that started them (:mod:`.child_processes`): pool workers on
any end of the trainer, kill -9 included; a local Ray on Ctrl-C or SIGTERM (``ray.shutdown``)
and, on Linux, on kill -9 too. Used as a context manager, an evaluator left by an exception
(Ctrl-C, SIGTERM, an error) stops its workers at once rather than waiting for their chunks.
"""

from __future__ import annotations

import logging
import os
import re
import signal
import socket
import threading
from collections.abc import Callable, Sequence
from functools import partial
from types import FrameType
from typing import Any, TypeVar

import numpy as np

from mentor_core.errors import ConfigError, MentorError, one_line
from mentor_core.evolution.genome import Genome
from mentor_core.training.child_processes import Reaper, die_with_parent, spawn_pool, stop_pool
from mentor_core.training.gain_overlap import GainOverlap, split_evenly
from mentor_core.training.problem import Evaluation, GainScope, NavigationProblem

Item = TypeVar("Item")
Result = TypeVar("Result")


def _concat(parts: Sequence[Evaluation], gains: GainScope) -> Evaluation:
    """The chunks' evaluations in order; with ``gains="best"`` only the G of the whole call's
    best is kept (each chunk computed its own best's), as one call in process gives."""
    objectives = np.concatenate([p.objectives for p in parts], axis=0)
    if gains == "best" and objectives.shape[0]:
        best = int(np.argmax(objectives[:, 0]))
        kept = objectives[best, 1]
        objectives[:, 1] = np.nan
        objectives[best, 1] = kept
    return Evaluation(
        objectives=objectives,
        success_rate=np.concatenate([p.success_rate for p in parts]),
        collision_rate=np.concatenate([p.collision_rate for p in parts]),
        behaviour=np.concatenate([p.behaviour for p in parts], axis=0),
    )


class Evaluator:
    """Base class: evaluate a list of genomes on the problem, in order."""

    def __init__(self, problem: NavigationProblem) -> None:
        self.problem = problem

    def evaluate(self, genomes: Sequence[Genome], gains: GainScope = "all") -> Evaluation:
        """Objectives and outcome rates for ``genomes``, row i for genome i; ``gains`` as
        :meth:`NavigationProblem.evaluate`: every backend gives the same numbers."""
        return self.problem.evaluate(genomes, gains)

    #: chunks :meth:`map_chunks` splits its items into (one in process)
    workers: int = 1

    def map_chunks(
        self, fn: Callable[[Sequence[Item]], Result], items: Sequence[Item]
    ) -> list[Result]:
        """``fn`` of contiguous chunks of ``items``, in order, a chunk per worker (one call in
        process): for other work on genomes than :meth:`evaluate`, such as the refinement's.
        ``fn`` must pickle (a module-level function, or a partial of one) and give each
        item's result whatever its chunk."""
        chunks = split_evenly(len(items), self.workers)
        if len(chunks) <= 1:
            return [fn(items)]
        return self._map(fn, [items[lo:hi] for lo, hi in chunks])

    def _map(
        self, fn: Callable[[Sequence[Item]], Result], chunks: list[Sequence[Item]]
    ) -> list[Result]:
        """``fn`` of each chunk on the workers, in order (backends with workers)."""
        raise NotImplementedError

    def describe(self) -> str:
        """Where the genomes are evaluated, in a few words (for a command's log)."""
        return "in process"

    def close(self) -> None:
        """Release workers (no-op in process)."""

    def terminate(self) -> None:
        """Stop at once, abandoning work in progress (an interrupted run); default close()."""
        self.close()

    def __enter__(self) -> Evaluator:
        return self

    def __exit__(self, exc_type: type[BaseException] | None, *exc: object) -> None:
        if exc_type is None:
            self.close()
        else:
            self.terminate()


class InProcessEvaluator(Evaluator):
    """Evaluate in the calling process (the default).

    Where numba has two threads or more, a generation's experience gains run on background
    threads while the rest of it is simulated (:mod:`~.gain_overlap`; the same numbers).
    ``overlap=False`` computes them after the simulation, as the other backends do.
    """

    def __init__(self, problem: NavigationProblem, overlap: bool = True) -> None:
        super().__init__(problem)
        self._overlap = GainOverlap() if overlap and GainOverlap.available() else None

    def evaluate(self, genomes: Sequence[Genome], gains: GainScope = "all") -> Evaluation:
        """As :meth:`Evaluator.evaluate`."""
        return self.problem.evaluate(genomes, gains, self._overlap)

    def describe(self) -> str:
        """In process, and whether G overlaps the simulation."""
        if self._overlap is None:
            return "in process"
        return f"in process (G on {_count(self._overlap.threads, 'background thread')})"

    def close(self) -> None:
        """Stop the background threads."""
        if self._overlap is not None:
            self._overlap.close()

    def terminate(self) -> None:
        """Stop the background threads, dropping G tasks not started."""
        if self._overlap is not None:
            self._overlap.close(wait=False)


class PoolEvaluator(Evaluator):
    """Evaluate on a local process pool of ``workers`` processes.

    The workers die with this process (:func:`~.child_processes.die_with_parent`), kill -9
    included, and ignore Ctrl-C (this process stops them); use the evaluator from the thread
    that created it.
    """

    def __init__(self, problem: NavigationProblem, workers: int) -> None:
        super().__init__(problem)
        if workers < 1:
            raise ValueError(f"workers must be at least 1, got {workers}")
        self.workers = workers
        self._pool = spawn_pool(workers, die_with_parent, (os.getpid(),))

    def describe(self) -> str:
        """``"N worker processes"``."""
        return f"{self.workers} worker processes"

    def evaluate(self, genomes: Sequence[Genome], gains: GainScope = "all") -> Evaluation:
        """Evaluate contiguous chunks in parallel and concatenate them in order."""
        # the problem (a world and its scenarios) is small, so it travels with each chunk
        return _concat(self.map_chunks(partial(self.problem.evaluate, gains=gains), genomes),
                       gains)

    def _map(
        self, fn: Callable[[Sequence[Item]], Result], chunks: list[Sequence[Item]]
    ) -> list[Result]:
        futures = [self._pool.submit(fn, chunk) for chunk in chunks]
        return [f.result() for f in futures]

    def close(self) -> None:
        """Shut the pool down (after the chunks in progress)."""
        self._pool.shutdown(wait=True, cancel_futures=True)

    def terminate(self) -> None:
        """Stop the workers now (SIGTERM, then SIGKILL) and shut the pool down."""
        stop_pool(self._pool)


class BackendError(MentorError, RuntimeError):
    """An evaluation backend cannot be used (Ray missing, cluster unreachable)."""


# how long the reachability check of a cluster address waits before giving up
RAY_CONNECT_TIMEOUT_S = 5.0
# the Ray addresses that are words: a private runtime started here, and Ray's own "auto" (the
# cluster RAY_ADDRESS names, else the one `ray start` started on this machine)
RAY_LOCAL = "local"
RAY_AUTO = "auto"


def _ray_host_port(address: str) -> tuple[str, int]:
    """``host:port`` (or ``[ipv6]:port``) of a Ray cluster address, BackendError otherwise."""
    host, sep, port = address.rpartition(":")
    host = host.strip("[]")
    if not sep or not host or not port.isdigit():
        raise BackendError(
            f"Ray address {address!r} is not 'local', 'auto' or HOST:PORT (the head node's "
            "GCS port, e.g. 10.0.0.5:6379)"
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


def _causes(err: BaseException) -> list[BaseException]:
    """``err`` and the exceptions it was raised from or during, outermost first."""
    chain: list[BaseException] = []
    cause: BaseException | None = err
    while cause is not None and cause not in chain:
        chain.append(cause)
        cause = cause.__cause__ or cause.__context__
    return chain


def _ray_failure(address: str, err: Exception) -> BackendError:
    """One line for a failed ``ray.init``: Ray's own words, its hint when a token is missing."""
    for cause in _causes(err):
        # Ray raises AuthenticationError, or quotes it in the traceback text of a
        # RuntimeError when it gave up retrying (a wrong or missing token)
        if type(cause).__name__ == "AuthenticationError":
            hint = one_line(cause)
        else:
            quoted = re.search(r"AuthenticationError: (.+)", str(cause))
            hint = quoted.group(1).strip() if quoted else ""
        if hint:
            return BackendError(f"cannot join Ray at {address}: token authentication: {hint}")
    if address == RAY_AUTO and "Could not find any running Ray instance" in str(err):
        return BackendError(
            "Ray address 'auto' found no running Ray cluster (Ray looks at RAY_ADDRESS, then "
            "at the cluster `ray start --head` started on this machine): start one, give its "
            "HOST:PORT, or use 'local' for a private Ray on this machine"
        )
    verb = "start" if address == RAY_LOCAL else "join"
    first = _first_line(err) or type(err).__name__
    why = _last_line(err.__cause__) if err.__cause__ is not None else ""  # Ray's own reason
    return BackendError(f"cannot {verb} Ray at {address}: {first}" + (f" ({why})" if why else ""))


def _first_line(err: BaseException) -> str:
    lines = str(err).strip().splitlines()
    return lines[0].strip() if lines else ""


def _last_line(err: BaseException) -> str:
    lines = str(err).strip().splitlines()
    return lines[-1].strip() if lines else ""


class RayEvaluator(Evaluator):
    """Evaluate on Ray: a private local runtime, or a running cluster joined.

    Args:
        problem: what every genome is evaluated on (put in Ray's object store once).
        address: ``"local"``: start a private single-machine Ray with ``workers`` CPUs (all
            cores when None), no dashboard; it stops with :meth:`close` and dies with this
            process (ray.shutdown on Ctrl-C/SIGTERM; after a kill -9 a
            :class:`~.child_processes.Reaper` stops Ray's agents, which outlive it). ``"auto"``:
            join the running cluster as Ray's own ``auto`` finds it (``RAY_ADDRESS``, else the
            cluster ``ray start`` started on this machine). ``HOST:PORT``: join the cluster
            whose head's GCS listens there. A cluster with token authentication needs
            ``RAY_AUTH_MODE=token`` and its token (``RAY_AUTH_TOKEN``, ``RAY_AUTH_TOKEN_PATH``
            or ``~/.ray/auth_token``), as Ray documents; Ray itself enables it for ``auto``
            when a token file exists. In all cases Ray's own logging is at ERROR and worker
            output is not forwarded (the tasks print nothing; their exceptions still reach the
            caller). If Ray is already initialised in this process, that runtime is used.
        workers: number of chunks a population is split into (one Ray task each); default
            the CPUs of the Ray runtime.

    :meth:`close` calls ``ray.shutdown()`` only if this evaluator called ``ray.init`` (a local
    Ray it started stops; a joined cluster keeps running, this process disconnects).
    Ray is an optional extra (``pip install 'mentor-core[ray]'``). Raises
    :class:`BackendError` (one line) when Ray is missing or the cluster cannot be reached.
    """

    def __init__(
        self, problem: NavigationProblem, address: str = RAY_LOCAL, workers: int | None = None
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
        self._reaper = Reaper()
        if self._ray.is_initialized():
            self._where = "the Ray runtime of this process"
        else:
            self._init_ray(address, workers)
            self._where = "a private local Ray" if address == RAY_LOCAL else "the Ray cluster"
        try:
            self._cpus = int(self._ray.cluster_resources().get("CPU", 1))
            self._nodes = sum(1 for node in self._ray.nodes() if node.get("Alive"))
            self._gcs = str(self._ray.get_runtime_context().gcs_address)
            self.workers = workers or max(1, self._cpus)
            self._problem_ref = self._ray.put(problem)
            self._remote = self._ray.remote(_ray_evaluate)
            self._call = self._ray.remote(_ray_call)
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
        if address not in (RAY_LOCAL, RAY_AUTO):
            _check_reachable(address, RAY_CONNECT_TIMEOUT_S)
        if address == RAY_LOCAL:
            self._reaper.start()  # before ray.init: a kill -9 while it starts is covered too
        # ray.init replaces the SIGTERM handler with its own sys.exit (and Ray's C++ core adds
        # a crash reporter); an application's own handler (mentor-train's) is put back
        own_handler = _application_sigterm_handler()
        try:
            if address == RAY_LOCAL:
                ray.init(address=RAY_LOCAL, num_cpus=workers or os.cpu_count(), **quiet)
            else:
                ray.init(address=address, **quiet)
        except BaseException as err:
            ray.shutdown()  # whatever a failed or interrupted ray.init started
            self._reaper.stop()
            if isinstance(err, Exception):  # ConnectionError, RuntimeError, ValueError
                raise _ray_failure(address, err) from None
            if own_handler and isinstance(err, SystemExit) and err.code == signal.SIGTERM:
                own_handler(signal.SIGTERM, None)  # the SIGTERM Ray's handler took
            raise
        finally:
            if own_handler:
                signal.signal(signal.SIGTERM, own_handler)
        self._owns_ray = True

    def describe(self) -> str:
        """Which Ray, its nodes and CPUs, e.g. ``the Ray cluster at 10.0.0.5:6379 (3 nodes,
        48 CPUs), 48 tasks a generation``."""
        return (
            f"{self._where} at {self._gcs} ({_count(self._nodes, 'node')}, "
            f"{_count(self._cpus, 'CPU')}), {_count(self.workers, 'task')} a generation"
        )

    def evaluate(self, genomes: Sequence[Genome], gains: GainScope = "all") -> Evaluation:
        """Evaluate contiguous chunks as Ray tasks and concatenate them in order."""
        chunks = split_evenly(len(genomes), self.workers)
        if not chunks:
            return self.problem.evaluate(genomes, gains)
        refs = [
            self._remote.remote(self._problem_ref, list(genomes[lo:hi]), gains)
            for lo, hi in chunks
        ]
        return _concat(self._ray.get(refs), gains)

    def _map(
        self, fn: Callable[[Sequence[Item]], Result], chunks: list[Sequence[Item]]
    ) -> list[Result]:
        return list(self._ray.get([self._call.remote(fn, list(chunk)) for chunk in chunks]))

    def close(self) -> None:
        """``ray.shutdown()`` if this evaluator called ``ray.init``; idempotent."""
        if self._owns_ray:
            self._owns_ray = False
            self._ray.shutdown()
        self._reaper.stop()


def _count(n: int, noun: str) -> str:
    return f"{n} {noun}" + ("" if n == 1 else "s")


def _application_sigterm_handler() -> Callable[[int, FrameType | None], Any] | None:
    """The SIGTERM handler the application set in Python, if any (main thread only)."""
    if threading.current_thread() is not threading.main_thread():
        return None
    handler = signal.getsignal(signal.SIGTERM)
    return handler if callable(handler) else None


def _ray_evaluate(
    problem: NavigationProblem, genomes: Sequence[Genome], gains: GainScope
) -> Evaluation:
    return problem.evaluate(genomes, gains)


def _ray_call(fn: Callable[[Sequence[Item]], Result], items: Sequence[Item]) -> Result:
    return fn(items)


def make_evaluator(
    problem: NavigationProblem, workers: int | None = None, ray_address: str | None = None
) -> Evaluator:
    """The backend a command line asks for: Ray if an address is given, else a pool or not.

    ``ray_address``: ``local``, ``auto`` or ``HOST:PORT`` (see :class:`RayEvaluator`).
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
