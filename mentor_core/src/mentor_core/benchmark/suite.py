"""The benchmark suite: worlds of each family, solvable start/goal pairs, splits, time limits.

**Splits** (fixed here, once): world ``i`` of a family has the seed ``SPLITS[split] + i``,
validation ``0, 1, ...`` and test ``1,000,000, ...``; settings are chosen on the validation
split, the test split only reports. The world and its pairs come from one generator,
``np.random.default_rng([seed, family code])``: the world first (redrawn from the same
generator, at most ``WORLD_TRIES`` times, in the rare case that it holds fewer than
``PAIRS_PER_WORLD`` solvable pairs), then its pairs. A suite of ``N`` pairs per family
takes worlds ``0 .. ceil(N / 5) - 1``, five pairs each (the last one fewer), so a larger suite
extends a smaller one and the layouts are the same for both robots, each at its own scale.

**Pairs**, as the unseen test draws them (``scripts/make_unseen_bags.py``): start and goal
uniform over the points at least ``1.25`` half body diagonals from every obstacle and wall
(the trainer's clearance), straight distance in ``[size / 4, min(uncapped distance, size
sqrt 2)]`` (the robot file's time budget: UGV 3-17 m in the 12 m arena, Swarm-Robot 1-2 m
in the 4 m arena), start heading uniform. Each pair must be solvable: a path for the body's
circumscribed disc exists (``mentor_core.navigation.shortest_path``), and its length ``l``
into the goal radius is at most ``FEASIBLE_SHARE`` (0.7) of the paper's 50 s at the
reference planner's top pace (UGV 17.5 m, Swarm-Robot 2.8 m), so that the 50 s limit can be
met with room to spare.

**Time limits**: the paper's 50 s for every pair, and a limit scaled to the pair's shortest
path, ``T = 2 l / v + (pi / h) dt``: twice the time the shortest path takes at the top pace
``v = step_max / dt``, plus the time to turn round once at ``h`` per decision (UGV ``4 l +
4`` s, Swarm-Robot ``25 l + 4`` s).

**Reference planner**: the action limits of the planners shipped when the benchmark was
made (issue 15): heading change +-45 deg, UGV steps 0.02-0.5 m with a 0.2 m clearance margin,
Swarm-Robot steps 0.01-0.08 m with 0.05 m, egocentric inputs. They set the feasibility
bound and the scaled limits, so neither changes when the shipped training configs do, and
the oracle acts within them. The baselines act within them too, or within the limits of the
robot's shipped training config (:func:`shipped_limits`, ``mentor-bench --baseline-limits``),
so that they can act as the shipped planners do once those differ. An evolved planner runs
with its own (its genome's metadata), as ``mentor-eval`` runs it.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from mentor_core.navigation.pairs import (
    FEASIBLE_SHARE,
    distance_range,
    world_with_pairs,
)
from mentor_core.sim.families import FAMILIES
from mentor_core.sim.planner_settings import with_planner
from mentor_core.sim.robots import RobotProfile
from mentor_core.sim.world import Scenario, World
from mentor_core.training.config import shipped_config

SPLITS = {"validation": 0, "test": 1_000_000}
PAIRS_PER_WORLD = 5
#: the most pairs of a family in a suite: 20,000 worlds each, far inside the million seeds
#: between the splits (the validation split never reaches the test split's worlds), and about
#: 1 GB for nine families (some 1 kB a pair with its world)
MAX_PAIRS_PER_FAMILY = 100_000
PAPER_LIMIT = 50.0  # s, the paper's test limit
# the planners shipped with issue 15 (train_<robot>_paper.yaml), frozen for the benchmark
_REFERENCE: dict[str, dict[str, float | str | None]] = {
    "ugv": {"input_encoding": "egocentric", "heading_change_max": math.pi / 4,
            "step_max": 0.5, "step_min": 0.02, "clearance_margin": 0.2},
    "swarm": {"input_encoding": "egocentric", "heading_change_max": math.pi / 4,
              "step_max": None, "step_min": None, "clearance_margin": 0.05},
}  # fmt: skip


@dataclass(frozen=True)
class BenchPair:
    """One start/goal pair of the suite.

    Attributes:
        family: the world family's name.
        seed: the world's seed (``SPLITS[split] + world index``).
        index: the pair's place among its world's pairs.
        scenario: the world, start pose and goal.
        shortest: length of the shortest path into the goal radius for the body's
            circumscribed disc, m (SPL's ``l``).
        time_limit: the limit scaled to ``shortest``, s (module docstring).
    """

    family: str
    seed: int
    index: int
    scenario: Scenario
    shortest: float
    time_limit: float


@dataclass(frozen=True)
class Suite:
    """The pairs of one robot and split, family by family, world by world."""

    robot: str
    split: str
    reference: RobotProfile
    families: tuple[str, ...]
    pairs: tuple[BenchPair, ...]


def reference_profile(robot: RobotProfile) -> RobotProfile:
    """``robot`` with the reference planner's action limits (module docstring); a robot
    the benchmark does not know keeps its own."""
    settings = _REFERENCE.get(robot.name, {})
    return with_planner(robot, **settings, source="benchmark reference planner")


#: the planner settings that make a planner's action limits (the reference planner's keys)
LIMIT_KEYS = ("input_encoding", "heading_change_max", "step_max", "step_min", "clearance_margin",
              "control_period")


def shipped_limits(robot: RobotProfile) -> RobotProfile:
    """``robot`` with the action limits of its shipped paper-scale training config
    (``train_<robot>_paper.yaml``): those the shipped planners act with, for baselines that
    act as they do. ValueError for a robot without a shipped config."""
    settings = shipped_config(robot.name).planner_settings()
    chosen = {key: settings[key] for key in LIMIT_KEYS}
    return with_planner(robot, **chosen, source=f"train_{robot.name}_paper.yaml")


def top_pace(profile: RobotProfile) -> float:
    """The fastest a planner can go, ``step_max / control_period``, m/s."""
    return profile.step_max / profile.control_period


def scaled_limit(shortest: float, reference: RobotProfile) -> float:
    """``T = 2 l / v + (pi / h) dt`` (s) for a shortest path of ``l`` m (module docstring)."""
    turn = math.pi / reference.heading_change_max * reference.control_period
    return 2.0 * shortest / top_pace(reference) + turn


def world_pairs(
    family: str, seed: int, robot: RobotProfile, reference: RobotProfile | None = None
) -> tuple[World, list[BenchPair]]:
    """World ``seed`` of ``family`` at ``robot``'s test arena and its ``PAIRS_PER_WORLD``
    solvable pairs (module docstring). Deterministic for (family, seed, robot); ValueError for
    an unknown family or a world that holds too few pairs in ``WORLD_TRIES`` draws."""
    if family not in FAMILIES:
        raise ValueError(f"unknown world family {family!r} (known: {', '.join(FAMILIES)})")
    ref = reference_profile(robot) if reference is None else reference
    code, generate = FAMILIES[family]
    size = robot.test_arena
    world, drawn = world_with_pairs(
        generate, size, f"{family}-{seed}", robot, PAIRS_PER_WORLD, distance_range(robot, size),
        FEASIBLE_SHARE * PAPER_LIMIT * top_pace(ref), np.random.default_rng([seed, code]),
    )  # fmt: skip
    return world, [BenchPair(family, seed, k, scenario, length, scaled_limit(length, ref))
                   for k, (scenario, length) in enumerate(drawn)]  # fmt: skip


def build_suite(
    robot: RobotProfile, split: str = "validation", families: Sequence[str] | None = None,
    pairs_per_family: int = 20,
) -> Suite:
    """The suite of ``robot`` (its robot-file profile) on ``split``: ``pairs_per_family``
    pairs of each family (default: all, in ``FAMILIES`` order). ValueError for an unknown
    split or family or a count below 1."""
    if split not in SPLITS:
        raise ValueError(f"unknown split {split!r} (known: {', '.join(SPLITS)})")
    chosen = tuple(FAMILIES) if families is None else tuple(families)
    unknown = [f for f in chosen if f not in FAMILIES]
    if unknown or not chosen:
        raise ValueError(f"unknown world family {unknown[0] if unknown else ''!r} "
                         f"(known: {', '.join(FAMILIES)})")  # fmt: skip
    if len(set(chosen)) != len(chosen):
        raise ValueError("a world family is named twice")
    if not 1 <= pairs_per_family <= MAX_PAIRS_PER_FAMILY:
        raise ValueError(
            f"pairs per family must be in 1..{MAX_PAIRS_PER_FAMILY}, got {pairs_per_family}"
        )
    ref = reference_profile(robot)
    pairs: list[BenchPair] = []
    for family in chosen:
        left = pairs_per_family
        index = 0
        while left > 0:
            _, drawn = world_pairs(family, SPLITS[split] + index, robot, ref)
            pairs += drawn[:left]
            left -= len(drawn[:left])
            index += 1
    return Suite(robot.name, split, ref, chosen, tuple(pairs))
