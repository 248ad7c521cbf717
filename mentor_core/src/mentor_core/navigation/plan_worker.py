"""Where a scan map's plans are made: at once (the benchmark, lockstep, ``mentor-eval``), a
fixed number of decisions late (the benchmark with a planner's delay simulated), or on a
thread beside the controller (the planner node deciding continuously, as Nav2's planner
server runs beside its controller server).

A :class:`PlanJob` is a snapshot: the map as it was when the plan was asked for, the start and
the goal; its :meth:`PlanJob.run` makes the :class:`~.grid_planner.GridPlanner` and the path.
A worker takes jobs with :meth:`submit` (a job not started yet is replaced by a newer one: only
the latest map matters) and hands back finished :class:`PlanResult` s with :meth:`poll`; the
controller never waits for it.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Protocol

import numpy as np
from numpy.typing import NDArray

from mentor_core.navigation.grid import OccupancyGrid
from mentor_core.navigation.grid_planner import GridPlanner
from mentor_core.navigation.guide import GuideConfig

FloatArray = NDArray[np.float64]
XY = tuple[float, float]


@dataclass(frozen=True)
class PlanResult:
    """A plan made: for ``goal`` from ``start``, on the map snapshot of the job (its
    ``planner``, which the guide then checks its lines of sight on), ``path`` None when none
    was found, ``seconds`` it took (wall clock); ``owner`` the job's."""

    owner: object
    goal: XY
    start: XY
    planner: GridPlanner
    path: FloatArray | None
    seconds: float


@dataclass(frozen=True)
class PlanJob:
    """A plan to make on the map ``grid`` gives (a snapshot, built by the worker: a copy of
    the cells is all the decision pays) from ``start`` to ``goal`` with ``config``, for
    ``owner`` (who asked: a result for a guide since replaced is not used)."""

    owner: object
    grid: Callable[[], OccupancyGrid]
    start: XY
    goal: XY
    config: GuideConfig

    def run(self) -> PlanResult:
        """Make the plan (:class:`~.grid_planner.GridPlanner`)."""
        began = time.perf_counter()
        planner = self.config.planner(self.grid())
        path = planner.plan(self.start, self.goal)
        return PlanResult(self.owner, self.goal, self.start, planner, path,
                          time.perf_counter() - began)


class PlanWorker(Protocol):
    """What makes a scan map's plans away from the decision (module docstring)."""

    @property
    def busy(self) -> bool:
        """A job is waiting or running."""

    def submit(self, job: PlanJob) -> None:
        """Make ``job``'s plan (replacing a job not started yet)."""

    def poll(self) -> PlanResult | None:
        """The latest plan finished since the last poll, or None; called once a decision."""

    def close(self) -> None:
        """Stop (a thread: at its next job's end)."""


class DelayedPlans:
    """Plans made at once but handed back ``decisions`` polls later: a planner that takes
    that many control periods, simulated deterministically (the benchmark's
    ``scan_map.plan_delay``). A job submitted while one is held waits its turn, as on a
    thread (the latest one only)."""

    def __init__(self, decisions: int) -> None:
        if decisions < 1:
            raise ValueError(f"decisions must be at least 1, got {decisions}")
        self.decisions = int(decisions)
        self._held: tuple[int, PlanResult] | None = None  # polls left, result
        self._next: PlanJob | None = None

    @property
    def busy(self) -> bool:
        return self._held is not None or self._next is not None

    def submit(self, job: PlanJob) -> None:
        if self._held is None:
            self._held = (self.decisions, job.run())
        else:
            self._next = job

    def poll(self) -> PlanResult | None:
        if self._held is None:
            return None
        left, result = self._held
        if left > 1:
            self._held = (left - 1, result)
            return None
        self._held = None
        if self._next is not None:
            job, self._next = self._next, None
            self.submit(job)
        return result

    def close(self) -> None:
        self._held = self._next = None


class ThreadPlans:
    """Plans made on a daemon thread beside the decisions (module docstring). The kernels of
    the plan release the GIL, so the controller's thread keeps deciding meanwhile.
    ``on_done`` is called on the worker thread with each result (for a log line)."""

    def __init__(self, on_done: Callable[[PlanResult], None] | None = None) -> None:
        self._lock = threading.Condition()
        self._job: PlanJob | None = None
        self._running = False
        self._done: PlanResult | None = None
        self._closed = False
        self._on_done = on_done
        #: the last job that failed, as one line ('' : none); the thread goes on
        self.error = ""
        self._thread = threading.Thread(target=self._loop, name="mentor-plan", daemon=True)
        self._thread.start()

    @property
    def busy(self) -> bool:
        with self._lock:
            return self._running or self._job is not None

    def submit(self, job: PlanJob) -> None:
        with self._lock:
            self._job = job
            self._lock.notify()

    def poll(self) -> PlanResult | None:
        with self._lock:
            done, self._done = self._done, None
            return done

    def close(self) -> None:
        with self._lock:
            self._closed = True
            self._job = None
            self._lock.notify()

    def _loop(self) -> None:
        while True:
            with self._lock:
                while self._job is None and not self._closed:
                    self._lock.wait()
                if self._closed:
                    return
                job, self._job = self._job, None
                self._running = True
            assert job is not None
            try:
                result: PlanResult | None = job.run()
            except Exception as err:  # a bug must not end planning: the next job may pass
                result = None
                self.error = f"{type(err).__name__}: {err}"
            with self._lock:
                self._running = False
                if result is not None:
                    self._done = result
            if result is not None and self._on_done is not None:
                try:
                    self._on_done(result)
                except Exception as err:  # the caller's hook must not end planning either
                    self.error = f"{type(err).__name__}: {err}"
