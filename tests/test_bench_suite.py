"""The benchmark's worlds and pairs (sim/families.py, benchmark/suite.py): every family
gives valid, deterministic worlds; every pair is solvable at the unseen test's distances; the
splits are disjoint and fixed."""

from __future__ import annotations

import math

import numpy as np
import pytest

from mentor_core.benchmark import suite
from mentor_core.benchmark.suite import (
    FEASIBLE_SHARE,
    LIMIT_KEYS,
    PAIRS_PER_WORLD,
    PAPER_LIMIT,
    SPLITS,
    build_suite,
    reference_profile,
    scaled_limit,
    shipped_limits,
    top_pace,
    world_pairs,
)
from mentor_core.navigation.pairs import distance_range
from mentor_core.navigation.shortest_path import VisibilityGraph
from mentor_core.sim.families import FAMILIES
from mentor_core.sim.robots import get_profile
from mentor_core.sim.scenarios import CLEARANCE_FACTOR
from mentor_core.training.config import TrainerConfig, shipped_config
from mentor_core.training.trainer import make_problem


@pytest.mark.parametrize("family", sorted(FAMILIES))
def test_family_worlds_are_valid_and_deterministic(family: str) -> None:
    code, generate = FAMILIES[family]
    for seed in range(12):
        for size in (12.0, 4.0):  # both robots' test arenas
            a = generate(size, np.random.default_rng([seed, code]))
            b = generate(size, np.random.default_rng([seed, code]))
            assert a == b  # World validates its boxes: inside, no overlap
            assert a.size == size and len(a.obstacles) > 0
    w0 = generate(12.0, np.random.default_rng([0, code]))
    w1 = generate(12.0, np.random.default_rng([1, code]))
    assert w0 != w1


@pytest.mark.parametrize("robot", ["ugv", "swarm"])
def test_generated_worlds_are_solvable_and_deterministic(robot: str) -> None:
    profile = get_profile(robot)
    reference = reference_profile(profile)
    d_min, d_max = distance_range(profile, profile.test_arena)
    longest = FEASIBLE_SHARE * PAPER_LIMIT * top_pace(reference)
    clear = CLEARANCE_FACTOR * profile.half_diagonal
    for family in FAMILIES:
        world, pairs = world_pairs(family, 3, profile)
        again_world, again = world_pairs(family, 3, profile)
        assert world == again_world and [p.scenario for p in pairs] == [
            p.scenario for p in again]
        assert len(pairs) == PAIRS_PER_WORLD
        graph = VisibilityGraph(world, profile.half_diagonal)
        for p in pairs:
            start, goal = p.scenario.start[:2], p.scenario.goal
            assert d_min <= math.dist(start, goal) <= d_max
            assert world.free_at([start, goal], clear).all()
            assert graph.path(start, goal) is not None  # a path for the footprint exists
            assert p.shortest == pytest.approx(
                graph.to_disc(start, goal, profile.goal_radius))
            assert 0.0 < p.shortest <= longest
            assert p.time_limit == pytest.approx(scaled_limit(p.shortest, reference))


def test_distances_are_the_unseen_tests() -> None:
    ugv, swarm = get_profile("ugv"), get_profile("swarm")
    assert distance_range(ugv, 12.0) == pytest.approx((3.0, 12.0 * math.sqrt(2.0)))
    assert distance_range(swarm, 4.0) == pytest.approx((1.0, 2.0))


def test_scaled_limit_formula() -> None:
    ugv = reference_profile(get_profile("ugv"))  # steps <= 0.5 m, +-45 deg
    assert scaled_limit(10.0, ugv) == pytest.approx(2 * 10.0 / 0.5 + 4.0)
    swarm = reference_profile(get_profile("swarm"))  # steps <= 0.08 m
    assert scaled_limit(1.0, swarm) == pytest.approx(2 * 1.0 / 0.08 + 4.0)


@pytest.mark.parametrize("robot", ["ugv", "swarm"])
def test_shipped_limits_are_those_the_shipped_planners_train_with(robot: str) -> None:
    profile = get_profile(robot)
    trained = make_problem(shipped_config(robot)).profile
    limits = shipped_limits(profile)
    for key in LIMIT_KEYS:
        assert getattr(limits, key) == getattr(trained, key), key
    # the reference stays frozen whatever the shipped configs say
    assert reference_profile(profile).heading_change_max == pytest.approx(math.pi / 4)
    with pytest.raises(ValueError, match="no shipped config 'paper' for robot 'tank'"):
        shipped_config("tank")


def test_shipped_limits_follow_the_shipped_config_away_from_the_reference(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    ugv = get_profile("ugv")
    data = shipped_config("ugv").to_dict() | {"step_max": 0.75, "heading_change_max_deg": 30,
                                              "control_period": 0.5}
    monkeypatch.setattr(suite, "shipped_config", lambda robot: TrainerConfig.from_dict(data))
    limits = shipped_limits(ugv)
    assert limits.step_max == 0.75
    assert limits.heading_change_max == pytest.approx(math.pi / 6)
    assert limits.control_period == 0.5
    reference = reference_profile(ugv)  # frozen
    assert reference.control_period == ugv.control_period
    assert reference.step_max == 0.5
    assert reference.heading_change_max == pytest.approx(math.pi / 4)


def test_splits_are_disjoint_and_a_larger_suite_extends_a_smaller_one() -> None:
    profile = get_profile("swarm")
    small = build_suite(profile, "validation", ["slalom", "doe"], pairs_per_family=3)
    large = build_suite(profile, "validation", ["slalom", "doe"], pairs_per_family=7)
    test = build_suite(profile, "test", ["slalom", "doe"], pairs_per_family=7)
    assert [p.family for p in small.pairs] == ["slalom"] * 3 + ["doe"] * 3
    for family in ("slalom", "doe"):
        a = [p for p in small.pairs if p.family == family]
        b = [p for p in large.pairs if p.family == family]
        assert [p.scenario for p in a] == [p.scenario for p in b[:3]]
        assert {p.seed for p in b} == {0, 1}
    assert {p.seed for p in test.pairs} == {SPLITS["test"], SPLITS["test"] + 1}
    validation_worlds = {p.scenario.world for p in large.pairs}
    assert not validation_worlds & {p.scenario.world for p in test.pairs}


def test_bad_requests_are_refused() -> None:
    profile = get_profile("ugv")
    with pytest.raises(ValueError, match="unknown split"):
        build_suite(profile, "train")
    with pytest.raises(ValueError, match="unknown world family 'caves'"):
        build_suite(profile, families=["caves"])
    with pytest.raises(ValueError, match=r"in 1\.\.100000"):
        build_suite(profile, families=["doe"], pairs_per_family=0)
    with pytest.raises(ValueError, match="twice"):
        build_suite(profile, families=["doe", "doe"])
