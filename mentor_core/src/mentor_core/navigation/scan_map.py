"""A map a robot builds from its own range readings, and a global plan on it (the SLAM +
Nav2 pattern: a costmap from the sensors, unknown space planned as free).

:class:`ScanMap` starts unknown and, per decision, counts the cells each sensor ray passes
up to its reading as seen free and the cell of a reading short of the sensor range as hit
(a beam's reading on every ray of its cone; details on the class). :class:`ScanGuide` is
one robot's :class:`~mentor_core.navigation.guide.PathGuide` planning on its own
:class:`ScanMap` with unknown cells free: it plans again when a newly seen obstacle cell
lies within the planner's disc (plus a cell) of the path it follows, or when it has no
path. Nothing of the world is known but what the robot's sensors read from where it
has been; the memory of where obstacles are is the map.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from mentor_core.navigation.follow import cumulative_length, point_at, progress
from mentor_core.navigation.grid import (
    FREE,
    OCCUPIED,
    UNKNOWN,
    OccupancyGrid,
    disc_touches,
    grid_fault,
)
from mentor_core.navigation.guide import GuideConfig, PathGuide, guide_config
from mentor_core.sim.robots import RobotProfile
from mentor_core.sim.sensors import beam_frames, sensor_readings
from mentor_core.sim.world import Scenario

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]


class ScanMap:
    """The occupancy grid of what one robot has read (module docstring): ``size`` m square
    from ``origin`` (its lower-left corner, default ``(0, 0)``, the arena's), cells of
    ``resolution`` m; rays beyond it end on its border cells.

    Each cell counts the rays that ended in it (hits) and the rays that passed through it
    (misses); it is occupied while its hits are at least its misses, free when only rays
    passed, unknown when none came. A beam sensor reads the nearest hit of its cone: every
    ray of the cone is free up to the reading, and the hit is either put on every ray (the
    sonar model of Moravec and Elfes: the obstacle lies somewhere on that arc; rays that
    later pass a cell of the arc clear it) or, as :func:`scan_guided_goals` does unless
    asked, left out (an arc as wide as the cone closes gaps the robot could pass: measured
    in experiment E026, "A map of what the robot read").
    """

    def __init__(
        self, size: float, resolution: float, origin: tuple[float, float] = (0.0, 0.0)
    ) -> None:
        if not (math.isfinite(size) and size > 0 and math.isfinite(resolution) and resolution > 0):
            raise ValueError(f"size and resolution must be positive, got {size}, {resolution}")
        if not all(math.isfinite(v) for v in origin):
            raise ValueError(f"origin must be finite, got {origin}")
        fault = grid_fault(size, size, resolution, "the scan map")
        if fault:
            raise ValueError(fault)
        self.resolution = float(resolution)
        self.origin = (float(origin[0]), float(origin[1]))
        n = max(1, math.ceil(size / resolution))
        self.hits = np.zeros((n, n), dtype=np.int32)
        self.misses = np.zeros((n, n), dtype=np.int32)

    @property
    def data(self) -> NDArray[np.int8]:
        """``(n, n)`` cell values: -1 unknown, 0 free, 100 occupied (module docstring)."""
        out = np.full(self.hits.shape, UNKNOWN, dtype=np.int8)
        out[self.misses > 0] = FREE
        out[self._occupied()] = OCCUPIED
        return out

    def _occupied(self) -> NDArray[np.bool_]:
        return (self.hits > 0) & (self.hits >= self.misses)

    def update(
        self, rays: ArrayLike, readings: ArrayLike, max_range: float,
        located: ArrayLike | None = None,
    ) -> FloatArray:  # fmt: skip
        """Add rays from ``rays`` ``(k, 3)`` (x, y, heading) that read ``readings`` ``(k,)``
        (m, +inf out of range); ``located`` ``(k,)`` (default all): whether a ray's reading
        marks its end cell as hit, or only the free cells before it (a beam's reading, whose
        hit may lie on any of its rays). Returns the centres ``(j, 2)`` of the cells that
        became occupied."""
        f = np.asarray(rays, dtype=np.float64).reshape(-1, 3)
        r = np.asarray(readings, dtype=np.float64).reshape(-1)
        before = self._occupied()
        marks = np.ones(len(r), dtype=bool) if located is None else np.asarray(located, bool)
        hit = np.isfinite(r) & (r < max_range)
        reach = np.where(hit, r, max_range)
        step = 0.5 * self.resolution
        t = np.arange(math.ceil(max_range / step)) * step  # (s,)
        along = t[None, :] < reach[:, None] - step  # up to half a cell short of the hit
        cos, sin = np.cos(f[:, 2]), np.sin(f[:, 2])
        ys = f[:, 1, None] + sin[:, None] * t
        rows, cols = self._cells(ys, f[:, 0, None] + cos[:, None] * t)
        ray = np.broadcast_to(np.arange(len(f))[:, None], along.shape)
        n = self.hits.shape[0]
        cells = n * n
        # a ray counts once per cell it passes (keys: ray, then the cell's flat index)
        passed = np.unique((ray[along] * n + rows[along]) * n + cols[along]) % cells
        np.add.at(self.misses.reshape(-1), passed, 1)  # a view: the counts themselves
        hit &= marks
        ends = self._cells(f[hit, 1] + sin[hit] * reach[hit], f[hit, 0] + cos[hit] * reach[hit])
        ended = np.unique(ends[0] * n + ends[1])  # a cell hit by several rays of a cone: once
        np.add.at(self.hits.reshape(-1), ended, 1)
        rows, cols = np.nonzero(self._occupied() & ~before)
        return np.stack([(cols + 0.5), (rows + 0.5)], axis=1) * self.resolution + self.origin

    def grid(self) -> OccupancyGrid:
        """The map as an :class:`OccupancyGrid` (its origin the map's)."""
        return OccupancyGrid(self.resolution, (*self.origin, 0.0), self.data)

    def blocks(self, xy: ArrayLike, radius: float) -> bool:
        """Whether a robot of ``radius`` m at ``xy`` would touch a cell this map holds
        occupied (:func:`~mentor_core.navigation.grid.disc_touches`)."""
        p = (np.asarray(xy, dtype=np.float64).reshape(2) - self.origin) / self.resolution
        r = radius / self.resolution
        r0, c0 = max(0, math.floor(p[1] - r)), max(0, math.floor(p[0] - r))
        window = np.s_[r0 : math.floor(p[1] + r) + 2, c0 : math.floor(p[0] + r) + 2]
        hits = self.hits[window]
        return disc_touches((hits > 0) & (hits >= self.misses[window]), p - (c0, r0), r)

    def _cells(self, y: FloatArray, x: FloatArray) -> tuple[IntArray, IntArray]:
        n = self.hits.shape[0]
        x0, y0 = self.origin
        rows = np.clip(np.floor((y - y0) / self.resolution).astype(np.int64), 0, n - 1)
        cols = np.clip(np.floor((x - x0) / self.resolution).astype(np.int64), 0, n - 1)
        return rows, cols


class ScanGuide:
    """One robot's plan on its own :class:`ScanMap` of side ``size`` m from ``origin``
    (module docstring)."""

    def __init__(
        self, size: float, config: GuideConfig, origin: tuple[float, float] = (0.0, 0.0)
    ) -> None:
        self.map = ScanMap(size, config.resolution, origin)
        self.guide = PathGuide(config)
        self.guide.set_map(self.map.grid())
        self.plans = 0  # maps planned on, the first included

    def refresh(self) -> None:
        """Plan on the map as it is now at the next :meth:`target` (the plan followed is
        made only on the map as it was when a newly seen obstacle last blocked it)."""
        self.guide.set_map(self.map.grid())
        self.plans += 1

    def target(self, rays: ArrayLike, readings: ArrayLike, max_range: float,
               xy: ArrayLike, goal: ArrayLike,
               located: ArrayLike | None = None) -> tuple[float, float]:  # fmt: skip
        """Add the rays' readings to the map (:meth:`ScanMap.update`), plan again if they
        block the path, and return the goal the network should see
        (:meth:`PathGuide.target`)."""
        new = self.map.update(rays, readings, max_range, located)
        path = self.guide.path
        if new.size and (path is None or _near(new, path, self.guide.config)):
            self.guide.set_map(self.map.grid())
            self.plans += 1
        return self.guide.target(xy, goal)


    def read(self, pose: ArrayLike, readings: ArrayLike, goal: ArrayLike, profile: RobotProfile,
             beam_arcs: bool = False) -> tuple[float, float]:  # fmt: skip
        """:meth:`target` of a robot of ``profile`` at ``pose`` (x, y, theta) that read
        ``readings`` ``(k,)`` (m, +inf out of range), each sensor's reading on every ray of
        its beam; ``beam_arcs``: a beam's hit goes on every ray of its cone
        (:class:`ScanMap`), else only its free space counts."""
        p = np.asarray(pose, dtype=np.float64).reshape(1, 3)
        rays = beam_frames(p, profile)[0]  # (sensors, beam rays, 3)
        r = np.asarray(readings, dtype=np.float64).reshape(profile.n_sensors)
        per_ray = np.broadcast_to(r[:, None], rays.shape[:2]).reshape(-1)
        distinct = profile.distinct_rays.reshape(-1)  # beam_frames repeats a single ray
        located = np.repeat(beam_arcs | ~profile.beamed, profile.beam_rays)  # sensor-major
        return self.target(rays.reshape(-1, 3)[distinct], per_ray[distinct],
                           profile.sensor_range, p[0, :2], goal, located[distinct])  # fmt: skip


#: the scan map's finest cell, m: finer cells gained the Swarm-Robot nothing measurable
SCAN_CELL_MIN = 0.025


def scan_map_resolution(profile: RobotProfile) -> float:
    """The scan map's cell: a quarter of the footprint's circumscribed radius, to 5 mm, but
    not under :data:`SCAN_CELL_MIN` (0.05 m for the UGV, 0.025 m for the Swarm-Robot).
    Chosen on the validation split (experiment E050, "The scan map's cells"): the
    UGV's headline planners reach 92.6 % with 0.05 m cells, 91.1 % with 0.1 m (half the
    radius, before) and 81.9 % with 0.2 m; the Swarm-Robot's reach 88.6, 88.0 and 85.7 %
    with 0.0125, 0.025 and 0.05 m."""
    return max(SCAN_CELL_MIN, round(profile.half_diagonal / 4.0 / 0.005) * 0.005)


#: the carrot's distance along a plan on the scan map, in goal radii (the world-map guide's:
#: 2). Chosen on the validation split (experiment E046, "The carrot on the scan
#: map"): the UGV's planners behind the shim and the guard reach 91 % with 1-1.5 radii, 89 %
#: with 2 and 86 % with 4; the Swarm-Robot's are level (88 %) at 1.5 and 2.
SCAN_LOOKAHEAD_RADII = 1.5

#: the weight of the clearance cost of the plan on the scan map, per robot
#: (``navigation.grid_planner``): the plan keeps the whole margin (one footprint radius beyond
#: the footprint's, ``guide_config``) where that costs little and must keep
#: :data:`SCAN_LEAST_MARGIN_RADII` of it; a robot not named keeps the whole margin as a hard
#: disc. Chosen on the validation split (experiment E080, "A clearance cost on the
#: scan map's plan"): the Swarm-Robot's planners reach 92.8 % / SPL 0.856 against 91.9 % /
#: 0.842 with the hard disc, which closed gaps four of its body widths wide; the UGV's were
#: level (its dense forests gained 3 points, its mazes lost 4).
SCAN_CLEARANCE_COST: dict[str, float] = {"swarm": 1.0}

#: the least margin the plan on the scan map keeps with a clearance cost, in footprint radii
SCAN_LEAST_MARGIN_RADII = 0.5


def scan_guide_config(
    profile: RobotProfile, lookahead: float | None = None, resolution: float | None = None,
    least_margin: float | None = None, clearance_cost: float | None = None,
) -> GuideConfig:  # fmt: skip
    """The guide's settings on a scan map: :func:`~mentor_core.navigation.guide.guide_config`
    with cells of ``resolution`` m (default :func:`scan_map_resolution`), the carrot
    ``lookahead`` m along the plan (default :data:`SCAN_LOOKAHEAD_RADII` goal radii; the
    distance off the plan before planning again is the same) and the clearance cost
    ``clearance_cost`` for keeping less than the default margin, down to ``least_margin`` m
    (defaults: its robot's :data:`SCAN_CLEARANCE_COST`, :data:`SCAN_LEAST_MARGIN_RADII`
    footprint radii; a cost of 0: the margin is a hard disc) (a deployment's ``scan_map``)."""
    ahead = SCAN_LOOKAHEAD_RADII * profile.goal_radius if lookahead is None else lookahead
    cell = scan_map_resolution(profile) if resolution is None else resolution
    weight = SCAN_CLEARANCE_COST.get(profile.name, 0.0)
    weight = weight if clearance_cost is None else clearance_cost
    least = SCAN_LEAST_MARGIN_RADII * profile.half_diagonal
    least = least if least_margin is None else least_margin
    return guide_config(profile, lookahead=ahead, resolution=cell,
                        least_margin=least if weight > 0.0 else None,
                        clearance_cost=weight)  # fmt: skip


def _near(cells: FloatArray, path: FloatArray, config: GuideConfig) -> bool:
    """Whether a cell centre lies within the planner's disc plus a cell of the path (its
    nearest point on the path, :func:`~mentor_core.navigation.follow.progress`)."""
    reach = config.inflation + config.resolution
    s = cumulative_length(path)
    return any(math.dist(c, point_at(path, progress(path, c, 0.0, s), s)) <= reach for c in cells)


def scan_guided_goals(
    scenarios: Sequence[Scenario], profile: RobotProfile, config: GuideConfig,
    beam_arcs: bool = False,
) -> tuple[Callable[[FloatArray, IntArray], FloatArray], list[ScanGuide]]:  # fmt: skip
    """``input_goals`` for :func:`mentor_core.controller.episodes.run_episodes` on ``scenarios``:
    robot ``i`` plans on the map of what its own sensors read (the readings the simulator
    gives it at its pose), and the guides (for their maps and plan counts). ``beam_arcs``:
    a beam sensor's hit goes on every ray of its cone (:class:`ScanMap`), else only its free
    space counts."""
    guides = [ScanGuide(sc.world.size, config) for sc in scenarios]

    def input_goals(poses: FloatArray, robots: IntArray) -> FloatArray:
        out = np.empty((len(robots), 2), dtype=np.float64)
        for k, i in enumerate(robots.tolist()):
            sc = scenarios[i]
            readings = sensor_readings(poses[k : k + 1], profile, sc.world)[0]
            out[k] = guides[i].read(poses[k], readings, sc.goal, profile, beam_arcs)
        return out

    return input_goals, guides
