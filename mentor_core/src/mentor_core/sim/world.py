"""Worlds (square arena with axis-aligned box obstacles), scenarios, and their YAML file.

Frame ``map`` (REP-105): origin at the arena's lower-left corner, x right, y up, the arena is
``[0, size] x [0, size]`` m. An obstacle is a box ``[xmin, ymin, xmax, ymax]`` (m) inside the
arena; obstacles may touch and overlap (real layouts overlap at every corner: the ray casts,
the collision tests and pymunk take each box on its own, so the obstacle is their union).

World file (YAML, format ``mentor-world``, version 1, lengths in m, angles in rad)::

    format: mentor-world
    version: 1
    units: m                     # optional; only "m" is accepted
    name: demo                   # optional
    size: 12.0                   # (0, 1e5] m
    obstacles:                   # may be empty
      - [1.0, 1.0, 2.0, 1.5]     # xmin, ymin, xmax, ymax
    scenarios:                   # optional start/goal pairs
      - {start: [0.5, 0.5, 0.0], goal: [10.0, 10.0]}   # start (x, y, theta), goal (x, y)

Instead of ``size``, a file may name a ROS map, ``map: maps/office.yaml`` (relative to the
world file's folder): the arena and obstacles come from the map, read by the ``map_reader``
that :func:`load_world` is given (``mentor_core.navigation.map_world.load_world_file`` gives
the navigation wing's); ``obstacles`` are added to the map's.

Read with YAML 1.2 numbers (``1e3`` is a number) and strict types (``size: "12"`` is refused);
every fault is one FileFormatError line naming the file and the key.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Annotated, Any, Literal

import numpy as np
import yaml
from numpy.typing import ArrayLike, NDArray
from pydantic import Field

from mentor_core.atomic import write_text_atomic
from mentor_core.errors import ConfigError, FileFormatError, is_version
from mentor_core.sim.kinematics import wrap_angle
from mentor_core.validation import Float, Str, config_dataclass, read_yaml, validate

WORLD_FORMAT = "mentor-world"
WORLD_VERSION = 1
#: the largest arena side, m: beyond it float64 positions lose the sub-micrometre precision
#: that collision checks and ray casts rely on (the robots' arenas are 4-12 m)
MAX_ARENA_SIZE = 1e5


@dataclass(frozen=True, eq=False)
class World:
    """A square arena of side ``size`` (m) with read-only (k, 4) float64 ``obstacles``.

    The constructor copies and checks the obstacles (ValueError naming the fault): finite,
    ``xmax > xmin`` and ``ymax > ymin``, inside the arena (they may overlap). Equality and
    hash compare size, name and the obstacle values.
    """

    size: float
    obstacles: NDArray[np.float64] = field(
        default_factory=lambda: np.zeros((0, 4), dtype=np.float64)
    )
    name: str = ""

    def __post_init__(self) -> None:
        size = float(self.size)
        if not math.isfinite(size) or size <= 0.0:
            raise ValueError(f"arena size must be a positive finite number, got {self.size!r}")
        if size > MAX_ARENA_SIZE:
            raise ValueError(
                f"arena size {size:g} m is beyond the largest arena, {MAX_ARENA_SIZE:g} m "
                "(larger ones lose the float precision the collision checks need)"
            )
        boxes = np.array(self.obstacles, dtype=np.float64, copy=True)
        if boxes.size == 0:
            boxes = boxes.reshape(0, 4)
        if boxes.ndim != 2 or boxes.shape[1] != 4:
            raise ValueError(f"obstacles must be a (k, 4) array, got shape {boxes.shape}")
        fault = _obstacle_fault(boxes, size)
        if fault:
            raise ValueError(fault)
        boxes.setflags(write=False)
        object.__setattr__(self, "size", size)
        object.__setattr__(self, "obstacles", boxes)
        object.__setattr__(self, "name", str(self.name))

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, World):
            return NotImplemented
        return (
            self.size == other.size
            and self.name == other.name
            and np.array_equal(self.obstacles, other.obstacles)
        )

    def __hash__(self) -> int:
        return hash((self.size, self.name, self.obstacles.tobytes()))

    def __repr__(self) -> str:
        boxes = len(self.obstacles)
        return f"World(size={self.size}, obstacles=<{boxes} boxes>, name={self.name!r})"

    def signed_distance(self, points: ArrayLike) -> NDArray[np.float64]:
        """Signed distance (m) from each point (n, 2) to the nearest obstacle or wall.

        Per box: outside, the Euclidean distance ``hypot(max(xmin - x, 0, x - xmax),
        max(ymin - y, 0, y - ymax))``; inside, minus the depth ``min(x - xmin, xmax - x,
        y - ymin, ymax - y)``. Walls: ``min(x, size - x, y, size - y)`` (negative outside).
        The result is the minimum over boxes and walls.
        """
        p = np.asarray(points, dtype=np.float64).reshape(-1, 2)
        x, y = p[:, 0:1], p[:, 1:2]
        walls = np.minimum(np.minimum(x, self.size - x), np.minimum(y, self.size - y))[:, 0]
        if self.obstacles.shape[0] == 0:
            return walls
        b = self.obstacles
        dx = np.maximum(np.maximum(b[None, :, 0] - x, x - b[None, :, 2]), 0.0)
        dy = np.maximum(np.maximum(b[None, :, 1] - y, y - b[None, :, 3]), 0.0)
        depth = np.minimum(
            np.minimum(x - b[None, :, 0], b[None, :, 2] - x),
            np.minimum(y - b[None, :, 1], b[None, :, 3] - y),
        )
        boxes = np.where(depth > 0.0, -depth, np.hypot(dx, dy))
        return np.asarray(np.minimum(walls, boxes.min(axis=1)), dtype=np.float64)

    def free_at(self, points: ArrayLike, clearance: float = 0.0) -> NDArray[np.bool_]:
        """(n,) True where a point is at least ``clearance`` (m) from every obstacle and wall."""
        return self.signed_distance(points) >= clearance


@dataclass(frozen=True)
class Scenario:
    """A mission in ``world``: start pose (x, y, theta) (m, m, rad) and goal (x, y) (m).

    The constructor wraps theta onto (-pi, pi] and raises ValueError when a value is not
    finite or the start or goal lies outside the arena or strictly inside an obstacle.
    """

    world: World
    start: tuple[float, float, float]
    goal: tuple[float, float]

    def __post_init__(self) -> None:
        start = tuple(float(v) for v in self.start)
        goal = tuple(float(v) for v in self.goal)
        if len(start) != 3 or len(goal) != 2:
            raise ValueError("start must be (x, y, theta) and goal (x, y)")
        if not all(math.isfinite(v) for v in start + goal):
            raise ValueError(f"start {start} or goal {goal} is not finite")
        for label, xy in (("start", start[:2]), ("goal", goal)):
            fault = _point_fault(self.world, xy)
            if fault:
                raise ValueError(f"{label} {xy} {fault}")
        wrapped = (start[0], start[1], float(wrap_angle(start[2])))
        object.__setattr__(self, "start", wrapped)
        object.__setattr__(self, "goal", (goal[0], goal[1]))


def _obstacle_fault(boxes: NDArray[np.float64], size: float) -> str:
    """The first thing wrong with a (k, 4) obstacle array, or '' when it is valid."""
    for i, (x0, y0, x1, y1) in enumerate(boxes):
        if not np.all(np.isfinite((x0, y0, x1, y1))):
            return f"obstacles[{i}] is not finite"
        if x1 <= x0 or y1 <= y0:
            return f"obstacles[{i}] has xmax <= xmin or ymax <= ymin"
        if x0 < 0.0 or y0 < 0.0 or x1 > size or y1 > size:
            return f"obstacles[{i}] lies outside the arena [0, {size}]^2"
    return ""


def _point_fault(world: World, xy: Sequence[float]) -> str:
    x, y = xy
    if not (0.0 <= x <= world.size and 0.0 <= y <= world.size):
        return "lies outside the arena"
    b = world.obstacles
    inside = (b[:, 0] < x) & (x < b[:, 2]) & (b[:, 1] < y) & (y < b[:, 3])
    if np.any(inside):
        return f"lies inside obstacles[{int(np.flatnonzero(inside)[0])}]"
    return ""


#: reads a ROS map YAML into a world (the ``map`` key of a world file)
MapReader = Callable[[Path], World]


@config_dataclass
class _ScenarioEntry:
    start: tuple[Float, Float, Float]
    goal: tuple[Float, Float]


@config_dataclass
class _WorldFile:
    """The keys of a world file (module docstring), types checked; the geometry is checked
    by :class:`World` and :class:`Scenario`, ``size`` or ``map`` by :func:`load_world`."""

    format: Str
    version: Annotated[int, Field(strict=True)]
    size: Float | None = None
    map: Str | None = None
    units: Literal["m"] = "m"
    name: Str | None = None
    obstacles: list[tuple[Float, Float, Float, Float]] | None = None
    scenarios: list[_ScenarioEntry] | None = None


def load_world(
    path: str | Path, map_reader: MapReader | None = None
) -> tuple[World, list[Scenario]]:
    """Read and validate a world file; FileFormatError naming the file, the key and the fault
    (for a missing, empty or non-YAML file as :func:`mentor_core.validation.read_yaml`; a file
    with a ``map`` key needs ``map_reader``, see the module docstring)."""
    source = Path(path)
    doc = read_yaml(source)
    if isinstance(doc, dict):  # the format first: a foreign file is named as such
        if doc.get("format") != WORLD_FORMAT:
            raise FileFormatError(
                source, f"format is {doc.get('format')!r}, not {WORLD_FORMAT!r}"
            )
        if not is_version(doc.get("version"), WORLD_VERSION):
            raise FileFormatError(source, f"version {doc.get('version')!r} is not supported")
    try:
        spec = validate(_WorldFile, doc)
    except ConfigError as err:
        raise FileFormatError(source, str(err)) from None
    base = _map_world(spec, source, map_reader)
    if base is not None:
        size = base.size
    elif spec.size is None:
        raise FileFormatError(source, "size: missing key (or give 'map')")
    else:
        size = spec.size
        try:
            World(size=size)  # the size alone first, so that its fault is named as such
        except ValueError as err:
            raise FileFormatError(source, f"size: {err}") from None
    boxes = np.array(spec.obstacles or [], dtype=np.float64).reshape(-1, 4)
    if base is not None:
        boxes = np.concatenate([base.obstacles, boxes])
    name = spec.name if spec.name is not None else (base.name if base is not None else "")
    try:
        world = World(size=size, obstacles=boxes, name=name)
    except ValueError as err:  # names the obstacle: obstacles[i] ...
        raise FileFormatError(source, str(err)) from None
    scenarios = []
    for i, entry in enumerate(spec.scenarios or []):
        try:
            scenarios.append(Scenario(world, entry.start, entry.goal))
        except ValueError as err:
            raise FileFormatError(source, f"scenarios[{i}]: {err}") from None
    return world, scenarios


def _map_world(spec: _WorldFile, source: Path, map_reader: MapReader | None) -> World | None:
    """The world of the file's ``map`` key (None without one); FileFormatError naming the
    world file for a bad key, and the map's own fault after ``map:``."""
    if spec.map is None:
        return None
    if spec.size is not None:
        raise FileFormatError(source, "map: give 'size' or 'map', not both (a map sets the arena)")
    if not spec.map.strip():
        raise FileFormatError(source, "map: must name a map YAML file")
    if map_reader is None:
        raise FileFormatError(
            source,
            "map: key 'map' needs a map reader: load the file with "
            "mentor_core.navigation.map_world.load_world_file",
        )
    path = Path(spec.map)
    try:
        return map_reader(path if path.is_absolute() else source.parent / path)
    except ValueError as err:  # FileFormatError naming the map YAML or its image
        raise FileFormatError(source, f"map: {err}") from None


def save_world(path: str | Path, world: World, scenarios: Iterable[Scenario] = ()) -> None:
    """Write ``world`` and start/goal pairs as a world file, atomically.

    Floats are written with ``repr`` precision, so :func:`load_world` gives back equal values.
    Raises ValueError when a scenario belongs to another world.
    """
    scenarios = list(scenarios)
    if any(s.world != world for s in scenarios):
        raise ValueError("every scenario saved with a world must belong to that world")
    doc: dict[str, Any] = {
        "format": WORLD_FORMAT,
        "version": WORLD_VERSION,
        "units": "m",
        "name": world.name,
        "size": world.size,
        "obstacles": [[float(v) for v in box] for box in world.obstacles],
        "scenarios": [
            {"start": [float(v) for v in s.start], "goal": [float(v) for v in s.goal]}
            for s in scenarios
        ],
    }
    write_text_atomic(path, yaml.safe_dump(doc, sort_keys=False, default_flow_style=None))
