"""A world file of this project: an IR-SIM world (its own YAML) with a ``custom.mentor`` block.

IR-SIM reads the file as it is (``irsim.make(path)``): ``world`` (the arena, ``width`` =
``height`` = its side, ``step_time``, ``collision_mode``), ``robot`` (one differential drive
with a ``lidar2d``, at the first pair's start) and ``obstacle`` (the static obstacles: the
arena's four walls, circles, polygons, rectangles). IR-SIM hands ``custom`` back untouched;
this project's block there says what the world is for::

    custom:
      mentor:
        format: mentor-irsim-world
        version: 1
        robot: ugv                 # a robot of mentor_core/data/robots.yaml
        family: pillar_hall        # the world's family (worlds.FAMILIES)
        kind: static               # static or dynamic
        split: test                # validation or test
        seed: 1000000              # the seed the world was drawn from
        pairs:                     # start/goal pairs, solvable on the static map
          - start: [x, y, theta]   # m, m, rad
            goal: [x, y]           # m
            shortest: 7.31         # m, the shortest path into the goal radius (SPL's l)
            agents: []             # IR-SIM obstacle entries that walk during this pair

An episode of pair ``k`` runs the file with the robot at the pair's start, its goal the
pair's goal, and the pair's agents added to the obstacles (:func:`pair_config`).
:func:`load_world` checks all of it; a fault is one line naming the file.
"""

from __future__ import annotations

import copy
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from mentor_core.errors import ConfigError, FileFormatError, is_number, short_repr
from mentor_core.sim.robots import load_profiles
from mentor_core.yaml_reading import read_yaml

FORMAT = "mentor-irsim-world"
VERSION = 1
KINDS = ("static", "dynamic")
SPLITS = ("validation", "test")


@dataclass(frozen=True)
class WorldPair:
    """One start/goal pair (module docstring): start ``(x, y, theta)``, goal ``(x, y)``,
    the shortest path's length ``shortest`` (m) and the agents walking during it."""

    start: tuple[float, float, float]
    goal: tuple[float, float]
    shortest: float
    agents: tuple[Mapping[str, Any], ...] = ()


@dataclass(frozen=True)
class IrsimWorld:
    """A world file read and checked (module docstring); ``config`` holds IR-SIM's blocks."""

    path: str
    robot: str
    family: str
    kind: str
    split: str
    seed: int
    size: float
    step_time: float
    pairs: tuple[WorldPair, ...]
    config: Mapping[str, Any]

    @property
    def name(self) -> str:
        """The file's stem."""
        return Path(self.path).stem


def load_world(path: str | Path, robot: str | None = None) -> IrsimWorld:
    """The world file ``path`` (module docstring), checked; FileFormatError naming the file
    for a missing, malformed or inconsistent one, ConfigError when it is for another robot
    than ``robot`` (None: any)."""
    data = read_yaml(path)
    world = parse_world(data, path)
    if robot is not None and world.robot != robot:
        raise ConfigError(f"the world is for robot {world.robot!r}, not {robot!r}",
                          key="custom.mentor.robot", path=path)  # fmt: skip
    return world


def parse_world(data: Any, path: str | Path) -> IrsimWorld:
    """A world file's document ``data`` checked (:func:`load_world`)."""

    def fault(text: str) -> FileFormatError:
        return FileFormatError(path, text)

    if not isinstance(data, dict):
        raise fault(f"expected a mapping, got {short_repr(data)}")
    unknown = sorted(set(data) - {"world", "robot", "obstacle", "custom", "gui"})
    if unknown:
        raise fault(f"unknown top-level key {unknown[0]!r} (IR-SIM's: world, robot, obstacle, "
                    "custom, gui)")  # fmt: skip
    meta = (data.get("custom") or {}).get("mentor") if isinstance(data.get("custom"), dict) \
        else None
    if not isinstance(meta, dict):
        raise fault("no custom.mentor block (not a world of this project)")
    if meta.get("format") != FORMAT or meta.get("version") != VERSION:
        raise fault(f"custom.mentor: expected format {FORMAT!r} version {VERSION}")
    robot = meta.get("robot")
    if robot not in load_profiles():
        raise fault(f"custom.mentor.robot: {short_repr(robot)} is no known robot "
                    f"(known: {', '.join(sorted(load_profiles()))})")  # fmt: skip
    for key, allowed in (("kind", KINDS), ("split", SPLITS)):
        if meta.get(key) not in allowed:
            raise fault(f"custom.mentor.{key}: expected one of {', '.join(allowed)}, got "
                        f"{short_repr(meta.get(key))}")  # fmt: skip
    world = data.get("world")
    if not isinstance(world, dict):
        raise fault("no world block")
    size, height = world.get("width"), world.get("height")
    step = world.get("step_time", 0.1)
    if not (is_number(size) and size > 0 and size == height and math.isfinite(size)):
        raise fault(f"world: width and height must be one positive side, got {size!r}, "
                    f"{height!r}")  # fmt: skip
    if not (is_number(step) and 0 < step <= 1):
        raise fault(f"world.step_time: expected (0, 1] s, got {short_repr(step)}")
    robots = data.get("robot")
    if not (isinstance(robots, list) and len(robots) == 1 and isinstance(robots[0], dict)):
        raise fault("robot: expected a list of one robot")
    sensors = robots[0].get("sensors") or []
    if not any(isinstance(s, dict) and s.get("name") == "lidar2d" for s in sensors):
        raise fault("robot: it carries no lidar2d sensor")
    if not isinstance(data.get("obstacle", []), list):
        raise fault("obstacle: expected a list")
    pairs = meta.get("pairs")
    if not isinstance(pairs, list) or not pairs:
        raise fault("custom.mentor.pairs: expected a non-empty list")
    seed = meta.get("seed", 0)
    if not (isinstance(seed, int) and not isinstance(seed, bool)):
        raise fault(f"custom.mentor.seed: expected an integer, got {short_repr(seed)}")
    parsed = tuple(_pair(p, k, float(size), fault) for k, p in enumerate(pairs))
    config = {k: v for k, v in data.items() if k != "custom"}
    return IrsimWorld(str(path), str(robot), str(meta.get("family", "")), str(meta["kind"]),
                      str(meta["split"]), seed, float(size), float(step), parsed,
                      config)  # fmt: skip


