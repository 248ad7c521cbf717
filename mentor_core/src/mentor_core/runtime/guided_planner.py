"""The planner with a global plan: the genome's network steered along a path (Nav2's
planner / controller split, with the evolved network as the controller).

:class:`GuidedPlanner` decides as :class:`~mentor_core.runtime.planner.GenomePlanner` does,
the same network inputs and actions, but the goal its network sees is the one a
:class:`~mentor_core.navigation.guide.PathGuide` gives: the carrot a lookahead distance along
the global path (given, or planned on the map it was handed), the final goal near the path's
end. The planner node calls it with the map and paths it receives; ``mentor-eval
--global-plan`` runs the same guide offline (:func:`mentor_core.navigation.guide.guided_goals`).
:class:`ScanGuidedPlanner` plans on the map of what the robot itself has read instead
(:class:`~mentor_core.navigation.scan_map.ScanGuide`), as ``mentor-bench`` and ``mentor-eval``
run a deployment with a ``scan_map``
(:func:`mentor_core.navigation.scan_map.scan_guided_goals`).

:func:`wire_grid` is the grid a ``nav_msgs/OccupancyGrid`` carries (its resolution is a
float32), so an in-process episode plans on exactly what the planner node receives.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Protocol

import numpy as np
from numpy.typing import ArrayLike, NDArray

from mentor_core.navigation.grid import MAX_CELLS, OccupancyGrid, disc_touches
from mentor_core.navigation.guide import GuideConfig, PathGuide
from mentor_core.navigation.plan_worker import PlanWorker
from mentor_core.navigation.scan_map import ScanGuide
from mentor_core.runtime.planner import GenomePlanner
from mentor_core.sim.robots import RobotProfile
from mentor_core.sim.scan_adapter import MountedScan


class Controller(Protocol):
    """What steers along a plan: :class:`~mentor_core.runtime.planner.GenomePlanner`, or a
    hand-written policy in the same decision chain (the IR-SIM baselines)."""

    @property
    def profile(self) -> RobotProfile:
        """The robot it decides for (its sensors)."""

    def reset(self) -> None:
        """Start blank (a new goal or episode)."""

    def decide(self, ranges: ArrayLike, pose: ArrayLike, goal: ArrayLike) -> tuple[float, float]:
        """``(dtheta, ds)`` (rad, m) for readings, pose and goal."""


def _xy(goal: ArrayLike) -> str:
    x, y = np.asarray(goal, dtype=np.float64).reshape(2)
    return f"({x:.3f}, {y:.3f})"


def wire_grid(grid: OccupancyGrid) -> OccupancyGrid:
    """``grid`` as a ``nav_msgs/OccupancyGrid`` carries it: the resolution rounded to float32."""
    return replace(grid, resolution=float(np.float32(grid.resolution)))


class GuidedPlanner:
    """An evolved genome steering towards a guide's goal (module docstring).

    Args:
        planner: the genome's planner (network, profile, limits).
        config: the guide's settings (:func:`mentor_core.navigation.guide.guide_config`).
    """

    def __init__(self, planner: GenomePlanner, config: GuideConfig) -> None:
        self.planner = planner
        self.guide = PathGuide(config)
        self._obstacles: tuple[OccupancyGrid, NDArray[np.bool_]] | None = None

    def reset(self) -> None:
        """Start the network blank (a new goal or episode; :meth:`GenomePlanner.reset`)."""
        self.planner.reset()

    def set_map(self, grid: OccupancyGrid) -> None:
        """Plan on ``grid`` from now on (see :meth:`PathGuide.set_map`)."""
        self.guide.set_map(grid)

    def set_path(self, path: ArrayLike) -> None:
        """Follow ``path`` ``(k, 2)`` until the goal changes (see :meth:`PathGuide.set_path`)."""
        self.guide.set_path(path)

    def goal_fault(self, goal: ArrayLike) -> str:
        """Why ``goal`` (x, y) cannot be reached on the map planned on (one line: it lies in
        an obstacle, where the robot's footprint would touch one), or '' (also without a
        map). A goal no plan reaches is not refused: the robot then steers to it as the plain
        planner does, and the node's progress checker and time limit judge it."""
        planner = self.guide.planner
        if planner is None:
            return ""
        grid = planner.grid
        if self._obstacles is None or self._obstacles[0] is not grid:  # once a map
            self._obstacles = (grid, grid.obstacles(unknown_is_obstacle=False))
        cells = grid.to_local(goal)[0] / grid.resolution
        if disc_touches(self._obstacles[1], cells, self.guide.config.radius / grid.resolution):
            return f"goal {_xy(goal)} lies in an obstacle of the map"
        return ""

    def decide(self, ranges: ArrayLike, pose: ArrayLike, goal: ArrayLike) -> tuple[float, float]:
        """Decision ``(dtheta, ds)`` (rad, m) as :meth:`GenomePlanner.decide`, the network
        seeing the guide's goal instead of ``goal``."""
        p = np.asarray(pose, dtype=np.float64).reshape(3)
        aim = self.guide.target(p[:2], goal)
        return self.planner.decide(ranges, p, aim)


