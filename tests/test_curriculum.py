"""Training worlds of the structured families (training/curriculum.py) and their config keys."""

from __future__ import annotations

import numpy as np
import pytest

from mentor_core.benchmark.suite import SPLITS, world_pairs
from mentor_core.errors import ConfigError
from mentor_core.navigation.pairs import distance_range
from mentor_core.navigation.shortest_path import VisibilityGraph
from mentor_core.sim.robots import get_profile, with_planner
from mentor_core.training.config import TrainerConfig
from mentor_core.training.curriculum import family_scenarios
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
    d_min, d_max = distance_range(profile, profile.train_arena)
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


@pytest.mark.parametrize(
    ("extra", "key"),
    [
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
