"""``mentor-bench --workers``: the benchmark's tasks on worker processes
(:mod:`mentor_core.benchmark.parallel`); the CLI's equality with one process is in
``test_bench_cli.py``."""

from __future__ import annotations

import functools

import numpy as np
import pytest

from mentor_core.benchmark.contenders import Contender, hand_written
from mentor_core.benchmark.parallel import run_parallel
from mentor_core.benchmark.runner import run_all
from mentor_core.benchmark.suite import Suite, build_suite, reference_profile
from mentor_core.errors import MentorError
from mentor_core.sim.robots import get_profile


def _setup(fail: bool = False) -> tuple[Suite, list[Contender]]:
    if fail:
        raise MentorError("planners/gone.json: no such file")
    robot = get_profile("ugv")
    suite = build_suite(robot, "validation", ["doe", "traps"], 2)
    return suite, [hand_written(n, reference_profile(robot)) for n in ("bug", "vfh")]


def test_workers_give_the_results_of_one_process_in_its_order() -> None:
    suite, contenders = _setup()
    lines: list[str] = []
    got = run_parallel(_setup, 2, lines.append)
    want = run_all(suite, contenders)
    assert [r.contender.name for r in got] == ["bug", "vfh"]
    for g, w in zip(got, want, strict=True):
        assert g.scores == w.scores
        assert np.array_equal(g.outcomes.path_length, w.outcomes.path_length)
    assert [line.split(":")[0] for line in lines] == ["bug", "bug", "vfh", "vfh"]
    assert "doe" in lines[0] and "traps" in lines[1]


def test_a_worker_that_cannot_start_is_one_error_not_a_hang() -> None:
    built = _setup()
    with pytest.raises(MentorError, match="a benchmark worker stopped"):
        run_parallel(functools.partial(_setup, fail=True), 2, built=built)


def test_at_least_one_worker() -> None:
    with pytest.raises(ValueError, match="workers must be at least 1"):
        run_parallel(_setup, 0)
