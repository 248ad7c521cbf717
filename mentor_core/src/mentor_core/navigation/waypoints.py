"""The goal a network sees when a teacher who knows the map shows it the way (training only).

For a robot at ``p`` on a scenario with goal ``g`` (radius ``R``), the teacher's next target
is the first point of the shortest way from ``p`` into the goal's disc
(:meth:`~mentor_core.navigation.goal_distance.GoalDistance.waypoints`: the goal itself when
``p`` sees into the disc, else the first corner of the way round). The network is shown
that direction at the distance still to go::

    aim(p) = p + (w(p) - p) / |w(p) - p| * (D(p) + R),

``D`` the shortest distance into the disc; a robot that sees into the disc is shown ``g``
itself, so that in the open the goal inputs are the paper's. This is how
:class:`~mentor_core.navigation.guide.PathGuide` shows a global plan's carrot (its direction,
at the length of the plan still to go), without the plan: the shortest ways are exact and
cost one visibility test per corner, cheap enough to ask every decision of a training run.

The ways keep the global planner's disc clear (the footprint's circumscribed radius plus the
margin, :attr:`~mentor_core.navigation.guide.GuideConfig.inflation`); a robot closer to an
obstacle than that disc is shown the way of the footprint's own disc, and one that has no
way at all the goal.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from mentor_core.navigation.goal_distance import GoalDistance
from mentor_core.navigation.guide import GuideConfig
from mentor_core.navigation.shortest_path import VisibilityGraph
from mentor_core.sim.world import Scenario

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]


class WaypointGoals:
    """``input_goals(poses (m, 3), robots (m,)) -> (m, 2)`` for
    :func:`mentor_core.sim.episode.run_episodes`: robot ``i`` on
    ``scenarios[i % len(scenarios)]`` is shown the way into the disc of ``goal_radius`` (m)
    about its goal (module docstring). Robots are indexed as
    :meth:`mentor_core.training.problem.NavigationProblem.simulate` numbers them (genome-major
    over the scenarios). ``guided`` (one bool per scenario; default all) names the scenarios
    shown the way; the robots of the others see their goal. A class, not a closure, so that a
    training problem holding it pickles to pool workers."""

    def __init__(
        self, scenarios: Sequence[Scenario], config: GuideConfig, goal_radius: float,
        guided: Sequence[bool] | None = None,
    ) -> None:  # fmt: skip
        if not scenarios:
            raise ValueError("WaypointGoals needs at least one scenario")
        if guided is not None and len(guided) != len(scenarios):
            raise ValueError(f"guided has {len(guided)} flags for {len(scenarios)} scenarios")
        flags = [True] * len(scenarios) if guided is None else [bool(g) for g in guided]
        self.goal_radius = float(goal_radius)
        graphs: dict[tuple[int, float], VisibilityGraph] = {}  # per world and disc, built once
        # per scenario its ways (the planner's disc's, then the body's); None: it shows its
        # goal, and nothing is built for it
        self._ways: list[tuple[GoalDistance, ...] | None] = []
        for sc, flag in zip(scenarios, flags, strict=True):
            if not flag:
                self._ways.append(None)
                continue
            pair = []
            for radius in (config.inflation, config.radius):
                key = (id(sc.world), radius)
                if key not in graphs:
                    graphs[key] = VisibilityGraph(sc.world, radius)
                pair.append(GoalDistance(graphs[key], sc.goal, goal_radius))
            self._ways.append(tuple(pair))
        self._goals = np.array([sc.goal[:2] for sc in scenarios], dtype=np.float64)

    @property
    def guided(self) -> list[bool]:
        """Per scenario whether its robots are shown the way (else their goal)."""
        return [ways is not None for ways in self._ways]

    def __call__(self, poses: FloatArray, robots: IntArray) -> FloatArray:
        here = np.asarray(poses, dtype=np.float64)[:, :2]
        which = np.asarray(robots, dtype=np.int64) % len(self._ways)
        out = self._goals[which]
        for s in np.unique(which).tolist():
            ways = self._ways[s]
            if ways is None:
                continue
            rows = np.flatnonzero(which == s)
            out[rows] = _aims(here[rows], ways, self.goal_radius, out[rows])
        return out


def _aims(
    here: FloatArray, ways: tuple[GoalDistance, ...], goal_radius: float,
    goal: FloatArray,
) -> FloatArray:  # fmt: skip
    """Each point's aim (module docstring): the planner's disc's way, else the body's, else
    the goal."""
    out = goal.copy()
    todo = np.arange(len(here))
    for way in ways:
        if not len(todo):
            break
        dist, corner = way.distances_and_waypoints(here[todo])
        found = np.isfinite(dist)
        rows = todo[found]
        step = corner[found] - here[rows]
        length = np.hypot(step[:, 0], step[:, 1])
        # a point that sees into the disc is shown the goal itself, bit for bit
        bend = np.any(corner[found] != goal[rows], axis=1) & (length > 0.0)
        scale = (dist[found][bend] + goal_radius) / length[bend]
        out[rows[bend]] = here[rows[bend]] + step[bend] * scale[:, None]
        todo = todo[~found]
    return out
