"""Start/goal pairs a robot can drive: drawn in free space, kept when a path exists.

A candidate pair is drawn as the trainer's DoE draws them (``mentor_core.sim.scenarios``):
start and goal uniform over the points at least ``1.25`` half body diagonals from every
obstacle and wall, start heading uniform in (-pi, pi], straight distance in a given range. It
is kept when the shortest path of the body's circumscribed disc into the goal radius
(:mod:`mentor_core.navigation.shortest_path`) exists and is at most ``longest`` m long.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from mentor_core.navigation.shortest_path import VisibilityGraph
from mentor_core.sim.robots import RobotProfile
from mentor_core.sim.scenarios import CLEARANCE_FACTOR
from mentor_core.sim.world import Scenario, World

BATCH = 64  # candidate pairs per draw
ROUNDS = 40  # draws before a world counts as too crowded for its pairs
WORLD_TRIES = 10  # worlds drawn before a layout counts as too crowded for its pairs
#: share of a time limit the shortest path may take at the planner's top pace
FEASIBLE_SHARE = 0.7


def distance_range(robot: RobotProfile, size: float) -> tuple[float, float]:
    """Straight start-goal distances of the unseen test in an arena of side ``size``, m:
    ``[size / 4, min(uncapped distance, size sqrt 2)]`` (``scripts/make_unseen_bags.py``)."""
    return size / 4.0, min(robot.uncapped_distance, size * math.sqrt(2.0))


def solvable_pairs(
    world: World,
    robot: RobotProfile,
    count: int,
    distances: tuple[float, float],
    longest: float,
    rng: np.random.Generator,
) -> list[tuple[Scenario, float]]:
    """Up to ``count`` pairs of ``world`` with their shortest path lengths (m), in drawing
    order; fewer when ``ROUNDS`` draws of ``BATCH`` candidates do not hold them.

    ``distances`` is the straight start-goal range ``(d_min, d_max)``, m.
    """
    clear = CLEARANCE_FACTOR * robot.half_diagonal
    graph = VisibilityGraph(world, robot.half_diagonal)
    d_min, d_max = distances
    lo, hi = clear, world.size - clear
    found: list[tuple[Scenario, float]] = []
    for _ in range(ROUNDS):
        starts = rng.uniform(lo, hi, (BATCH, 2))
        goals = rng.uniform(lo, hi, (BATCH, 2))
        headings = np.pi - 2.0 * np.pi * rng.random(BATCH)  # (-pi, pi]
        dist = np.hypot(*(goals - starts).T)
        ok = (world.free_at(starts, clear) & world.free_at(goals, clear)
              & (dist >= d_min) & (dist <= d_max))  # fmt: skip
        for i in np.flatnonzero(ok):
            length = graph.to_disc(starts[i], goals[i], robot.goal_radius)
            if not length <= longest:  # inf (no path) or too long
                continue
            start = (float(starts[i, 0]), float(starts[i, 1]), float(headings[i]))
            found.append((Scenario(world, start, (float(goals[i, 0]), float(goals[i, 1]))),
                          length))  # fmt: skip
            if len(found) == count:
                return found
    return found


def world_with_pairs(
    generate: Callable[[float, np.random.Generator], World],
    size: float,
    name: str,
    robot: RobotProfile,
    count: int,
    distances: tuple[float, float],
    longest: float,
    rng: np.random.Generator,
) -> tuple[World, list[tuple[Scenario, float]]]:
    """A world of side ``size`` from ``generate`` holding ``count`` :func:`solvable_pairs`,
    world and pairs drawn from ``rng`` in turn; the world is drawn again, at most
    ``WORLD_TRIES`` times, while it holds fewer. ValueError when none does."""
    for _ in range(WORLD_TRIES):
        drawn = generate(size, rng)
        world = World(drawn.size, drawn.obstacles, name=name)
        pairs = solvable_pairs(world, robot, count, distances, longest, rng)
        if len(pairs) == count:
            return world, pairs
    raise ValueError(f"{name}: too few solvable start/goal pairs")
