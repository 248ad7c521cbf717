"""The paper's design of experiments (DoE): composite worlds and start/goal scenarios.

Paper, section III-A: the square arena is divided into 4 grids (2 x 2 quadrants); in each
grid, Latin hypercube sampling gives the centroid (x, y) and size (w, h) of its rectangular
obstacles, and constrained sampling keeps them from overlapping. Crowded and sparse grids make
the composite environment: :class:`DoEConfig` fixes how many grids are crowded and the
obstacle-count range of each kind; which grids are crowded, and each grid's count, come from
the generator.

Everything random comes from the ``np.random.Generator`` passed in, so the same seed gives the
same worlds and scenarios on any machine.
"""

from __future__ import annotations

import math
from typing import Annotated, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from pydantic import Field, model_validator

from mentor_core.errors import ConfigError
from mentor_core.sim.collision import robot_collides
from mentor_core.sim.robots import RobotProfile
from mentor_core.sim.world import Scenario, World
from mentor_core.validation import Float, Int, config_dataclass, fault, to_plain, validate

# default start/goal clearance = this factor x the body's half diagonal: the robot fits in
# any heading, with a quarter of its half diagonal to spare
CLEARANCE_FACTOR = 1.25
# candidate start/goal pairs drawn per round; fixed so that the first scenarios of a seed do
# not depend on how many are asked for
_BATCH = 256
_MAX_ROUNDS = 400
#: the most pairs :func:`sample_scenarios` draws in one world (its search's rounds x batch)
MAX_PAIRS = _BATCH * _MAX_ROUNDS
# draws of walls of one world, accepted or not
_WALL_TRIES = 200

_Count = Annotated[Int, Field(ge=0)]
_Fraction = Annotated[Float, Field(gt=0.0)]


@config_dataclass
class DoEConfig:
    """Obstacle layout of a composite world; lengths as fractions of the arena side.

    Attributes:
        grids_per_side: the arena is split into ``grids_per_side**2`` equal grids (paper: 2).
        crowded_grids: how many grids are crowded; the others are sparse.
        crowded_count, sparse_count: inclusive (min, max) obstacle count of such a grid.
        size_fraction: (min, max) obstacle side (w and h, each) / arena side.
        gap_fraction: least gap between two obstacles, and twice the least gap between an
            obstacle and its grid's border, / arena side.
        max_rounds: Latin hypercube rounds per grid before it keeps the obstacles it has.
        wall_count: inclusive (min, max) number of long walls across the grids (the paper:
            none, ``(0, 0)``); see :func:`sample_world`.
        wall_length_fraction: (min, max) wall length / arena side.
        wall_thickness_fraction: wall thickness / arena side.
        wall_anchor_share: probability that a wall starts at the arena's border (a wall
            that closes part of the arena off, as a corridor's) rather than standing free.
        wall_passage_fraction: least gap between two walls, and between a free wall's ends
            and the border, / arena side: a passage wide enough to drive through.
    """

    grids_per_side: Annotated[Int, Field(ge=1)] = 2
    crowded_grids: _Count = 2
    crowded_count: tuple[_Count, _Count] = (8, 12)
    sparse_count: tuple[_Count, _Count] = (1, 3)
    size_fraction: tuple[_Fraction, _Fraction] = (0.03, 0.10)
    gap_fraction: Annotated[Float, Field(ge=0.0)] = 0.02
    max_rounds: Annotated[Int, Field(ge=1)] = 50
    wall_count: tuple[_Count, _Count] = (0, 0)
    wall_length_fraction: tuple[_Fraction, _Fraction] = (0.35, 0.65)
    wall_thickness_fraction: _Fraction = 0.025
    wall_anchor_share: Annotated[Float, Field(ge=0.0, le=1.0)] = 0.5
    wall_passage_fraction: Annotated[Float, Field(gt=0.0, lt=0.5)] = 0.125

    @classmethod
    def from_dict(cls, data: dict[str, Any], source: str = "<dict>") -> DoEConfig:
        """Build from a plain mapping (YAML lists for the pairs); ConfigError naming the key
        (``doe.<key>``) and ``source`` for an unknown key or a bad value."""
        return validate(cls, data, source, prefix="doe")

    def to_dict(self) -> dict[str, Any]:
        """A plain mapping (lists for the pairs) that :meth:`from_dict` turns back."""
        plain: dict[str, Any] = to_plain(self)
        return plain

    @model_validator(mode="after")
    def _consistent(self) -> DoEConfig:
        if self.crowded_grids > self.grids_per_side**2:
            raise fault("crowded_grids", "must be between 0 and the number of grids")
        for key in ("crowded_count", "sparse_count", "size_fraction", "wall_count",
                    "wall_length_fraction"):  # fmt: skip
            lo, hi = getattr(self, key)
            if lo > hi:
                raise fault(key, f"must be a pair [min, max] with min <= max, got [{lo}, {hi}]")
        if self.size_fraction[1] + self.gap_fraction >= 1.0 / self.grids_per_side:
            raise fault("size_fraction", "largest obstacle plus gap must fit in a grid")
        room = 1.0 - 2.0 * self.wall_passage_fraction
        if self.wall_length_fraction[1] > room:
            raise fault("wall_length_fraction", "max must be <= 1 - 2 wall_passage_fraction")
        if self.wall_thickness_fraction > room:
            raise fault("wall_thickness_fraction", "must be <= 1 - 2 wall_passage_fraction")
        return self


