"""The goal a robot's network steers to when it follows a global plan (Nav2's planner /
controller split: a global path through the map, a local controller along it).

A :class:`PathGuide` holds one robot's global path, given (a ``nav_msgs/Path``) or planned on
a map (:class:`~mentor_core.navigation.grid_planner.GridPlanner`), and turns the robot's
position into the goal its network sees (:meth:`PathGuide.target`):

* the carrot: the point ``lookahead`` m along the path past the robot's progress ``s*``
  (:func:`~mentor_core.navigation.follow.lookahead_point`; progress never goes back), or, when
  the planner's disc cannot reach it in a straight line from the robot, the farthest of the
  points ``k lookahead / 8`` past ``s*`` (k = 7 .. 1) that it can (failing that, that the
  body's circle can: a robot closer to a wall than the disc);
* the network sees the goal in the carrot's direction at the distance still to go along the
  path, ``max(|carrot - p|, L - s*)``: a goal as far as the real one, as in training, rather
  than one that a lookahead ahead keeps arriving at (``S = R / d`` of the network's inputs
  would say the goal is near all the way);
* the final goal itself once the carrot reaches the path's end (the robot is within
  ``lookahead`` of it along the path), or when there is no path (no map, no path given, or
  none found: the plain planner's behaviour);
* a new plan, from where the robot is, when the goal changes, when the map changes, or when
  the robot has strayed more than ``replan_distance`` from its point on the path (if none is
  found from there, the old path stays). A given path is followed until the goal changes
  (then the map, if any, plans); a goal with no plan is not planned again until the goal or
  the map changes.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from mentor_core.navigation.follow import as_path, cumulative_length, lookahead_point, point_at
from mentor_core.navigation.grid import OccupancyGrid, world_grid
from mentor_core.navigation.grid_planner import GridPlanner
from mentor_core.sim.robots import RobotProfile
from mentor_core.sim.world import World

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
XY = tuple[float, float]
_SIGHT_STEPS = 8


@dataclass(frozen=True)
class GuideConfig:
    """How a robot follows a global plan (m throughout).

    Attributes:
        lookahead: distance of the carrot along the path past the robot's progress.
        replan_distance: plan again when the robot is farther than this from its path point.
        radius: the footprint's circumscribed radius (``RobotProfile.half_diagonal``).
        margin: added to ``radius`` for planning (the planner's inflation is their sum; with
            a clearance cost, what the plan keeps where it can).
        resolution: cell side used when a world is rasterised for planning.
        allow_unknown: unknown map cells are free (True, Nav2's default) or obstacles.
        tolerance: how far a start or goal may move onto a traversable cell (None: the
            planner's default).
        least_margin: the least margin (added to ``radius``) the plan may keep, at the
            clearance cost, where keeping ``margin`` means a long way round (None:
            ``margin``, a hard disc; :mod:`~mentor_core.navigation.grid_planner`).
        clearance_cost: the weight of that cost (the planner's ``clearance_cost``).
        plan_delay: decisions between asking for a plan on a scan map and following it (0:
            at once; :mod:`~mentor_core.navigation.plan_worker`), a planner's delay
            simulated in the benchmark.
        whole_scan: a scan map marks every ray of the lidar scan the readings were read off,
            where there is one, not only the sensors' readings.
    """

    lookahead: float
    replan_distance: float
    radius: float
    margin: float
    resolution: float
    allow_unknown: bool = True
    tolerance: float | None = None
    least_margin: float | None = None
    clearance_cost: float = 0.0
    plan_delay: int = 0
    whole_scan: bool = False

    def __post_init__(self) -> None:
        if not (isinstance(self.plan_delay, int) and self.plan_delay >= 0):
            raise ValueError(f"plan_delay must be a whole number >= 0, got {self.plan_delay}")
        for name in ("lookahead", "replan_distance", "resolution"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0.0):
                raise ValueError(f"{name} must be a positive number (m), got {value}")
        for name in ("radius", "margin"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value >= 0.0):
                raise ValueError(f"{name} must be a number >= 0 (m), got {value}")
        if not (math.isfinite(self.clearance_cost) and self.clearance_cost >= 0.0):
            raise ValueError(f"clearance_cost must be a number >= 0, got {self.clearance_cost}")
        least = self.least_margin
        if least is not None and not (math.isfinite(least) and 0.0 <= least <= self.margin):
            raise ValueError(f"least_margin must be a number in [0, margin] (m), got {least}")

    @property
    def inflation(self) -> float:
        """The planner's preferred disc radius (m): ``radius + margin``."""
        return self.radius + self.margin

    @property
    def hard_inflation(self) -> float:
        """The disc the plan must keep (m): ``radius + least_margin`` (``inflation`` without
        a clearance cost)."""
        return self.radius + (self.margin if self.least_margin is None else self.least_margin)

    def planner(self, grid: OccupancyGrid) -> GridPlanner:
        """A :class:`GridPlanner` on ``grid`` with these settings."""
        return GridPlanner(grid, self.hard_inflation, allow_unknown=self.allow_unknown,
                           tolerance=self.tolerance, preferred=self.inflation,
                           clearance_cost=self.clearance_cost)  # fmt: skip


def guide_config(
    profile: RobotProfile,
    *,
    lookahead: float | None = None,
    replan_distance: float | None = None,
    margin: float | None = None,
    resolution: float | None = None,
    allow_unknown: bool = True,
    least_margin: float | None = None,
    clearance_cost: float = 0.0,
) -> GuideConfig:
    """A robot's defaults, each replaced where given: ``lookahead`` twice the goal radius,
    ``replan_distance`` the lookahead, ``margin`` the footprint radius (the planner keeps a
    disc twice the body's clear: room for the network's wobble), ``resolution`` a
    quarter of the footprint radius rounded down to a millimetre, at most 0.05 m; no
    clearance cost (``least_margin``, ``clearance_cost``: :class:`GuideConfig`)."""
    body = profile.half_diagonal
    ahead = 2.0 * profile.goal_radius if lookahead is None else lookahead
    cell = min(0.05, math.floor(body / 4.0 * 1000.0) / 1000.0)
    return GuideConfig(
        lookahead=ahead,
        replan_distance=ahead if replan_distance is None else replan_distance,
        radius=body,
        margin=body if margin is None else margin,
        resolution=cell if resolution is None else resolution,
        allow_unknown=allow_unknown,
        least_margin=least_margin,
        clearance_cost=clearance_cost,
    )


class PathGuide:
    """One robot's global plan and the goal its network steers to (module docstring).

    ``planner`` may be shared by several guides on one map; :meth:`set_map` builds one.
    """

    def __init__(
        self, config: GuideConfig, planner: GridPlanner | None = None,
        plans_itself: bool = True,
    ) -> None:
        self.config = config
        self.planner = planner
        #: it plans itself (at a new goal, map or straying); False: plans come from
        #: :meth:`adopt` (made elsewhere, :mod:`~mentor_core.navigation.plan_worker`)
        self.plans_itself = plans_itself
        #: the last :meth:`target` found the robot off its path (beyond ``replan_distance``)
        self.strayed = False
        #: the path followed ``(k, 2)`` (m, ``map``), None without one
        self.path: FloatArray | None = None
        #: how many paths have been planned or given (a caller republishes when it changes)
        self.revision = 0
        #: the last carrot (x, y) steered to, None when the last target was the final goal
        self.carrot: XY | None = None
        self._given = False
        self._goal: XY | None = None
        self._failed: XY | None = None  # a goal no plan was found for
        self._from_s = 0.0
        self._lengths: FloatArray | None = None  # the path's cumulative lengths
        self._length = 0.0

    def set_map(self, grid: OccupancyGrid) -> None:
        """Plan on ``grid`` from now on; a planned path is planned again at the next target."""
        self.planner = self.config.planner(grid)
        self._failed = None
        if not self._given:
            self._set(None)

    def set_path(self, path: ArrayLike) -> None:
        """Follow ``path`` ``(k, 2)`` (m, ``map``) until the goal changes."""
        self._set(as_path(path))
        self._given = True

    def adopt(self, planner: GridPlanner, path: FloatArray | None) -> None:
        """Follow ``path`` (None: none found), planned elsewhere by ``planner`` (whose map
        the lines of sight to the carrot are checked on)."""
        self.planner = planner
        self._set(path)

    def _set(self, path: FloatArray | None) -> None:
        self.path = path
        self._from_s = 0.0
        self._lengths = None if path is None else cumulative_length(path)
        self._length = 0.0 if self._lengths is None else float(self._lengths[-1])
        self._given = False
        if path is not None:
            self.revision += 1

    def _plan(self, xy: XY, goal: XY) -> None:
        if self.planner is None or self._failed == goal or not self.plans_itself:
            return
        path = self.planner.plan(xy, goal)
        self._set(path)
        self._failed = goal if path is None else None

    def target(self, xy: ArrayLike, goal: ArrayLike) -> XY:
        """The goal (x, y) the network should see with the robot at ``xy`` and its final goal
        ``goal`` (module docstring)."""
        here = (float(np.asarray(xy)[0]), float(np.asarray(xy)[1]))
        final = (float(np.asarray(goal)[0]), float(np.asarray(goal)[1]))
        if final != self._goal:
            adopt = self._given and self._goal is None  # a path given before any goal
            self._goal = final
            self._failed = None
            if not adopt:
                self._set(None)
        self.carrot = None
        self.strayed = False
        if self.path is None:
            self._plan(here, final)
        if self.path is None:
            return final
        carrot, s = lookahead_point(
            self.path, here, self.config.lookahead, self._from_s, self._lengths
        )
        off = math.dist(here, point_at(self.path, s, self._lengths))
        self.strayed = off > self.config.replan_distance
        if self.strayed and self.plans_itself and self.planner is not None and not self._given:
            path = self.planner.plan(here, final)  # none from here: keep the old one
            if path is not None:
                self._set(path)
                carrot, s = lookahead_point(path, here, self.config.lookahead)
        self._from_s = s
        if s + self.config.lookahead >= self._length:
            return final
        self.carrot = aim = self._in_sight(here, s, carrot)
        d = math.dist(here, aim)
        if d == 0.0:
            return aim
        scale = max(d, self._length - s) / d
        return here[0] + (aim[0] - here[0]) * scale, here[1] + (aim[1] - here[1]) * scale

    def _in_sight(self, here: XY, s: float, carrot: XY) -> XY:
        """The farthest of the carrot and the points before it (eighths of the lookahead)
        that the planner's disc (with a clearance cost: its preferred disc first, then the
        disc it must keep) can reach in a straight line, else the body's circle (a robot
        closer to a wall than the planner's disc); the carrot if neither can."""
        if self.planner is None:
            return carrot
        assert self.path is not None
        points = [
            point_at(self.path, s + self.config.lookahead * k / _SIGHT_STEPS, self._lengths)
            for k in range(_SIGHT_STEPS, 0, -1)
        ]
        radii: tuple[float | None, ...] = (None, self.config.radius)
        if self.planner.preferred > self.planner.radius:
            radii = (self.planner.preferred, *radii)
        for radius in radii:
            for point in points:
                if self.planner.visible(here, point, radius):
                    return point
        return carrot


def guided_goals(
    guides: Sequence[PathGuide], goals: ArrayLike
) -> Callable[[FloatArray, IntArray], FloatArray]:
    """``input_goals(poses (m, 3), robots (m,)) -> (m, 2)`` for
    :func:`mentor_core.controller.episodes.run_episodes`: robot ``i`` follows ``guides[i]`` to
    ``goals[i]``."""
    final = np.asarray(goals, dtype=np.float64).reshape(-1, 2)

    def input_goals(poses: FloatArray, robots: IntArray) -> FloatArray:
        return np.array(
            [
                guides[i].target(pose[:2], final[i])
                for pose, i in zip(poses, robots.tolist(), strict=True)
            ],
            dtype=np.float64,
        ).reshape(-1, 2)

    return input_goals


def world_guides(world: World, config: GuideConfig, n: int) -> list[PathGuide]:
    """``n`` guides planning on ``world`` rasterised at ``config.resolution`` (one planner,
    shared), one per robot or scenario."""
    planner = config.planner(world_grid(world, config.resolution))
    return [PathGuide(config, planner) for _ in range(n)]
