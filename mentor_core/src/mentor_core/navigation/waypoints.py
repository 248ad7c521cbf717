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
at the length of the plan still to go), without the plan. The shortest ways are exact
(:class:`~mentor_core.navigation.goal_distance.GoalDistance`); which corner a point's way
turns at first is looked up on a grid computed once per scenario (:class:`WaypointGoals`), so
that a training run's every decision costs a lookup.

The ways keep the global planner's disc clear (the footprint's circumscribed radius plus the
margin, :attr:`~mentor_core.navigation.guide.GuideConfig.inflation`); a robot closer to an
obstacle than that disc is shown the way of the footprint's own disc, and one that has no
way at all the goal.
"""

from __future__ import annotations

import math
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
    shown the way; the robots of the others see their goal.

    Which way a point takes (straight into the disc, or round which corner of which disc's
    graph) is looked up on a grid of ``cell`` m (default: half the footprint's radius, to a
    millimetre) computed once per guided scenario; the aim is then computed from the robot's
    own position (its distance to that corner plus the corner's exact way on). So a decision
    costs a lookup, not a visibility test per corner, and the aim is exact wherever the
    robot's cell takes the robot's own way (all but a cell's width at the edges of what a
    corner sees). A class, not a closure, so that a training problem holding it pickles to
    pool workers."""

    def __init__(
        self, scenarios: Sequence[Scenario], config: GuideConfig, goal_radius: float,
        guided: Sequence[bool] | None = None, cell: float | None = None,
    ) -> None:  # fmt: skip
        if not scenarios:
            raise ValueError("WaypointGoals needs at least one scenario")
        if guided is not None and len(guided) != len(scenarios):
            raise ValueError(f"guided has {len(guided)} flags for {len(scenarios)} scenarios")
        flags = [True] * len(scenarios) if guided is None else [bool(g) for g in guided]
        self.cell = max(0.001, round(config.radius / 2.0, 3)) if cell is None else float(cell)
        if not self.cell > 0.0:
            raise ValueError(f"cell must be positive, got {cell}")
        self.goal_radius = float(goal_radius)
        self._goals = np.array([sc.goal[:2] for sc in scenarios], dtype=np.float64)
        graphs: dict[tuple[int, float], VisibilityGraph] = {}  # per world and disc, built once
        fields: list[tuple[FloatArray, FloatArray] | None] = []
        for sc, guide in zip(scenarios, flags, strict=True):
            if not guide:
                fields.append(None)
                continue
            ways = []
            for radius in (config.inflation, config.radius):
                key = (id(sc.world), radius)
                if key not in graphs:
                    graphs[key] = VisibilityGraph(sc.world, radius)
                ways.append(GoalDistance(graphs[key], sc.goal, goal_radius))
            fields.append(_field(ways, sc.world.size, self.cell))
        # one array over the scenarios, so that a decision is a few vectorised lookups: per
        # scenario and cell (row y, column x) the first corner (NaN: the goal is shown) and
        # the way on from it; a scenario that shows its goal is all NaN
        n = max((f[1].shape[0] for f in fields if f is not None), default=1)
        self.guided = [f is not None for f in fields]
        self._guided = np.array(self.guided, dtype=np.bool_)
        self._n = n
        # flat, so that a decision is one take per array: index (s * n + row y) * n + column x
        corners = np.full((len(fields), n, n, 2), np.nan)
        via = np.full((len(fields), n, n), np.nan)
        for s, f in enumerate(fields):
            if f is not None:
                k = f[1].shape[0]
                corners[s, :k, :k], via[s, :k, :k] = f
        self._corners = corners.reshape(-1, 2)
        self._via = via.reshape(-1)

    def __call__(self, poses: FloatArray, robots: IntArray) -> FloatArray:
        which = np.asarray(robots, dtype=np.int64) % len(self._goals)
        out = self._goals[which]
        rows = np.flatnonzero(self._guided[which])  # the others see their goal
        if not rows.size:
            return out
        here = np.asarray(poses, dtype=np.float64)[rows, :2]
        n = self._n
        ij = np.clip((here / self.cell).astype(np.int64), 0, n - 1)  # positions are >= 0
        flat = (which[rows] * n + ij[:, 1]) * n + ij[:, 0]
        on = self._via[flat]
        step = self._corners[flat] - here
        length = np.hypot(step[:, 0], step[:, 1])
        bend = np.isfinite(on) & (length > 0.0)
        scale = (length[bend] + on[bend] + self.goal_radius) / length[bend]
        out[rows[bend]] = here[bend] + step[bend] * scale[:, None]
        return out


def _field(
    ways: Sequence[GoalDistance], size: float, cell: float
) -> tuple[FloatArray, FloatArray]:
    """Per cell (row y, column x) of a ``size`` m square: the first corner ``(n, n, 2)`` of
    the way from the cell's centre, by the first of ``ways`` that has one (the planner's disc,
    then the body's), and the way on from that corner ``(n, n)``; NaN where the centre sees
    into the disc or has no way (the robot is then shown its goal)."""
    n = max(1, math.ceil(size / cell))
    centres = (np.arange(n) + 0.5) * cell
    xs, ys = np.meshgrid(centres, centres)
    points = np.column_stack([xs.ravel(), ys.ravel()])
    corners = np.full((len(points), 2), np.nan)
    via = np.full(len(points), np.nan)
    todo = np.arange(len(points))
    for way in ways:
        if not len(todo):
            break
        first = way.first_corners(points[todo])
        bend = first >= 0
        corners[todo[bend]] = way.graph.nodes[first[bend]]
        via[todo[bend]] = way.via[first[bend]]
        todo = todo[first == -2]  # no way for this disc: the next one
    return corners.reshape(n, n, 2), via.reshape(n, n)