def latin_hypercube(n: int, d: int, rng: np.random.Generator) -> NDArray[np.float64]:
    """(n, d) Latin hypercube sample of the unit cube.

    Each column is ``u_ij = (pi_j(i) + r_ij) / n`` with ``pi_j`` a random permutation of
    0..n-1 and ``r_ij ~ U[0, 1)``: every one of the n equal slices of each axis holds exactly
    one point.
    """
    perms = np.argsort(rng.random((d, n)), axis=1).T
    return (perms + rng.random((n, d))) / n


def sample_world(size: float, rng: np.random.Generator, cfg: DoEConfig | None = None) -> World:
    """A composite world of side ``size`` (m): LHS obstacles per grid, none overlapping.

    Grid ``(i, j)`` (row-major) covers ``[i, i + 1] x [j, j + 1] * size / grids_per_side``.
    An obstacle's unit sample ``(u0, u1, u2, u3)`` becomes ``w = lerp(wmin, wmax, u2)``,
    ``h = lerp(wmin, wmax, u3)``, and a centroid with ``u0, u1`` spread over the part of the
    grid where the box keeps ``gap / 2`` from the grid border; so boxes of different grids are
    ``gap`` apart and inside the arena. Inside a grid, a candidate closer than ``gap`` to an
    accepted box (in both x and y) is rejected and a fresh LHS round is drawn for the missing
    ones; a grid that is still short after ``max_rounds`` rounds keeps fewer obstacles.

    Walls (``cfg.wall_count``, none in the paper's DoE) come after the grids: each an
    axis-aligned bar of a uniform length and the configured thickness, horizontal or vertical
    with even odds; with probability ``wall_anchor_share`` one end sits on the arena's border
    (either end, even odds), else it stands free with a passage to the border at both ends;
    its position across is uniform with a passage to the border. A wall closer than a passage
    to an earlier wall is drawn again (at most ``_WALL_TRIES`` draws in all), and the grids'
    boxes closer than ``gap`` to a wall are removed. Without walls no draw is made, so the
    paper's worlds do not change. ConfigError (key ``wall_count``) when fewer walls than its
    minimum fit.
    """
    cfg = DoEConfig() if cfg is None else cfg
    if not math.isfinite(size) or size <= 0.0:
        raise ValueError(f"arena size must be positive, got {size}")
    n_grids = cfg.grids_per_side**2
    crowded = np.zeros(n_grids, dtype=bool)
    crowded[rng.permutation(n_grids)[: cfg.crowded_grids]] = True
    cell = size / cfg.grids_per_side
    boxes: list[NDArray[np.float64]] = []
    for g in range(n_grids):
        lo, hi = cfg.crowded_count if crowded[g] else cfg.sparse_count
        count = int(rng.integers(lo, hi + 1))
        origin = (float(g % cfg.grids_per_side) * cell, float(g // cfg.grids_per_side) * cell)
        boxes.extend(_fill_grid(origin, cell, count, size, cfg, rng))
    if cfg.wall_count[1] > 0:
        walls = _draw_walls(size, cfg, rng)
        gap = cfg.gap_fraction * size
        boxes = walls + [b for b in boxes if not any(_too_close(b, w, gap) for w in walls)]
    return World(size=size, obstacles=np.array(boxes, dtype=np.float64).reshape(-1, 4))


def _draw_walls(
    size: float, cfg: DoEConfig, rng: np.random.Generator
) -> list[NDArray[np.float64]]:
    """The long walls of :func:`sample_world`, as boxes."""
    count = int(rng.integers(cfg.wall_count[0], cfg.wall_count[1] + 1))
    passage = cfg.wall_passage_fraction * size
    thick = cfg.wall_thickness_fraction * size
    walls: list[NDArray[np.float64]] = []
    for _ in range(_WALL_TRIES):
        if len(walls) == count:
            break
        length = rng.uniform(*cfg.wall_length_fraction) * size
        horizontal = rng.random() < 0.5
        if rng.random() < cfg.wall_anchor_share:
            along = 0.0 if rng.random() < 0.5 else size - length
        else:
            along = rng.uniform(passage, size - passage - length)
        across = rng.uniform(passage, size - passage - thick)
        wall = np.array(
            (along, across, along + length, across + thick) if horizontal
            else (across, along, across + thick, along + length)
        )  # fmt: skip
        if not any(_too_close(wall, other, passage) for other in walls):
            walls.append(wall)
    if len(walls) < cfg.wall_count[0]:
        raise ConfigError(
            f"only {len(walls)} walls fit in a {size:g} m arena with a passage of "
            f"{passage:g} m between them, {cfg.wall_count[0]} or more asked for",
            key="wall_count",
        )
    return walls


def _fill_grid(
    origin: tuple[float, float],
    cell: float,
    count: int,
    size: float,
    cfg: DoEConfig,
    rng: np.random.Generator,
) -> list[NDArray[np.float64]]:
    """Up to ``count`` boxes in one grid, pairwise at least ``gap`` apart (x or y)."""
    gap = cfg.gap_fraction * size
    smin, smax = (f * size for f in cfg.size_fraction)
    accepted: list[NDArray[np.float64]] = []
    for _ in range(cfg.max_rounds):
        missing = count - len(accepted)
        if missing == 0:
            break
        u = latin_hypercube(missing, 4, rng)
        w = smin + (smax - smin) * u[:, 2]
        h = smin + (smax - smin) * u[:, 3]
        cx = origin[0] + 0.5 * gap + 0.5 * w + u[:, 0] * (cell - gap - w)
        cy = origin[1] + 0.5 * gap + 0.5 * h + u[:, 1] * (cell - gap - h)
        for box in np.stack([cx - w / 2, cy - h / 2, cx + w / 2, cy + h / 2], axis=1):
            if not any(_too_close(box, other, gap) for other in accepted):
                accepted.append(box)
    return accepted


def _too_close(a: NDArray[np.float64], b: NDArray[np.float64], gap: float) -> bool:
    """True when boxes a and b, each grown by gap / 2, overlap with positive area."""
    ox = min(a[2], b[2]) - max(a[0], b[0])
    oy = min(a[3], b[3]) - max(a[1], b[1])
    return bool(ox > -gap and oy > -gap)


def sample_scenarios(
    world: World,
    profile: RobotProfile,
    n: int,
    rng: np.random.Generator,
    min_distance: float | None = None,
    max_distance: float | None = None,
    clearance: float | None = None,
) -> list[Scenario]:
    """``n`` start/goal pairs in free space of ``world``.

    Starts and goals are uniform over the points at least ``clearance`` (m) from every
    obstacle and wall, with the straight start-goal distance in ``[min_distance,
    max_distance]`` (m); the start heading is uniform in (-pi, pi].

    Defaults: ``clearance = 1.25 * half body diagonal`` (the body fits at any heading);
    ``min_distance = 2 * goal_radius`` (no scenario starts at its goal); ``max_distance =
    profile.uncapped_distance`` (the time-budget cap never cuts a straight run), at most the
    arena diagonal. Raises ValueError for a clearance below the half diagonal, an empty
    distance range, or when ``n`` pairs cannot be found.
    """
    if n < 0:
        raise ValueError(f"number of scenarios must be >= 0, got {n}")
    if n > MAX_PAIRS:  # refused before drawing: the search would end short of n anyway
        raise ValueError(f"at most {MAX_PAIRS} start/goal pairs are drawn in one world, not {n}")
    half_diag = profile.half_diagonal
    clear = CLEARANCE_FACTOR * half_diag if clearance is None else float(clearance)
    if clear < half_diag:
        raise ValueError(f"clearance {clear} m is below the robot's half diagonal {half_diag} m")
    d_min = 2.0 * profile.goal_radius if min_distance is None else float(min_distance)
    d_max = (
        min(profile.uncapped_distance, world.size * math.sqrt(2.0))
        if max_distance is None
        else float(max_distance)
    )
    if not 0.0 <= d_min <= d_max:
        raise ValueError(f"empty distance range [{d_min}, {d_max}] m")
    lo, hi = clear, world.size - clear
    if lo >= hi:
        raise ValueError(f"clearance {clear} m leaves no room in a {world.size} m arena")
    found: list[Scenario] = []
    for _ in range(_MAX_ROUNDS):
        if len(found) == n:
            return found
        starts = rng.uniform(lo, hi, (_BATCH, 2))
        goals = rng.uniform(lo, hi, (_BATCH, 2))
        # rng.random() is in [0, 1), so the heading is in (-pi, pi]
        headings = np.pi - 2.0 * np.pi * rng.random(_BATCH)
        dist = np.hypot(*(goals - starts).T)
        ok = (
            world.free_at(starts, clear)
            & world.free_at(goals, clear)
            & (dist >= d_min)
            & (dist <= d_max)
        )
        for i in np.flatnonzero(ok)[: n - len(found)]:
            start = (float(starts[i, 0]), float(starts[i, 1]), float(headings[i]))
            found.append(Scenario(world, start, (float(goals[i, 0]), float(goals[i, 1]))))
    if len(found) == n:
        return found
    raise ValueError(f"found only {len(found)} of {n} start/goal pairs in free space")


def start_overlap(world: World, start: ArrayLike, profile: RobotProfile) -> str:
    """Why a robot of ``profile`` cannot start at ``start`` (x, y, theta) in ``world`` (its
    body there overlaps an obstacle or crosses a wall), or '' when it can.

    Such a scenario is a bad one, not a collision of the planner: mentor-eval and the
    simulator node both skip it with this reason (``ScenarioPlan``), so that both run and
    score the same scenarios.
    """
    pose = np.asarray(start, dtype=np.float64).reshape(3)
    if not robot_collides(pose[None, :], profile, world)[0]:
        return ""
    x, y, th = (float(v) for v in pose)
    return f"its body at the start ({x:.3f}, {y:.3f}, {th:.3f}) overlaps an obstacle or a wall"


def training_scenarios(
    profile: RobotProfile,
    seed: int,
    n: int | None = None,
    cfg: DoEConfig | None = None,
    worlds: int = 1,
    distances: tuple[float, float] | None = None,
) -> list[Scenario]:
    """The training DoE: ``worlds`` composite worlds of side ``profile.train_arena`` and ``n``
    start/goal pairs spread over them (the paper: one world).

    ``n`` defaults to ``profile.train_scenarios``; world ``j`` gets ``n // worlds`` pairs, one
    more for ``j < n % worlds``, listed world by world. The seed's generator spawns two
    children, one for the first world and one for its pairs, then two more per further world,
    so the first world does not depend on ``worlds`` nor on ``n``, and with one world the first
    k scenarios are the same for every ``n >= k``. ``distances`` is the straight start-goal
    range ``(min, max)``, m (None: :func:`sample_scenarios`' defaults).
    """
    count = profile.train_scenarios if n is None else n
    if worlds < 1:
        raise ValueError(f"number of training worlds must be >= 1, got {worlds}")
    if count < worlds:
        raise ValueError(f"{count} scenarios cannot cover {worlds} training worlds")
    parent = np.random.default_rng(seed)
    rngs = parent.spawn(2) + parent.spawn(2 * (worlds - 1))
    lo, hi = (None, None) if distances is None else distances
    found: list[Scenario] = []
    for j in range(worlds):
        world = sample_world(profile.train_arena, rngs[2 * j], cfg)
        suffix = "" if j == 0 else f"-world{j}"
        named = World(world.size, world.obstacles, name=f"{profile.name}-train-seed{seed}{suffix}")
        pairs = count // worlds + (j < count % worlds)
        found += sample_scenarios(named, profile, pairs, rngs[2 * j + 1], lo, hi)
    return found
