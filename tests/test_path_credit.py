"""A success credited with its path's efficiency (``success_credit: path``; not in the paper):
objectives.performance.path_credit, and F of training/problem.py under it."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from mentor_core.benchmark.scores import spl
from mentor_core.evolution.genome import minimal_genome
from mentor_core.evolution.innovation import InnovationTracker
from mentor_core.objectives.performance import (
    credited_performance,
    path_credit,
    scenario_performance,
)
from mentor_core.sim.world import Scenario, World
from mentor_core.training.config import TrainerConfig
from mentor_core.training.problem import NavigationProblem
from mentor_core.training.trainer import make_problem


def test_path_credit_is_shortest_over_driven() -> None:
    assert path_credit([4.0, 4.0, 0.0, 2.0], [5.0, 3.0, 0.0, 8.0]) == pytest.approx(
        [0.8, 1.0, 1.0, 0.25]
    )
    # the benchmark's SPL is the same term, for the successes only
    assert spl(np.array([True, False]), np.array([4.0, 4.0]), np.array([5.0, 5.0])) == (
        pytest.approx([0.8, 0.0])
    )


def test_credited_performance_with_the_time_share_is_the_papers() -> None:
    rng = np.random.default_rng(0)
    reached = rng.random(50) < 0.5
    budget = rng.uniform(10.0, 50.0, 50)
    left = rng.uniform(0.0, 1.0, 50) * budget
    final = rng.uniform(0.0, 5.0, 50)
    assert credited_performance(reached, left / budget, final) == pytest.approx(
        scenario_performance(reached, left, budget, final), abs=1e-15
    )
    with pytest.raises(ValueError, match="non-negative"):
        credited_performance(reached, left / budget, -final)


def test_a_straight_run_earns_full_credit() -> None:
    # a network with zero weights neither turns nor changes its step: from a start facing
    # the goal it drives the shortest path, so its path credit is 1 and F_i = 2, where the
    # time credit leaves it below 2
    config = dataclasses.replace(TrainerConfig(robot="ugv"), input_encoding="egocentric")
    profile = make_problem(config).profile
    empty = World(12.0, np.zeros((0, 4)))
    scenarios = [Scenario(empty, (2.0, 6.0, 0.0), (8.0, 6.0)),
                 Scenario(empty, (6.0, 2.0, np.pi / 2), (6.0, 10.0))]  # fmt: skip
    tracker = InnovationTracker(next_node_id=profile.n_inputs + 1 + profile.n_outputs)
    drawn = minimal_genome(profile.n_inputs, profile.n_outputs, tracker,
                           np.random.default_rng(0))  # fmt: skip
    still = drawn.with_connections(
        [dataclasses.replace(c, weight=0.0) for c in drawn.connections], list(drawn.nodes)
    )
    by_path = NavigationProblem(profile, scenarios, success_credit="path")
    by_time = NavigationProblem(profile, scenarios)
    batch = by_path.simulate([still])
    assert batch.reached.all()
    shortest = np.array([6.0, 8.0]) - profile.goal_radius
    driven = batch.path_length(profile)
    # the arrival is judged at the motion's samples: a few cm past the disc's edge at most
    assert (driven >= shortest - 1e-9).all() and (driven <= shortest + 0.05).all()
    f_path = by_path.evaluate([still]).objectives[0, 0]
    f_time = by_time.evaluate([still]).objectives[0, 0]
    assert f_path == pytest.approx(2.0 + np.sum(shortest / driven), abs=1e-12)
    assert f_path > 3.98
    assert f_time < 3.5
    with pytest.raises(ValueError, match="success_credit"):
        NavigationProblem(profile, scenarios, success_credit="speed")  # type: ignore[arg-type]