def _pair(entry: Any, k: int, size: float, fault: Any) -> WorldPair:
    where = f"custom.mentor.pairs[{k}]"
    if not isinstance(entry, dict):
        raise fault(f"{where}: expected a mapping, got {short_repr(entry)}")
    start, goal = _numbers(entry.get("start"), 3), _numbers(entry.get("goal"), 2)
    if start is None or goal is None:
        raise fault(f"{where}: start must be [x, y, theta] and goal [x, y] in m, rad")
    for name, xy in (("start", start[:2]), ("goal", goal)):
        if not all(0.0 <= v <= size for v in xy):
            raise fault(f"{where}.{name}: {list(xy)} lies outside the {size:g} m arena")
    shortest = entry.get("shortest")
    if not (is_number(shortest) and math.isfinite(shortest) and shortest >= 0):
        raise fault(f"{where}.shortest: expected a length >= 0 m, got {short_repr(shortest)}")
    agents = entry.get("agents", [])
    if not isinstance(agents, list) or not all(isinstance(a, dict) for a in agents):
        raise fault(f"{where}.agents: expected a list of IR-SIM obstacle entries")
    return WorldPair((start[0], start[1], start[2]), (goal[0], goal[1]), float(shortest),
                     tuple(agents))  # fmt: skip


def _numbers(value: Any, n: int) -> tuple[float, ...] | None:
    if not (isinstance(value, list) and len(value) == n and all(is_number(v) for v in value)):
        return None
    out = tuple(float(v) for v in value)
    return out if all(math.isfinite(v) for v in out) else None


def pair_config(world: IrsimWorld, k: int) -> dict[str, Any]:
    """IR-SIM's blocks for an episode of pair ``k`` (module docstring): the robot at its
    start with its goal, the pair's agents after the static obstacles. IndexError for a
    pair the world lacks."""
    pair = world.pairs[k]
    config = copy.deepcopy(dict(world.config))
    robot = config["robot"][0]
    robot["state"] = list(pair.start)
    robot["goal"] = [*pair.goal, 0.0]
    config["obstacle"] = [*config.get("obstacle", []), *copy.deepcopy(list(pair.agents))]
    return config


def world_document(config: Mapping[str, Any], meta: Mapping[str, Any],
                   pairs: Sequence[WorldPair]) -> dict[str, Any]:  # fmt: skip
    """The document of a world file: IR-SIM's blocks ``config``, the ``custom.mentor`` block
    of ``meta`` (robot, family, kind, split, seed) and ``pairs``."""
    block = {"format": FORMAT, "version": VERSION, **meta, "pairs": [
        {"start": [round(v, 4) for v in p.start], "goal": [round(v, 4) for v in p.goal],
         "shortest": round(p.shortest, 4), "agents": [dict(a) for a in p.agents]}
        for p in pairs]}  # fmt: skip
    return {**config, "custom": {"mentor": block}}


__all__ = [
    "FORMAT",
    "KINDS",
    "SPLITS",
    "VERSION",
    "IrsimWorld",
    "WorldPair",
    "load_world",
    "pair_config",
    "parse_world",
    "world_document",
]