class ScanGuidedPlanner:
    """An evolved genome steering along a plan on the map of its own readings (module
    docstring): a map of side ``size`` m from ``origin`` (its lower-left corner, in the frame
    the poses are in), or with ``size`` None a map that grows from where the robot starts up
    to ``max_cells`` cells (then rolls); unknown space planned as free.

    Args:
        planner: the genome's planner (network, profile, limits), or any :class:`Controller`.
        config: the guide's settings (:func:`mentor_core.navigation.guide.guide_config`).
        worker: where plans are made (None: at once, as the benchmark makes them;
            :class:`~mentor_core.navigation.plan_worker.ThreadPlans`: beside the decisions),
            and ``replan_every`` s: plan again when the plan is that old (0: never for its
            age) (:class:`~mentor_core.navigation.scan_map.ScanGuide`).
    """

    def __init__(
        self, planner: Controller, config: GuideConfig, size: float | None,
        origin: tuple[float, float] = (0.0, 0.0), worker: PlanWorker | None = None,
        replan_every: float = 0.0, max_cells: int = MAX_CELLS,
    ) -> None:  # fmt: skip
        self.planner = planner
        self._blank = dict(size=None if size is None else float(size), config=config,
                           origin=(float(origin[0]), float(origin[1])), worker=worker,
                           replan_every=replan_every, max_cells=max_cells)  # fmt: skip
        self.scan = ScanGuide(**self._blank)  # type: ignore[arg-type]

    @property
    def guide(self) -> PathGuide:
        """The plan followed (its ``path`` and ``revision``)."""
        return self.scan.guide

    def reset(self, keep_map: bool = False) -> None:
        """Start blank (a new goal or episode): the network as :meth:`GenomePlanner.reset`,
        and an empty map, as each episode of ``mentor-bench`` starts; with
        ``keep_map`` the map stays (a robot sent to its next goal in the same place) and the
        next plan is made on all of it."""
        self.planner.reset()
        if keep_map:
            self.scan.refresh()
        else:
            self.scan = ScanGuide(**self._blank)  # type: ignore[arg-type]

    def goal_fault(self, goal: ArrayLike) -> str:
        """Why ``goal`` (x, y) cannot be reached on the scan map (one line: it lies in an
        obstacle the scans have seen, where the robot's footprint would touch it), or '' (as
        :meth:`GuidedPlanner.goal_fault`)."""
        if self.scan.map.blocks(goal, self.guide.config.radius):
            return f"goal {_xy(goal)} lies in an obstacle the scans have seen"
        return ""

    def decide(
        self, ranges: ArrayLike, pose: ArrayLike, goal: ArrayLike,
        scan: MountedScan | None = None,
    ) -> tuple[float, float]:  # fmt: skip
        """Decision ``(dtheta, ds)`` (rad, m) as :meth:`GenomePlanner.decide`, after adding
        ``ranges`` to the map, or, with the config's ``whole_scan``, every ray of ``scan``,
        the lidar scan they were read off (to the profile's sensor range); the network sees
        the guide's goal instead of ``goal``."""
        p = np.asarray(pose, dtype=np.float64).reshape(3)
        profile = self.planner.profile
        if scan is not None and self.scan.guide.config.whole_scan:
            rays, read = scan.rays(p)
            aim = self.scan.target(rays, read, profile.sensor_range, p[:2], goal)
        else:
            aim = self.scan.read(p, ranges, goal, profile)
        return self.planner.decide(ranges, p, aim)
