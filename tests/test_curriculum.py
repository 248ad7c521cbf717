"""Training worlds of the structured families (training/curriculum.py) and their config keys."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pytest
from numpy.typing import NDArray

from mentor_core.benchmark.suite import SPLITS, world_pairs
from mentor_core.cli.train import resolve_config
from mentor_core.errors import ConfigError
from mentor_core.evolution.genome import minimal_genome
from mentor_core.evolution.innovation import InnovationTracker
from mentor_core.navigation.pairs import distance_range
from mentor_core.navigation.shortest_path import VisibilityGraph
from mentor_core.sim.planner_settings import with_planner
from mentor_core.sim.robots import get_profile
from mentor_core.sim.world import Scenario
from mentor_core.training.config import TrainerConfig
from mentor_core.training.curriculum import drivable_length, family_scenarios, unseen_distances
from mentor_core.training.trainer import make_problem

FAMILIES = ("rooms", "slalom", "traps", "maze")


@pytest.mark.parametrize("robot", ["ugv", "swarm"])
def test_family_pairs_are_solvable_at_test_distances_and_seeded(robot: str) -> None:
    profile = get_profile(robot)
    planner = with_planner(profile, step_max=profile.step_max)
    pairs = family_scenarios(profile, planner, FAMILIES, 3, seed=0)
    again = family_scenarios(profile, planner, FAMILIES, 3, seed=0)
    other = family_scenarios(profile, planner, FAMILIES, 3, seed=1)
    assert len(pairs) == 12
    assert [(p.start, p.goal) for p in pairs] == [(p.start, p.goal) for p in again]
    assert [p.start for p in pairs] != [p.start for p in other]
    d_min, d_max = unseen_distances(profile, planner)
    assert (d_min, d_max) == distance_range(profile, profile.test_arena)  # not cut here
    for p in pairs:
        assert p.world.size == profile.train_arena
        d = float(np.hypot(p.goal[0] - p.start[0], p.goal[1] - p.start[1]))
        assert d_min <= d <= d_max
        graph = VisibilityGraph(p.world, profile.half_diagonal)
        assert np.isfinite(graph.to_disc(p.start[:2], p.goal, profile.goal_radius))


def test_no_training_world_is_a_benchmark_world() -> None:
    ugv = get_profile("ugv")
    trained = {p.world.obstacles.tobytes() for p in
               family_scenarios(ugv, ugv, FAMILIES, 1, seed=0)}  # fmt: skip
    for split in SPLITS.values():
        for family in FAMILIES:
            world, _ = world_pairs(family, split, ugv)
            assert world.obstacles.tobytes() not in trained


def test_config_adds_the_family_pairs_to_the_doe_scenarios() -> None:
    base = {"robot": "swarm", "n_scenarios": 4, "generations": 2, "stage1_generations": 1}
    plain = make_problem(TrainerConfig.from_dict(base))
    config = TrainerConfig.from_dict({**base, "families": ["rooms", "maze"], "family_pairs": 2})
    problem = make_problem(config)
    assert len(problem.scenarios) == 4 + 2 * 2
    assert [s.start for s in problem.scenarios[:4]] == [s.start for s in plain.scenarios]
    assert TrainerConfig.from_dict(config.to_dict()) == config


def _straight(scenarios: Sequence[Scenario]) -> NDArray[np.float64]:
    return np.array([np.hypot(s.goal[0] - s.start[0], s.goal[1] - s.start[1])
                     for s in scenarios])  # fmt: skip


def test_doe_pairs_at_the_test_distances() -> None:
    # issue 15, point 4: the shipped UGV (0.5 m steps) trained on 2-6.25 m, tested on 3-17 m
    base = {"robot": "ugv", "n_scenarios": 40, "step_max": 0.5, "generations": 2,
            "stage1_generations": 1}  # fmt: skip
    paper = make_problem(TrainerConfig.from_dict(base))
    test = make_problem(TrainerConfig.from_dict({**base, "pair_distances": "test"}))
    ugv = get_profile("ugv")
    lo, hi = unseen_distances(ugv, test.profile)
    assert (lo, hi) == (3.0, pytest.approx(12.0 * np.sqrt(2.0)))
    assert hi <= drivable_length(test.profile) == pytest.approx(0.7 * 50.0 * 0.5)
    d_paper, d_test = _straight(paper.scenarios), _straight(test.scenarios)
    assert d_paper.min() >= 2.0 * ugv.goal_radius and d_paper.max() <= 6.25
    assert d_test.min() >= lo and d_test.max() <= hi
    assert (d_test > 6.25).mean() > 0.4  # most of the test's range lies beyond the paper's
    same = paper.scenarios[0].world.obstacles, test.scenarios[0].world.obstacles
    assert same[0].tobytes() == same[1].tobytes()  # the same world, other pairs


def test_one_time_budget_for_every_training_scenario() -> None:
    base = {"robot": "swarm", "n_scenarios": 6, "generations": 2, "stage1_generations": 1}
    paper = make_problem(TrainerConfig.from_dict(base))
    fixed = make_problem(TrainerConfig.from_dict({**base, "time_budget": 50.0}))
    genome = minimal_genome(
        paper.n_inputs, 2, InnovationTracker(paper.n_inputs + 3), np.random.default_rng(0)
    )
    per_pair = paper.simulate([genome]).time_budget
    assert np.array_equal(per_pair, paper.profile.time_budgets(
        [s.start for s in paper.scenarios], [s.goal for s in paper.scenarios]))  # fmt: skip
    assert (per_pair < 50.0).any()
    assert np.array_equal(fixed.simulate([genome]).time_budget, np.full(6, 50.0))


@pytest.mark.parametrize(
    ("extra", "key"),
    [
        ({"pair_distances": "far"}, "pair_distances"),
        ({"time_budget": 0}, "time_budget"),
        ({"time_budget": "50"}, "time_budget"),
        ({"families": ["rooms", "castles"]}, "families"),
        ({"families": ["rooms", "rooms"]}, "families"),
        ({"families": "rooms"}, "families"),
        ({"family_pairs": 0}, "family_pairs"),
        ({"family_pairs": 2.5}, "family_pairs"),
    ],
)
def test_bad_curriculum_keys_are_named(extra: dict[str, object], key: str) -> None:
    with pytest.raises(ConfigError, match=key):
        TrainerConfig.from_dict({"robot": "swarm", **extra}, "c.yaml")


@pytest.mark.parametrize("robot", ["ugv", "swarm"])
def test_shipped_configs_paper_and_original(robot: str) -> None:
    # "original": the paper's own planner and training settings (the study's reference)
    original = resolve_config(robot, "dual", "original")
    assert (original.input_encoding, original.heading_change_max_deg, original.step_max,
            original.step_min, original.clearance_margin) == ("paper", None, None, None, None)
    assert original.doe.wall_count == (0, 0) and original.families == ()
    assert (original.pair_distances, original.time_budget) == ("paper", None)
    assert original.n_scenarios == get_profile(robot).train_scenarios  # Table I
    shipped = resolve_config(robot, "dual", "paper")
    # issue 15, point 4: the UGV trains at the test's distances (60 pairs), 50 decisions each
    # (25 s at 0.5 s a decision); the Swarm-Robot's paper draw already spans them
    expected = ("test", 25.0, 60, 0.5) if robot == "ugv" else ("paper", None, 20, None)
    assert (shipped.pair_distances, shipped.time_budget, shipped.n_scenarios,
            shipped.control_period) == expected
    assert original.control_period is None
