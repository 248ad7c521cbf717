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
cost one sum per corner and a few visibility tests per robot
(:mod:`~mentor_core.navigation.goal_distance`),
all robots of a decision in one compiled loop, cheap enough to ask every decision of a
training run.

The ways keep the global planner's disc clear (the footprint's circumscribed radius plus the
margin, :attr:`~mentor_core.navigation.guide.GuideConfig.inflation`); a robot closer to an
obstacle than that disc is shown the way of the footprint's own disc, and one that has no
way at all the goal.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np
from numpy.typing import NDArray

from mentor_core.navigation import goal_distance
from mentor_core.navigation.goal_distance import GoalDistance, _first_corner
from mentor_core.navigation.guide import GuideConfig
from mentor_core.navigation.shortest_path import VisibilityGraph, _point_free, _segment_blocked
from mentor_core.sim.world import Scenario

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]


class WaypointGoals:
    """``input_goals(poses (m, 3), robots (m,)) -> (m, 2)`` for
    :func:`mentor_core.controller.episodes.run_episodes`: robot ``i`` on
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
        self._packed = _pack(self._ways)

    @property
    def guided(self) -> list[bool]:
        """Per scenario whether its robots are shown the way (else their goal)."""
        return [ways is not None for ways in self._ways]

    def __call__(self, poses: FloatArray, robots: IntArray) -> FloatArray:
        here = np.asarray(poses, dtype=np.float64)[:, :2]
        which = np.asarray(robots, dtype=np.int64) % len(self._ways)
        out = self._goals[which]
        if _aims_numba is not None:
            _aims_numba(np.ascontiguousarray(here), which, self._goals, self.goal_radius,
                        *self._packed, out)  # fmt: skip
            return out
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


Packed = tuple[IntArray, IntArray, IntArray, FloatArray, FloatArray, FloatArray, FloatArray,
               NDArray[np.bool_]]  # fmt: skip


def _pack(ways: Sequence[tuple[GoalDistance, ...] | None]) -> Packed:
    """The ways as flat arrays for :func:`_aims_loop`: ``(S, L)`` way numbers per scenario
    and level (-1: not guided), then per way its box and corner offsets (``W + 1`` each), the
    shrunk boxes, the corners, their ``L(v)``, the arena's free bounds ``(W, 2)`` and
    whether the goal is reachable."""
    levels = max((len(w) for w in ways if w is not None), default=0)
    number = np.full((len(ways), levels), -1, dtype=np.int64)
    flat: list[GoalDistance] = []
    for s, w in enumerate(ways):
        if w is not None:
            number[s, : len(w)] = np.arange(len(flat), len(flat) + len(w))
            flat += w
    box_at = np.cumsum([0] + [len(g.graph.shrunk) for g in flat]).astype(np.int64)
    node_at = np.cumsum([0] + [len(g.graph.nodes) for g in flat]).astype(np.int64)
    boxes = np.concatenate([g.graph.shrunk for g in flat]) if flat else np.zeros((0, 4))
    nodes = np.concatenate([g.graph.nodes for g in flat]) if flat else np.zeros((0, 2))
    via = np.concatenate([g.via for g in flat]) if flat else np.zeros(0)
    bounds = np.array([g.graph.bounds for g in flat], dtype=np.float64).reshape(-1, 2)
    reachable = np.array([g.reachable for g in flat], dtype=np.bool_)
    return (number, box_at, node_at, np.ascontiguousarray(boxes, dtype=np.float64),
            np.ascontiguousarray(nodes, dtype=np.float64), via.astype(np.float64), bounds,
            reachable)  # fmt: skip


def _aims_loop(
    here: FloatArray, which: IntArray, goals: FloatArray, goal_radius: float,
    number: IntArray, box_at: IntArray, node_at: IntArray, boxes: FloatArray,
    nodes: FloatArray, via: FloatArray, bounds: FloatArray, reachable: NDArray[np.bool_],
    out: FloatArray,
) -> None:  # fmt: skip
    """Compiled twin of :func:`_aims` for all robots at once (arrays of :func:`_pack`);
    ``out`` holds each robot's goal and gets its aim."""
    totals = np.empty(nodes.shape[0])  # scratch for any one way's corners
    r = goal_radius
    for i in range(here.shape[0]):
        s = which[i]
        px, py = here[i, 0], here[i, 1]
        gx, gy = goals[s, 0], goals[s, 1]
        for level in range(number.shape[1]):
            w = number[s, level]
            if w < 0:
                break  # not guided: it sees its goal
            if not reachable[w]:
                continue
            b = boxes[box_at[w] : box_at[w + 1]]
            if not _point_free(px, py, b, bounds[w, 0], bounds[w, 1]):
                continue
            gap = np.hypot(gx - px, gy - py)
            if gap <= r:
                break  # inside the disc: the goal
            ex, ey = gx - r * ((gx - px) / gap), gy - r * ((gy - py) / gap)
            if not _segment_blocked(px, py, ex, ey, b):
                break  # sees into the disc: the goal, bit for bit
            at, to = node_at[w], node_at[w + 1]
            c = nodes[at:to]
            dist, k = _first_corner(px, py, c, via[at:to], b, totals)
            if k < 0:
                continue  # no way at this level
            sx, sy = c[k, 0] - px, c[k, 1] - py
            length = np.hypot(sx, sy)
            if (c[k, 0] != gx or c[k, 1] != gy) and length > 0.0:
                scale = (dist + r) / length
                out[i, 0] = px + sx * scale
                out[i, 1] = py + sy * scale
            break


_aims_numba: Callable[..., None] | None
if goal_distance._first_corners_numba is not None:
    from numba import njit

    _aims_numba = njit(cache=True)(_aims_loop)
else:  # pragma: no cover - numba is in the lock file; numpy stays the fallback
    _aims_numba = None
