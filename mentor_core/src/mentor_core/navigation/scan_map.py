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
import time
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from mentor_core.navigation.follow import cumulative_length, point_at, progress
from mentor_core.navigation.grid import (
    FREE,
    MAX_CELLS,
    OCCUPIED,
    UNKNOWN,
    OccupancyGrid,
    disc_touches,
    grid_fault,
)
from mentor_core.navigation.guide import GuideConfig, PathGuide, guide_config
from mentor_core.navigation.plan_worker import DelayedPlans, PlanJob, PlanWorker
from mentor_core.sim.robots import RobotProfile
from mentor_core.sim.sensors import beam_frames, sensor_readings
from mentor_core.sim.world import Scenario

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
XY = tuple[float, float]


class ScanMap:
    """The occupancy grid of what one robot has read (module docstring): ``size`` m square
    from ``origin`` (its lower-left corner, default ``(0, 0)``, the arena's), cells of
    ``resolution`` m; rays beyond it end on its border cells. With ``size`` None it has no
    border to set: it grows (:meth:`cover`) to hold every ray and goal, from the first pose,
    up to ``max_cells`` cells; beyond that it rolls, as Nav2's rolling costmap does, keeping
    the square of ``max_cells`` about the robot and forgetting what lies outside it.

    Each cell counts the rays that ended in it (hits) and the rays that passed through it
    (misses); it is occupied while its hits are at least its misses, free when only rays
    passed, unknown when none came. A beam sensor reads the nearest hit of its cone: every
    ray of the cone is free up to the reading, and the hit is either put on every ray (the
    sonar model of Moravec and Elfes: the obstacle lies somewhere on that arc; rays that
    later pass a cell of the arc clear it) or, as :func:`scan_guided_goals` does unless
    asked, left out (an arc as wide as the cone closes gaps the robot could pass: measured
    in experiment E026, "A map of what the robot read").

    The counts are 16-bit (a cell saturates after 65,535 rays, minutes of a robot standing
    still, and keeps its last state); a decision touches only the cells its rays cross, in a
    compiled kernel, so its cost does not grow with the map.
    """

    def __init__(
        self, size: float | None, resolution: float, origin: tuple[float, float] = (0.0, 0.0),
        max_cells: int = MAX_CELLS,
    ) -> None:  # fmt: skip
        if not (math.isfinite(resolution) and resolution > 0):
            raise ValueError(f"resolution must be positive, got {resolution}")
        if size is not None and not (math.isfinite(size) and size > 0):
            raise ValueError(f"size and resolution must be positive, got {size}, {resolution}")
        if not all(math.isfinite(v) for v in origin):
            raise ValueError(f"origin must be finite, got {origin}")
        if max_cells < 1:
            raise ValueError(f"max_cells must be at least 1, got {max_cells}")
        self.resolution = float(resolution)
        self.growing = size is None
        #: the most cells the map holds (its memory: :attr:`nbytes`)
        self.max_cells = int(max_cells) if self.growing else MAX_CELLS
        n = 0
        if size is not None:
            fault = grid_fault(size, size, resolution, "the scan map")
            if fault:
                raise ValueError(fault)
            n = max(1, math.ceil(size / resolution))
        self.origin = (float(origin[0]), float(origin[1]))
        self.hits = np.zeros((n, n), dtype=np.uint16)
        self.misses = np.zeros((n, n), dtype=np.uint16)
        #: ``(n, n)``: cells held occupied now (hits >= misses > ... module docstring)
        self.occupied = np.zeros((n, n), dtype=np.bool_)

    @property
    def nbytes(self) -> int:
        """The memory its cells hold (bytes)."""
        return int(self.hits.nbytes + self.misses.nbytes + self.occupied.nbytes)

    @property
    def data(self) -> NDArray[np.int8]:
        """``(n, n)`` cell values: -1 unknown, 0 free, 100 occupied (module docstring)."""
        return _values(self.misses, self.occupied)

    def cover(self, xmin: float, ymin: float, xmax: float, ymax: float,
              centre: tuple[float, float] | None = None) -> None:  # fmt: skip
        """Grow a growing map to hold the box ``[xmin, xmax] x [ymin, ymax]`` (m), in steps
        of :data:`GROW_CELLS` cells on a lattice fixed by its first cover, so cells never
        move; beyond ``max_cells`` the square about ``centre`` (default the box's) that fits
        (a no-op for a map of fixed size)."""
        if not self.growing:
            return
        res, step = self.resolution, GROW_CELLS
        n_rows, n_cols = self.hits.shape
        if n_rows == 0:  # the first cover fixes the lattice: cells of res from a step's corner
            self.origin = (math.floor(xmin / res / step) * step * res,
                           math.floor(ymin / res / step) * step * res)  # fmt: skip
        x0, y0 = self.origin
        c0 = min(0, math.floor((xmin - x0) / res / step) * step)
        r0 = min(0, math.floor((ymin - y0) / res / step) * step)
        c1 = max(n_cols, math.ceil((xmax - x0) / res / step) * step)
        r1 = max(n_rows, math.ceil((ymax - y0) / res / step) * step)
        if (c0, r0, c1, r1) == (0, 0, n_cols, n_rows):
            return
        side = max(step, math.isqrt(self.max_cells) // step * step)
        if (r1 - r0) * (c1 - c0) > self.max_cells:  # roll: the square about the centre
            cx, cy = centre if centre is not None else ((xmin + xmax) / 2, (ymin + ymax) / 2)
            c0 = math.floor(((cx - x0) / res - side / 2) / step) * step
            r0 = math.floor(((cy - y0) / res - side / 2) / step) * step
            c1, r1 = c0 + side, r0 + side
        self._reframe(r0, c0, r1 - r0, c1 - c0)

    def _reframe(self, r0: int, c0: int, rows: int, cols: int) -> None:
        """Hold cells ``[r0, r0 + rows) x [c0, c0 + cols)`` of the current lattice (keeping
        what overlaps, forgetting the rest)."""
        n_rows, n_cols = self.hits.shape
        sr0, sc0 = max(r0, 0), max(c0, 0)
        sr1, sc1 = min(r0 + rows, n_rows), min(c0 + cols, n_cols)

        def moved(a: NDArray[Any]) -> NDArray[Any]:
            b = np.zeros((rows, cols), dtype=a.dtype)
            if sr0 < sr1 and sc0 < sc1:
                b[sr0 - r0 : sr1 - r0, sc0 - c0 : sc1 - c0] = a[sr0:sr1, sc0:sc1]
            return b

        self.hits, self.misses = moved(self.hits), moved(self.misses)
        self.occupied = moved(self.occupied)
        res = self.resolution
        self.origin = (self.origin[0] + c0 * res, self.origin[1] + r0 * res)

    def update(
        self, rays: ArrayLike, readings: ArrayLike, max_range: float,
        located: ArrayLike | None = None,
    ) -> FloatArray:  # fmt: skip
        """Add rays from ``rays`` ``(k, 3)`` (x, y, heading) that read ``readings`` ``(k,)``
        (m, +inf out of range); ``located`` ``(k,)`` (default all): whether a ray's reading
        marks its end cell as hit, or only the free cells before it (a beam's reading, whose
        hit may lie on any of its rays). Returns the centres ``(j, 2)`` of the cells that
        became occupied, in row-major order."""
        f = np.ascontiguousarray(np.asarray(rays, dtype=np.float64).reshape(-1, 3))
        r = np.asarray(readings, dtype=np.float64).reshape(-1)
        marks = np.ones(len(r), dtype=bool) if located is None else np.asarray(located, bool)
        if self.growing and len(f):
            reach = max_range + self.resolution
            self.cover(float(f[:, 0].min()) - reach, float(f[:, 1].min()) - reach,
                       float(f[:, 0].max()) + reach, float(f[:, 1].max()) + reach,
                       centre=(float(f[:, 0].mean()), float(f[:, 1].mean())))  # fmt: skip
        hit = np.isfinite(r) & (r < max_range)
        reach_m = np.where(hit, r, max_range)
        step = 0.5 * self.resolution
        t = np.arange(math.ceil(max_range / step), dtype=np.float64) * step  # (s,)
        if not self.hits.size:
            return np.zeros((0, 2))
        # numpy's cos and sin, as before the kernel (numba's libm may differ in the last bit)
        turn = np.ascontiguousarray(np.stack([np.cos(f[:, 2]), np.sin(f[:, 2])], axis=1))
        became = _mark_rays(f, turn, reach_m, hit & marks, t, step, self.origin,
                            self.resolution, self.hits, self.misses, self.occupied)  # fmt: skip
        n_cols = self.hits.shape[1]
        rows, cols = became // n_cols, became % n_cols
        return np.stack([(cols + 0.5), (rows + 0.5)], axis=1) * self.resolution + self.origin

    def grid(self) -> OccupancyGrid | None:
        """The map as an :class:`OccupancyGrid` (its origin the map's); None for a map with
        no cells yet, or when read on another thread while the map grows (its arrays and
        origin then disagree for a moment)."""
        origin, misses, occupied = self.origin, self.misses, self.occupied
        if not misses.size or misses.shape != occupied.shape or origin != self.origin:
            return None
        return OccupancyGrid(self.resolution, (*origin, 0.0), _values(misses, occupied))

    def planning_grid(self) -> OccupancyGrid:
        """What a plan with unknown space free needs of the map, in a tenth of the time of
        :meth:`grid`: occupied cells 100, all others 0 (a snapshot: the map may change)."""
        return self.snapshot(True)()

    def snapshot(self, unknown_free: bool) -> Callable[[], OccupancyGrid]:
        """The map as it is now, as a plan needs it (:meth:`planning_grid` with
        ``unknown_free``, else :meth:`grid`), built when called: now only the cells are
        copied, so that a decision handing a plan to another thread pays a copy, no more."""
        res, origin = self.resolution, (*self.origin, 0.0)
        if unknown_free:
            occupied = self.occupied.copy()
            return lambda: OccupancyGrid(res, origin, occupied.view(np.int8) * np.int8(OCCUPIED))
        data = self.data
        return lambda: OccupancyGrid(res, origin, data)

    def blocks(self, xy: ArrayLike, radius: float) -> bool:
        """Whether a robot of ``radius`` m at ``xy`` would touch a cell this map holds
        occupied (:func:`~mentor_core.navigation.grid.disc_touches`)."""
        if not self.occupied.size:
            return False
        p = (np.asarray(xy, dtype=np.float64).reshape(2) - self.origin) / self.resolution
        r = radius / self.resolution
        r0, c0 = max(0, math.floor(p[1] - r)), max(0, math.floor(p[0] - r))
        window = np.s_[r0 : math.floor(p[1] + r) + 2, c0 : math.floor(p[0] + r) + 2]
        return disc_touches(self.occupied[window], p - (c0, r0), r)


def _values(misses: NDArray[np.uint16], occupied: NDArray[np.bool_]) -> NDArray[np.int8]:
    """Cell values of a map's counts: -1 unknown, 0 free (a ray passed), 100 occupied."""
    out = np.full(misses.shape, UNKNOWN, dtype=np.int8)
    out[misses > 0] = FREE
    out[occupied] = OCCUPIED
    return out


#: the step (cells) a growing scan map grows by, and the lattice its corners keep
GROW_CELLS = 64


def _mark_rays(rays: FloatArray, turn: FloatArray, reach: FloatArray, marks: NDArray[np.bool_],
               t: FloatArray, step: float, origin: tuple[float, float], res: float,
               hits: NDArray[np.uint16], misses: NDArray[np.uint16],
               occupied: NDArray[np.bool_]) -> IntArray:  # fmt: skip
    """:meth:`ScanMap.update`'s counting: each ray's cells up to half a cell short of its
    reach gain a miss (once per ray: a ray's cells are monotone in row and column, so it
    never comes back to a cell it left), the end cells of the rays that ``marks`` a hit
    (once per cell), then the cells touched are judged again; the flat indices of those that
    became occupied, sorted. The numpy arithmetic of the map before, cell for cell."""
    n_rows, n_cols = hits.shape
    x0, y0 = origin
    k = rays.shape[0]
    touched = np.empty(k * (t.shape[0] + 1), dtype=np.int64)
    m = 0
    for i in range(k):
        cos, sin = turn[i, 0], turn[i, 1]
        last = -1
        for j in range(t.shape[0]):
            if not t[j] < reach[i] - step:
                break
            row = min(max(math.floor((rays[i, 1] + sin * t[j] - y0) / res), 0), n_rows - 1)
            col = min(max(math.floor((rays[i, 0] + cos * t[j] - x0) / res), 0), n_cols - 1)
            cell = row * n_cols + col
            if cell != last:
                if misses[row, col] < 65535:
                    misses[row, col] += 1
                touched[m] = cell
                m += 1
                last = cell
    ends = np.empty(k, dtype=np.int64)
    e = 0
    for i in range(k):
        if marks[i]:
            cos, sin = turn[i, 0], turn[i, 1]
            row = min(max(math.floor((rays[i, 1] + sin * reach[i] - y0) / res), 0), n_rows - 1)
            col = min(max(math.floor((rays[i, 0] + cos * reach[i] - x0) / res), 0), n_cols - 1)
            ends[e] = row * n_cols + col
            e += 1
    ended = np.unique(ends[:e])
    for cell in ended:
        row, col = cell // n_cols, cell % n_cols
        if hits[row, col] < 65535:
            hits[row, col] += 1
        touched[m] = cell
        m += 1
    became = np.empty(m, dtype=np.int64)
    b = 0
    for q in range(m):
        cell = touched[q]
        row, col = cell // n_cols, cell % n_cols
        now = hits[row, col] > 0 and hits[row, col] >= misses[row, col]
        if now != occupied[row, col]:
            occupied[row, col] = now
            if now:
                became[b] = cell
                b += 1
    return np.sort(became[:b])


try:
    from numba import njit

    _mark_rays = njit(cache=True, nogil=True)(_mark_rays)
except ImportError:  # pragma: no cover - numba is in the lock file
    pass


class ScanGuide:
    """One robot's plan on its own :class:`ScanMap` of side ``size`` m from ``origin`` (None:
    a growing map of at most ``max_cells`` cells) (module docstring).

    Plans are made at once, when asked (the benchmark's, and lockstep's, decisions), or by
    ``worker`` (:mod:`~mentor_core.navigation.plan_worker`; a config's ``plan_delay`` makes
    one that hands each plan back that many decisions late): then each decision follows
    the latest plan it has, and asks for a new one, on a snapshot of the map, when the goal
    changes, when a newly seen obstacle lies near the path (or there is no path and the map
    changed), when the robot strays from the path, or when the plan is older than
    ``replan_every`` s of ``clock`` (0: never for its age).
    """

    def __init__(
        self, size: float | None, config: GuideConfig, origin: tuple[float, float] = (0.0, 0.0),
        worker: PlanWorker | None = None, replan_every: float = 0.0,
        clock: Callable[[], float] = time.monotonic, max_cells: int = MAX_CELLS,
    ) -> None:  # fmt: skip
        self.map = ScanMap(size, config.resolution, origin, max_cells)
        if worker is None and config.plan_delay > 0:
            worker = DelayedPlans(config.plan_delay)
        self.worker = worker
        self.guide = PathGuide(config, plans_itself=worker is None)
        if worker is None and self.map.hits.size:  # a growing map: at its first cells
            self.guide.set_map(self._snapshot())
        self.plans = 0  # maps planned on, the first included
        self.replan_every = float(replan_every)
        self._clock = clock
        self._asked: tuple[XY, float] | None = None  # the goal asked for last, and when
        #: seconds each plan took (with a worker), for measurement
        self.plan_seconds: list[float] = []

    def _snapshot(self) -> OccupancyGrid:
        return self.map.snapshot(self.guide.config.allow_unknown)()

    def refresh(self) -> None:
        """Plan on the map as it is now at the next :meth:`target` (the plan followed is
        made only on the map as it was when a newly seen obstacle last blocked it)."""
        if self.worker is None:
            self.guide.set_map(self._snapshot())
        else:
            self._asked = None
        self.plans += 1

    def target(self, rays: ArrayLike, readings: ArrayLike, max_range: float,
               xy: ArrayLike, goal: ArrayLike,
               located: ArrayLike | None = None) -> tuple[float, float]:  # fmt: skip
        """Add the rays' readings to the map (:meth:`ScanMap.update`), plan again if they
        block the path (or ask the worker to), and return the goal the network should see
        (:meth:`PathGuide.target`)."""
        new = self.map.update(rays, readings, max_range, located)
        if self.map.growing:  # the goal on the map, with room to plan round it
            self._cover(xy, goal)
        if self.worker is not None:
            return self._beside(new, xy, goal)
        if self._blocks_path(new):
            self.guide.set_map(self._snapshot())
            self.plans += 1
        return self.guide.target(xy, goal)

    def _blocks_path(self, new: FloatArray) -> bool:
        """Whether newly occupied cells ``new`` ask for a new plan: one lies near the path,
        or there is no path (and the map changed)."""
        path = self.guide.path
        return bool(new.size) and (path is None or _near(new, path, self.guide.config))

    def _beside(self, new: FloatArray, xy: ArrayLike, goal: ArrayLike) -> tuple[float, float]:
        """:meth:`target` with plans made by the worker (class docstring)."""
        assert self.worker is not None
        here = (float(np.asarray(xy)[0]), float(np.asarray(xy)[1]))
        final = (float(np.asarray(goal)[0]), float(np.asarray(goal)[1]))
        done = self.worker.poll()
        if done is not None and done.owner is self and self._asked is not None:
            self.plan_seconds.append(done.seconds)
            if done.goal == self._asked[0] == final:
                self.guide.adopt(done.planner, done.path)
        now = self._clock()
        ask = (self._asked is None or self._asked[0] != final or self._blocks_path(new)
               or self.guide.strayed)  # fmt: skip
        if not ask and self.replan_every > 0.0 and not self.worker.busy:
            ask = self._asked is not None and now - self._asked[1] >= self.replan_every
        if ask:
            snapshot = self.map.snapshot(self.guide.config.allow_unknown)
            self.worker.submit(PlanJob(self, snapshot, here, final, self.guide.config))
            self._asked = (final, now)
            self.plans += 1
        return self.guide.target(here, final)

    def _cover(self, xy: ArrayLike, goal: ArrayLike) -> None:
        """Grow the map to hold the robot and its goal, with room to plan round them: the
        plan's disc and lookahead and half their distance (the outside of the map is an
        obstacle to the plan: a detour needs the room)."""
        (x, y), (gx, gy) = np.asarray(xy, dtype=float)[:2], np.asarray(goal, dtype=float)[:2]
        config = self.guide.config
        room = config.inflation + config.lookahead + 0.5 * math.hypot(gx - x, gy - y)
        self.map.cover(min(x, gx) - room, min(y, gy) - room, max(x, gx) + room,
                       max(y, gy) + room, centre=(float(x), float(y)))  # fmt: skip

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


def warm_up_scan_map(config: GuideConfig) -> None:
    """Compile (or load from numba's cache) the scan map's and the plan's kernels now, on a
    small map, so that a robot's first decision does not wait seconds for them."""
    guide = ScanGuide(2.0, config)
    guide.target(np.array([[0.5, 1.0, 0.0]]), np.array([1.0]), 1.5, (0.5, 1.0), (1.8, 1.0))


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
