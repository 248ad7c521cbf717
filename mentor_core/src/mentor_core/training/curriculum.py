"""Training worlds of the structured families (a curriculum), with pairs at test distances.

The paper trains on one composite DoE world. Planners trained that way loop near the start,
follow a wall away and back, and miss doorways and the ends of walls in worlds of kinds they
never saw (issue 15). A config's ``families`` adds one training world of each named family
(:mod:`mentor_core.sim.families`: rooms, corridors, slalom, traps, forests, mazes) at the
training arena's side, with ``family_pairs`` start/goal pairs each, drawn as the benchmark
draws its pairs (:func:`mentor_core.navigation.pairs.solvable_pairs`): at the unseen test's
straight distances ``[size / 4, min(d*, size sqrt 2)]`` (``d*`` the robot file's uncapped
distance) and solvable for the body's circumscribed disc within what the planner can drive in
the time a training pair gets. :func:`unseen_distances` is that range, also used for the DoE's
pairs when a config asks for ``pair_distances: test`` (issue 15, point 4).

Seeds: world ``j`` of family ``f`` comes from ``default_rng([TRAINING_SEED_TAG, scenario_seed,
code_f])``; the benchmark's validation and test worlds use two-word seeds
``[seed, code_f]``, so no training world is a benchmark world.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from mentor_core.navigation.pairs import FEASIBLE_SHARE, distance_range, world_with_pairs
from mentor_core.sim.families import FAMILIES
from mentor_core.sim.robots import RobotProfile
from mentor_core.sim.world import Scenario

TRAINING_SEED_TAG = 7_000_001  # the first word of every training-world seed


def drivable_length(planner: RobotProfile) -> float:
    """Longest path a planner is asked to drive in training, m: ``FEASIBLE_SHARE`` of what its
    top pace covers within the time-budget cap (the benchmark's bound on a pair's shortest
    path; the trainer passes a planner whose cap is its config's ``time_budget`` when set)."""
    return FEASIBLE_SHARE * planner.time_budget_cap * planner.step_max / planner.control_period


def unseen_distances(robot: RobotProfile, planner: RobotProfile) -> tuple[float, float]:
    """Straight start-goal distances of training pairs "at the test's distances", m: the
    unseen test's range (:func:`~mentor_core.navigation.pairs.distance_range` at the robot's
    test arena) up to :func:`drivable_length`.

    ``robot`` is the robot file's profile (its test arena and uncapped distance), ``planner``
    the profile as trained (its top pace). For the UGV stepping 0.5 m: 3-17 m (the paper's
    DoE pairs: 2-6.25 m, capped by the lowered rated speed).
    """
    lo, hi = distance_range(robot, robot.test_arena)
    return lo, min(hi, drivable_length(planner))


def family_scenarios(
    robot: RobotProfile, planner: RobotProfile, families: Sequence[str], pairs: int, seed: int
) -> list[Scenario]:
    """``pairs`` training pairs in one world of each family (in the order given).

    ``robot`` is the robot file's profile (its distances), ``planner`` the profile as trained
    (its top pace and time-budget cap bound the shortest path). ValueError for an unknown
    family, or a family whose worlds hold too few pairs.
    """
    size = robot.train_arena
    distances = unseen_distances(robot, planner)
    longest = drivable_length(planner)
    found: list[Scenario] = []
    for family in families:
        if family not in FAMILIES:
            raise ValueError(f"unknown world family {family!r} (known: {', '.join(FAMILIES)})")
        code, generate = FAMILIES[family]
        rng = np.random.default_rng([TRAINING_SEED_TAG, seed, code])
        name = f"{robot.name}-train-{family}-{seed}"
        _, chosen = world_with_pairs(generate, size, name, robot, pairs, distances, longest, rng)
        found += [scenario for scenario, _ in chosen]
    return found
