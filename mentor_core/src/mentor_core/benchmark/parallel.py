"""Running a benchmark on worker processes: one task per planner and world family.

    results = run_parallel(functools.partial(my_setup, args), workers=4)

A contender's policy is a closure (a compiled network, a plan on a map), which a process pool
cannot send, so each worker builds the suite and the contenders itself, once, with
``setup`` (a picklable callable, e.g. a module-level function bound to the command line's
arguments), and runs the ``(contender, family)`` tasks it is given by index. Every task runs
as :func:`~mentor_core.benchmark.runner.run_family` runs it in process, with a fresh policy,
so the results are the same for any number of workers, one included. Workers are spawned
(numba's threads do not survive a fork) and die with this process
(:func:`~mentor_core.training.child_processes.die_with_parent`).
"""

from __future__ import annotations

import os
import time
from collections.abc import Callable, Sequence
from concurrent.futures import Future
from concurrent.futures.process import BrokenProcessPool

from mentor_core.benchmark.contenders import Contender
from mentor_core.benchmark.runner import (
    ContenderResult,
    Progress,
    contender_result,
    family_line,
    run_family,
)
from mentor_core.benchmark.scores import Outcomes
from mentor_core.benchmark.suite import Suite
from mentor_core.errors import MentorError
from mentor_core.training.child_processes import die_with_parent, spawn_pool, stop_pool

#: builds the suite and the contenders, the same in every process
Setup = Callable[[], tuple[Suite, Sequence[Contender]]]

# a worker's suite and contenders, built once by its initializer (one per process)
_built: tuple[Suite, Sequence[Contender]] | None = None


def run_parallel(
    setup: Setup, workers: int, progress: Progress | None = None,
    built: tuple[Suite, Sequence[Contender]] | None = None,
) -> list[ContenderResult]:  # fmt: skip
    """Every contender of ``setup()`` on every family of its suite, on ``workers`` processes;
    the results in contender order, as :func:`~mentor_core.benchmark.runner.run_all` gives
    them. ``built``: ``setup()``'s result when the caller already has it. ``progress`` gets
    each family's line in order as the runs finish. ValueError for fewer than 1 worker;
    MentorError when a worker dies (its own error, e.g. ``setup``'s, is on stderr above); on
    any other exception, Ctrl-C included, the workers are stopped before it goes on."""
    if workers < 1:
        raise ValueError(f"workers must be at least 1, got {workers}")
    suite, contenders = setup() if built is None else built
    tasks = [(k, family) for k in range(len(contenders)) for family in suite.families]
    pool = spawn_pool(
        min(workers, len(tasks)) or 1,
        _start_worker,
        (os.getpid(), setup, len(suite.pairs), [c.name for c in contenders]),
    )
    try:
        futures: dict[tuple[int, str], Future[tuple[Outcomes, float]]] = {
            task: pool.submit(_run_task, *task) for task in tasks
        }
        results = []
        for k, contender in enumerate(contenders):
            parts, seconds = [], 0.0
            for family in suite.families:
                part, took = futures[(k, family)].result()
                parts.append(part)
                seconds += took
                if progress is not None:
                    progress(family_line(suite, contender, family, part, took))
            results.append(contender_result(suite, contender, parts, seconds))
    except BrokenProcessPool as err:
        stop_pool(pool)
        raise MentorError(f"a benchmark worker stopped ({err}); its error is above") from None
    except BaseException:  # Ctrl-C included: the workers ignore it, so stop them now
        stop_pool(pool)
        raise
    pool.shutdown(wait=True)
    return results


def _start_worker(parent: int, setup: Setup, pairs: int, names: list[str]) -> None:
    global _built
    die_with_parent(parent)
    suite, contenders = setup()
    if len(suite.pairs) != pairs or [c.name for c in contenders] != names:
        raise RuntimeError("a worker built another suite or other planners than its parent")
    _built = (suite, contenders)


def _run_task(k: int, family: str) -> tuple[Outcomes, float]:
    if _built is None:
        raise RuntimeError("the benchmark worker was not set up")
    suite, contenders = _built
    began = time.perf_counter()
    part = run_family(suite, contenders[k], family)
    return part, time.perf_counter() - began
