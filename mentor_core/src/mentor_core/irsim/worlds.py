"""The IR-SIM worlds of the benchmark, drawn from seeds at each robot's scale.

Each robot's arena is its test arena (``robots.yaml``: the UGV's 12 m, the Swarm-Robot's
4 m); lengths below are written for the UGV's 12 m and scaled by ``k = side / 12``, agents'
speeds by the robot's top pace (``k_v = rated_speed``: the UGV's 1 m/s, the Swarm-Robot's
0.06 m/s). Walls close the arena (rectangles just outside it, as this project's arenas have).

**Static families** (circles and polygons, none axis-aligned on purpose):

- ``pillar_hall``: round pillars (radius 0.2-0.45 k) on a jittered 2 k grid, a third left out;
- ``slanted_furniture``: 10-14 rectangles (0.6-2.2 k by 0.3-0.9 k) and triangles at random
  angles;
- ``cluttered_office``: two slanted partition walls with two doors each, chairs (circles)
  and desks (rotated rectangles).

**Dynamic families** (a few pillars, then agents: IR-SIM omnidirectional discs of radius
0.2-0.3 k walking at 0.3-0.8 ``k_v``, avoiding each other, the walls and the robot):

- ``wander_rvo``: 3-6 agents wandering (RVO) over the arena;
- ``wander_sfm``: 6-10 agents wandering by the social force model;
- ``crossing``: 10 agents in two flows across the robot's way, back and forth (RVO);
- ``corridor``: a corridor 2.6 k wide, 4 agents walking towards the robot along it;
- ``crowd``: 15 agents (social force) wandering about the start-goal line;
- ``stopper``: one agent walks onto the start-goal line ahead of the robot and stays there
  (there in half the time the robot takes at its shipped top pace; standing there from the
  start where it cannot be), and 2 wander.

**Pairs** as the benchmark draws them (:func:`mentor_core.navigation.pairs.solvable_pairs`:
the trainer's clearance, the unseen test's distances, solvable for the body's disc within
the feasibility bound) on the static map rasterised into boxes (:func:`static_world`, cells
of 0.1 k, each cell touching a shape blocked: never a path through an obstacle). World ``i``
of a family has the seed ``SPLITS[split] + i`` and its generator
``default_rng([seed, family code, robot code])``; lidar noise is on (1 cm for the UGV, 2 mm
for the Swarm-Robot, one 360-ray lidar at the body's centre, range the sensors').
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from matplotlib.path import Path as MplPath
from numpy.typing import NDArray

from mentor_core.benchmark.suite import (
    PAIRS_PER_WORLD,
    PAPER_LIMIT,
    SPLITS,
    reference_profile,
    shipped_limits,
    top_pace,
)
from mentor_core.irsim.world_file import WorldPair, world_document
from mentor_core.navigation.grid import OCCUPIED, OccupancyGrid, world_from_grid
from mentor_core.navigation.pairs import FEASIBLE_SHARE, distance_range, solvable_pairs
from mentor_core.sim.robots import RobotProfile, get_profile
from mentor_core.sim.world import Scenario, World

FloatArray = NDArray[np.float64]
Shape = dict[str, Any]
#: the robots worlds are made for, and their codes in the seeds
ROBOT_CODES = {"ugv": 1, "swarm": 2}
STATIC = {"pillar_hall": 101, "slanted_furniture": 102, "cluttered_office": 103}
DYNAMIC = {"wander_rvo": 201, "wander_sfm": 202, "crossing": 203, "corridor": 204,
           "crowd": 205, "stopper": 206}  # fmt: skip
FAMILIES = {**STATIC, **DYNAMIC}
#: worlds per family and split (five pairs each): 60 static and 90 dynamic test pairs a robot
WORLDS = {("static", "test"): 4, ("static", "validation"): 1,
          ("dynamic", "test"): 3, ("dynamic", "validation"): 1}  # fmt: skip
WALL = 0.3  # m (times k): the walls' thickness, outside the arena


@dataclass(frozen=True)
class RobotSetup:
    """How a robot is put into IR-SIM: its lidar (rays, ranges in m, noise std in m) and
    the world's step (s; it divides every driver's control period)."""

    rays: int
    range_min: float
    noise: float
    step_time: float


SETUPS = {"ugv": RobotSetup(360, 0.05, 0.01, 0.125),
          "swarm": RobotSetup(360, 0.01, 0.002, 0.25)}  # fmt: skip


def scale(profile: RobotProfile) -> float:
    """``k``: the robot's test arena over the UGV's 12 m."""
    return profile.test_arena / 12.0


def circle(x: float, y: float, r: float, name: str = "") -> Shape:
    """A static circle of radius ``r`` at ``(x, y)`` (IR-SIM's obstacle entry)."""
    entry: Shape = {"shape": {"name": "circle", "radius": round(r, 4)},
                    "state": [round(x, 4), round(y, 4), 0.0]}  # fmt: skip
    return {"name": name, **entry} if name else entry


def polygon(points: FloatArray) -> Shape:
    """A static polygon of ``points`` ``(n, 2)`` (IR-SIM's obstacle entry; its vertices in
    the world's frame, as its state is the origin: IR-SIM's default state is not)."""
    return {"shape": {"name": "polygon",
                      "vertices": [[round(float(x), 4), round(float(y), 4)] for x, y in points]},
            "state": [0.0, 0.0, 0.0]}


def box_points(x: float, y: float, length: float, width: float, angle: float) -> FloatArray:
    """Corners ``(4, 2)`` of a rectangle centred at ``(x, y)`` turned by ``angle`` rad."""
    c, s = math.cos(angle), math.sin(angle)
    half = np.array([[1, 1], [-1, 1], [-1, -1], [1, -1]]) * [length / 2, width / 2]
    return np.column_stack([x + half[:, 0] * c - half[:, 1] * s,
                            y + half[:, 0] * s + half[:, 1] * c])  # fmt: skip


def walls(size: float, k: float) -> list[Shape]:
    """The arena's four walls, just outside it."""
    t = WALL * k
    out = []
    for i, (x, y, length, width) in enumerate((
        (size / 2, -t / 2, size + 2 * t, t), (size / 2, size + t / 2, size + 2 * t, t),
        (-t / 2, size / 2, t, size), (size + t / 2, size / 2, t, size),
    )):  # fmt: skip
        out.append({"name": f"wall_{i}", **polygon(box_points(x, y, length, width, 0.0))})
    return out


# --- static layouts -------------------------------------------------------------------------

def pillar_hall(size: float, k: float, rng: np.random.Generator) -> list[Shape]:
    """Round pillars on a jittered grid (module docstring)."""
    out = []
    for x in np.arange(2.0 * k, size - k, 2.0 * k):
        for y in np.arange(2.0 * k, size - k, 2.0 * k):
            if rng.random() < 1.0 / 3.0:
                continue
            jx, jy = rng.uniform(-0.4 * k, 0.4 * k, 2)
            out.append(circle(x + jx, y + jy, rng.uniform(0.2, 0.45) * k))
    return out


def slanted_furniture(size: float, k: float, rng: np.random.Generator) -> list[Shape]:
    """Rectangles and triangles at random angles (module docstring)."""
    out = []
    for _ in range(int(rng.integers(10, 15))):
        x, y = rng.uniform(1.0 * k, size - 1.0 * k, 2)
        angle = rng.uniform(-math.pi, math.pi)
        if rng.random() < 0.7:
            pts = box_points(x, y, rng.uniform(0.6, 2.2) * k, rng.uniform(0.3, 0.9) * k, angle)
        else:
            r = rng.uniform(0.4, 0.8) * k
            a = angle + np.array([0.0, 2.1, 4.2]) + rng.uniform(-0.3, 0.3, 3)
            pts = np.column_stack([x + r * np.cos(a), y + r * np.sin(a)])
        out.append(polygon(pts))
    return out


def cluttered_office(size: float, k: float, rng: np.random.Generator) -> list[Shape]:
    """Two slanted partitions with two doors each, chairs and desks (module docstring)."""
    out = []
    door = 1.4 * k
    for base in (size / 3, 2 * size / 3):
        tilt = rng.uniform(-0.12, 0.12)
        cuts = np.sort(rng.uniform(0.15, 0.85, 2) * size)
        if cuts[1] - cuts[0] < 2 * door:
            cuts[1] = min(cuts[0] + 2 * door, size - door)
        edges = [0.0, cuts[0] - door / 2, cuts[0] + door / 2, cuts[1] - door / 2,
                 cuts[1] + door / 2, size]  # fmt: skip
        for y0, y1 in zip(edges[0::2], edges[1::2], strict=True):
            if y1 - y0 < 0.2 * k:
                continue
            yc = (y0 + y1) / 2
            xc = base + math.tan(tilt) * (yc - size / 2)
            out.append(polygon(box_points(xc, yc, y1 - y0, 0.15 * k, math.pi / 2 + tilt)))
    for _ in range(int(rng.integers(8, 13))):
        x, y = rng.uniform(0.8 * k, size - 0.8 * k, 2)
        if rng.random() < 0.5:
            out.append(circle(x, y, rng.uniform(0.2, 0.3) * k))
        else:
            out.append(polygon(box_points(x, y, 1.2 * k, 0.6 * k, rng.uniform(-math.pi, math.pi))))
    return out


def few_pillars(size: float, k: float, rng: np.random.Generator) -> list[Shape]:
    """The dynamic families' light layout: 4-6 round pillars."""
    out = []
    for _ in range(int(rng.integers(4, 7))):
        x, y = rng.uniform(1.5 * k, size - 1.5 * k, 2)
        out.append(circle(x, y, rng.uniform(0.2, 0.4) * k))
    return out


def corridor_walls(size: float, k: float, rng: np.random.Generator) -> list[Shape]:
    """Two blocks leaving a corridor 2.6 k wide along x through the arena's middle."""
    half = 1.3 * k
    y0, y1 = size / 2 - half, size / 2 + half
    return [polygon(box_points(size / 2, y0 / 2, size, y0, 0.0)),
            polygon(box_points(size / 2, (y1 + size) / 2, size, size - y1, 0.0))]


LAYOUTS: dict[str, Callable[[float, float, np.random.Generator], list[Shape]]] = {
    "pillar_hall": pillar_hall, "slanted_furniture": slanted_furniture,
    "cluttered_office": cluttered_office, "corridor": corridor_walls,
}  # fmt: skip


# --- the static map -------------------------------------------------------------------------

def blocked_cells(shapes: list[Shape], size: float, resolution: float) -> NDArray[np.bool_]:
    """``(n, n)`` cells (row 0 at ``y = 0``) that touch a shape: a cell's centre within
    half its diagonal of a circle or a polygon (conservative)."""
    n = math.ceil(size / resolution - 1e-9)
    c = (np.arange(n) + 0.5) * resolution
    xs, ys = np.meshgrid(c, c)
    pts = np.column_stack([xs.ravel(), ys.ravel()])
    reach = resolution * math.sqrt(0.5)
    hit = np.zeros(len(pts), dtype=bool)
    for entry in shapes:
        shape = entry["shape"]
        if shape["name"] == "circle":
            x, y = entry["state"][:2]
            hit |= np.hypot(pts[:, 0] - x, pts[:, 1] - y) <= shape["radius"] + reach
        else:
            v = np.asarray(shape["vertices"], dtype=np.float64)
            hit |= MplPath(v).contains_points(pts) | (_edge_distance(pts, v) <= reach)
    return hit.reshape(n, n)


def _edge_distance(pts: FloatArray, v: FloatArray) -> FloatArray:
    a, b = v, np.roll(v, -1, axis=0)
    ab = b - a
    t = np.clip(((pts[:, None, :] - a[None]) * ab[None]).sum(-1) / (ab * ab).sum(-1), 0, 1)
    near = a[None] + t[..., None] * ab[None]
    out: FloatArray = np.hypot(*(pts[:, None, :] - near).transpose(2, 0, 1)).min(axis=1)
    return out


def static_world(shapes: list[Shape], size: float, k: float, name: str = "") -> World:
    """The static map of ``shapes`` as this project's world of boxes (module docstring)."""
    res = 0.1 * k
    cells = blocked_cells([s for s in shapes if not s.get("name", "").startswith("wall_")],
                          size, res)  # fmt: skip
    grid = OccupancyGrid(res, (0.0, 0.0, 0.0), np.where(cells, OCCUPIED, 0).astype(np.int8))
    world = world_from_grid(grid, name)
    return World(size, np.clip(world.obstacles, 0.0, size), name)


# --- agents ---------------------------------------------------------------------------------

def agent(i: int, xy: FloatArray, goals: list[FloatArray], speed: float, radius: float,
          behavior: dict[str, Any], k: float) -> Shape:  # fmt: skip
    """An agent: an omnidirectional disc walking to ``goals`` by ``behavior``."""
    v = round(speed, 4)
    beh = {"vxmax": v, "vymax": v, "neighbor_threshold": round(3.0 * k, 3), **behavior}
    if behavior["name"] == "sfm":
        beh = {"vmax": v, "neighbor_threshold": round(3.0 * k, 3), **behavior}
    return {"name": f"agent_{i}", "shape": {"name": "circle", "radius": round(radius, 4)},
            "kinematics": {"name": "omni"},
            "state": [round(float(xy[0]), 4), round(float(xy[1]), 4), 0.0],
            "goal": [[round(float(g[0]), 4), round(float(g[1]), 4), 0.0] for g in goals],
            "goal_threshold": round(0.15 * k, 4), "vel_max": [v, v], "vel_min": [-v, -v],
            "behavior": beh}  # fmt: skip


def agents_for(
    family: str, pair: Scenario, world: World, k: float, pace: float, goal_radius: float,
    top: float, rng: np.random.Generator,
) -> list[Shape]:  # fmt: skip
    """The agents of a dynamic family's pair (module docstring), each placed in free space
    away from the robot's start and goal (``goal_radius`` m: the robot's; ``top`` m/s: the
    robot's top pace as its planners are shipped)."""
    size = world.size
    start, goal = np.array(pair.start[:2]), np.array(pair.goal)
    along = goal - start
    dist = float(np.hypot(*along))
    u = along / dist
    n_vec = np.array([-u[1], u[0]])
    lo, hi = [0.5 * k, 0.5 * k, -math.pi], [size - 0.5 * k, size - 0.5 * k, math.pi]

    def speed() -> float:
        return float(rng.uniform(0.3, 0.8) * pace)

    def radius() -> float:
        return float(rng.uniform(0.2, 0.3) * k)

    def free(xy: FloatArray, r: float) -> bool:
        inside = bool(np.all(xy > r) and np.all(xy < size - r))
        return inside and bool(world.free_at(xy[None], r + 0.1 * k)[0]) and min(
            float(np.hypot(*(xy - start))), float(np.hypot(*(xy - goal)))) > 1.2 * k + r

    def spot(centre: FloatArray | None = None, spread: float = 0.0) -> FloatArray:
        for _ in range(500):
            xy = (rng.uniform(0.5 * k, size - 0.5 * k, 2) if centre is None
                  else centre + rng.uniform(-spread, spread, 2))  # fmt: skip
            if free(xy, 0.3 * k):
                return xy
        raise ValueError("no free place for an agent")

    def wanderers(count: int, first: int, name: str, box: tuple[list[float], list[float]]
                  ) -> list[Shape]:  # fmt: skip
        beh = {"name": name, "wander": True, "range_low": box[0], "range_high": box[1]}
        return [agent(first + i, spot(), [spot()], speed(), radius(), beh, k)
                for i in range(count)]  # fmt: skip

    arena = ([round(v, 3) for v in lo], [round(v, 3) for v in hi])
    if family == "wander_rvo":
        return wanderers(int(rng.integers(3, 7)), 0, "rvo", arena)
    if family == "wander_sfm":
        return wanderers(int(rng.integers(6, 11)), 0, "sfm", arena)
    if family == "crowd":
        mid = (start + goal) / 2
        reach = 0.5 * dist + 1.5 * k
        box = ([round(float(max(0.5 * k, mid[0] - reach)), 3),
                round(float(max(0.5 * k, mid[1] - reach)), 3), -math.pi],
               [round(float(min(size - 0.5 * k, mid[0] + reach)), 3),
                round(float(min(size - 0.5 * k, mid[1] + reach)), 3), math.pi])  # fmt: skip
        out = []
        for i in range(15):
            beh = {"name": "sfm", "wander": True, "range_low": box[0], "range_high": box[1]}
            out.append(agent(i, spot(mid, reach), [spot(mid, reach)], speed(), radius(),
                             beh, k))  # fmt: skip
        return out
    if family == "crossing":
        out = []
        for i in range(10):
            t = rng.uniform(0.25, 0.75) * dist
            side = 1.0 if i % 2 == 0 else -1.0
            width = rng.uniform(2.5, 4.0) * k
            a = _clip(start + t * u + side * width * n_vec, size, k)
            b = _clip(start + t * u - side * width * n_vec, size, k)
            out.append(agent(i, a, [b, a], speed(), radius(), {"name": "rvo", "loop": True}, k))
        return out
    if family == "corridor":
        out = []
        for i in range(4):
            t = rng.uniform(0.6, 1.2) * dist
            lateral = rng.uniform(-0.6, 0.6) * k
            a = _clip(start + t * u + lateral * n_vec, size, k)
            b = _clip(start - 1.5 * k * u + lateral * n_vec, size, k)
            out.append(agent(i, a, [b, a], speed(), radius(), {"name": "rvo", "loop": True}, k))
        return out
    if family == "stopper":
        # on the line 55 % of the way (at least 2.5 k from the start, 1.4 k short of the
        # goal), it stands before the robot can be there: it starts 1.2-1.8 k aside, or
        # nearer, so that at 0.8 k_v it arrives within half the time the robot takes at its
        # top pace (``top``), or right there, standing, when that is under 0.3 k
        reach = 1.4 * k + goal_radius
        t = min(max(0.55 * dist, 2.5 * k), dist - reach)
        stop = start + t * u
        side = 1.0 if rng.random() < 0.5 else -1.0
        aside = min(rng.uniform(1.2, 1.8) * k, 0.8 * pace * 0.5 * t / top)
        aside = aside if aside >= 0.3 * k else 0.0
        begin = _clip(stop + side * aside * n_vec, size, k)
        first = agent(0, begin, [stop], 0.8 * pace, 0.25 * k, {"name": "dash"}, k)
        first["goal_threshold"] = round(0.05 * k, 4)
        return [first, *wanderers(2, 1, "rvo", arena)]
    raise ValueError(f"unknown dynamic family {family!r}")


def _clip(xy: FloatArray, size: float, k: float) -> FloatArray:
    out: FloatArray = np.clip(xy, 0.6 * k, size - 0.6 * k)
    return out


# --- a world --------------------------------------------------------------------------------

def robot_block(profile: RobotProfile, setup: RobotSetup) -> Shape:
    """The robot's IR-SIM entry: a ``length`` x ``width`` rectangle on a differential drive
    with one 360-ray lidar at its centre (placed at each pair's start by the episode)."""
    inc = 2.0 * math.pi / setup.rays
    return {
        "name": "robot", "kinematics": {"name": "diff"},
        "shape": {"name": "rectangle", "length": profile.length, "width": profile.width},
        "state": [0.0, 0.0, 0.0], "goal": [0.0, 0.0, 0.0],
        "goal_threshold": round(profile.goal_radius, 4),
        "vel_min": [-4.0 * profile.rated_speed, -2 * math.pi],
        "vel_max": [4.0 * profile.rated_speed, 2 * math.pi],
        "sensors": [{"name": "lidar2d", "range_min": setup.range_min,
                     "range_max": profile.sensor_range,
                     "angle_range": round(2.0 * math.pi - inc, 10), "number": setup.rays,
                     "noise": True, "std": setup.noise, "angle_std": 0.0}],
    }  # fmt: skip


def make_world(robot: str, family: str, split: str, index: int) -> dict[str, Any]:
    """The document of world ``index`` of ``family`` for ``robot`` on ``split`` (module
    docstring). ValueError for an unknown robot, family or split, or a layout without its
    pairs."""
    if robot not in ROBOT_CODES or family not in FAMILIES or split not in SPLITS:
        raise ValueError(f"unknown robot, family or split: {robot!r}, {family!r}, {split!r}")
    profile = get_profile(robot)
    setup = SETUPS[robot]
    k, size = scale(profile), profile.test_arena
    seed = SPLITS[split] + index
    rng = np.random.default_rng([seed, FAMILIES[family], ROBOT_CODES[robot]])
    ref = reference_profile(profile)
    longest = FEASIBLE_SHARE * PAPER_LIMIT * top_pace(ref)
    layout = LAYOUTS.get(family, few_pillars)
    for _ in range(10):
        shapes = layout(size, k, rng)
        world = static_world(shapes, size, k, f"{robot}-{family}-{seed}")
        drawn = solvable_pairs(world, profile, PAIRS_PER_WORLD, distance_range(profile, size),
                               longest, rng)  # fmt: skip
        if len(drawn) == PAIRS_PER_WORLD:
            break
    else:
        raise ValueError(f"{robot} {family} {seed}: too few solvable pairs")
    pace = profile.rated_speed
    pairs = [WorldPair(s.start, s.goal, length,
                       tuple(agents_for(family, s, world, k, pace, profile.goal_radius,
                                        top_pace(shipped_limits(profile)), rng)
                             if family in DYNAMIC else ()))
             for s, length in drawn]  # fmt: skip
    config: dict[str, Any] = {
        "world": {"height": size, "width": size,
                  "step_time": setup.step_time, "collision_mode": "unobstructed_obstacles"},
        "robot": [robot_block(profile, setup)],
        "obstacle": [*walls(size, k), *shapes],
    }  # fmt: skip
    first = pairs[0]
    config["robot"][0]["state"] = [round(v, 4) for v in first.start]
    config["robot"][0]["goal"] = [round(first.goal[0], 4), round(first.goal[1], 4), 0.0]
    meta = {"robot": robot, "family": family, "kind": "dynamic" if family in DYNAMIC
            else "static", "split": split, "seed": seed}  # fmt: skip
    document: dict[str, Any] = plain(world_document(config, meta, pairs))
    return document


def plain(value: Any) -> Any:
    """``value`` with numpy numbers as Python's (floats rounded to 0.1 mm), for YAML."""
    if isinstance(value, dict):
        return {key: plain(v) for key, v in value.items()}
    if isinstance(value, list | tuple):
        return [plain(v) for v in value]
    if isinstance(value, np.integer):
        return int(value)
    if isinstance(value, float | np.floating):
        return round(float(value), 4)
    return value


def world_names(robot: str, split: str) -> list[tuple[str, int]]:
    """``(family, index)`` of every world of ``robot`` on ``split`` (:data:`WORLDS`)."""
    return [(family, i) for family in FAMILIES
            for i in range(WORLDS[("dynamic" if family in DYNAMIC else "static", split)])]


__all__ = [
    "DYNAMIC",
    "FAMILIES",
    "SETUPS",
    "STATIC",
    "WORLDS",
    "RobotSetup",
    "make_world",
    "robot_block",
    "static_world",
    "world_names",
]
