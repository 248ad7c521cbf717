"""Worlds from ROS maps: a map YAML + PGM as a :class:`~mentor_core.sim.world.World`, and
world files whose ``map`` key names one.

The map's occupied and unknown cells become obstacle boxes
(:func:`mentor_core.navigation.grid.world_from_grid`: unknown space is not driven into), the
arena is the square of the map's larger side, and the world's ``map`` frame is the map's own
shifted by its ``origin``: map point ``(x, y)`` is world point ``(x - origin_x,
y - origin_y)``, so the map's lower-left pixel corner is the arena's corner ``(0, 0)``.
A map rotated in its frame (``origin`` yaw != 0) is refused.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

from mentor_core.errors import FileFormatError
from mentor_core.navigation.grid import OccupancyGrid, world_from_grid
from mentor_core.navigation.map_file import load_map
from mentor_core.sim.world import Scenario, World, load_world


def arena_grid(grid: OccupancyGrid) -> OccupancyGrid:
    """``grid`` in the world's frame (module docstring): the same cells, origin ``(0, 0, 0)``."""
    return replace(grid, origin=(0.0, 0.0, 0.0))


def load_map_world(path: str | Path) -> tuple[World, OccupancyGrid]:
    """The world of a map YAML (named after its stem) and the map's grid in that world's
    frame; FileFormatError naming the YAML or image and the fault."""
    source = Path(path)
    grid = load_map(source)
    try:
        world = world_from_grid(grid, name=source.stem)
    except ValueError as err:
        raise FileFormatError(source, str(err)) from None
    return world, arena_grid(grid)


def read_map_world(path: Path) -> World:
    """The world of a map YAML (the ``map_reader`` of :func:`load_world_file`)."""
    return load_map_world(path)[0]


def load_world_file(path: str | Path) -> tuple[World, list[Scenario]]:
    """:func:`mentor_core.sim.world.load_world` that also reads world files naming a ROS map
    (``map: office.yaml``)."""
    return load_world(path, map_reader=read_map_world)
