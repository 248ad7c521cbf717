"""Which scenario each simulated robot runs in each episode.

The simulator node takes its scenarios from a world file
(:func:`mentor_core.navigation.map_world.load_world_file`: its obstacles, or a ROS map its
``map`` key names), a scenario bag (:func:`mentor_core.files.bags.read_scenario_bag`), a ROS
map (``map_yaml``: :data:`MAP_SCENARIOS` start/goal pairs sampled on it with the seed) or, when
given none, the training DoE of its first robot's profile
(:func:`mentor_core.sim.scenarios.training_scenarios` with a seed). :func:`source_map` is the
world as the occupancy grid the simulator publishes on ``/map``.
:class:`ScenarioPlan` screens every scenario for every robot profile (a start whose body
overlaps an obstacle or a wall cannot be run by that robot: it is skipped with a one-line
reason) and hands out the rest: in episode ``e`` robot ``j`` of ``n`` runs its
``(first + e n + j)``-th runnable scenario, cyclically
(:func:`mentor_core.runtime.simulator.scenario_for`).

Scenarios the simulator drew itself (the training DoE, pairs on a ROS map) are drawn for one
profile, at its scale. Each robot of another profile gets missions of its own in the same
world, as many, drawn for its body and its reach
(:func:`mentor_core.sim.scenarios.sample_scenarios` with the seed and the robot's place), so
that a Swarm-Robot beside a UGV is sent 2 m, not 12 m. Scenarios of a world file or a bag are
the user's: every robot runs them.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from mentor_core.errors import ConfigError, FileFormatError
from mentor_core.files.bags import read_scenario_bag
from mentor_core.navigation.grid import OccupancyGrid, world_grid
from mentor_core.navigation.map_world import load_map_world
from mentor_core.runtime.simulator import RobotSetup, scenario_for, start_fault
from mentor_core.sim.robots import RobotProfile
from mentor_core.sim.scenarios import sample_scenarios, training_scenarios
from mentor_core.sim.world import Scenario, World, load_world

#: start/goal pairs sampled on a ROS map given without scenarios (``map_yaml``)
MAP_SCENARIOS = 10
#: a seed stream of its own for the missions of robots of another profile
MISSION_STREAM = 7


@dataclass(frozen=True)
class ScenarioSource:
    """A world and its scenarios; ``origin`` names where they came from (for messages);
    ``map_resolution`` the cell side (m) of the ROS map the world was made of, None if none."""

    world: World
    scenarios: tuple[Scenario, ...]
    origin: str
    map_resolution: float | None = None
    #: the profile the scenarios were drawn for, and the seed (None: given by a file)
    drawn_for: str | None = None
    seed: int = 0

    def missions(self, profile: RobotProfile, robot: int) -> tuple[Scenario, ...]:
        """The scenarios robot number ``robot`` of ``profile`` runs (module docstring)."""
        if self.drawn_for is None or profile.name == self.drawn_for:
            return self.scenarios
        rng = np.random.default_rng([self.seed, robot, MISSION_STREAM])
        try:
            return tuple(sample_scenarios(self.world, profile, len(self.scenarios), rng))
        except ValueError as err:
            raise FileFormatError(self.origin, f"no missions for {profile.name}: {err}") from None


def load_scenario_source(
    world_file: str | Path = "",
    scenario_bag: str | Path = "",
    profile: RobotProfile | None = None,
    seed: int = 0,
    map_yaml: str | Path = "",
) -> ScenarioSource:
    """Scenarios from a world file, a scenario bag, a ROS map (:data:`MAP_SCENARIOS` pairs
    sampled for ``profile`` with ``seed``) or (none given) the training DoE of ``profile``
    with ``seed``.

    ConfigError when more than one source is given (or none and no profile);
    FileFormatError naming the file for a missing, corrupt or foreign file, or one without
    scenarios.
    """
    given = [str(f) for f in (world_file, scenario_bag, map_yaml) if str(f)]
    if len(given) > 1:
        raise ConfigError(
            "give only one of a world file, a scenario bag or a map", key="world"
        )
    resolutions: list[float] = []
    drawn_for: str | None = None

    def read_map(path: Path) -> World:
        map_world, grid = load_map_world(path)
        resolutions.append(grid.resolution)
        return map_world

    if str(world_file):
        world, scenarios = load_world(world_file, map_reader=read_map)
        origin = str(world_file)
    elif str(map_yaml):
        if profile is None:
            raise ConfigError("a map without scenarios needs a profile to sample them for")
        world = read_map(Path(map_yaml))
        rng = np.random.default_rng(seed)
        try:
            scenarios = sample_scenarios(world, profile, MAP_SCENARIOS, rng)
        except ValueError as err:
            fault = f"no start/goal pairs for {profile.name}: {err}"
            raise FileFormatError(map_yaml, fault) from None
        origin = f"{map_yaml}, pairs of seed {seed}"
        drawn_for = profile.name
    elif str(scenario_bag):
        world, scenarios, _, _ = read_scenario_bag(scenario_bag)
        origin = str(scenario_bag)
    else:
        if profile is None:
            raise ConfigError("no world file, no scenario bag and no profile to sample for")
        scenarios = training_scenarios(profile, seed)
        world = scenarios[0].world
        origin = f"training scenarios of {profile.name!r}, seed {seed}"
        drawn_for = profile.name
    if not scenarios:
        raise FileFormatError(origin, "holds no scenarios (start/goal pairs)")
    return ScenarioSource(world, tuple(scenarios), origin, resolutions[0] if resolutions else None,
                          drawn_for, seed)  # fmt: skip


def source_map(source: ScenarioSource, resolution: float) -> OccupancyGrid:
    """The simulated world as an occupancy grid in ``map`` (origin at the arena's corner):
    rasterised at the cell side of the ROS map it was made of (so its cells come back
    exactly; the map's unknown cells are walls in the simulator, so occupied), else at
    ``resolution`` (m)."""
    cell = source.map_resolution if source.map_resolution is not None else resolution
    return world_grid(source.world, cell)


class ScenarioPlan:
    """The scenario of every robot in every episode (module docstring).

    Args:
        source: world and scenarios.
        robots: ``(name, profile)`` of each robot, in order (robot ``j``).
        first: offset of the first scenario handed out.
        time_limit: T_tot of every episode, s; None for the profile's time budget.

    Raises FileFormatError (naming the source) when a robot can run none of the scenarios.
    """

    def __init__(
        self,
        source: ScenarioSource,
        robots: Sequence[tuple[str, RobotProfile]],
        first: int = 0,
        time_limit: float | None = None,
    ) -> None:
        if not robots:
            raise ConfigError("the simulator needs at least one robot", key="robots")
        self.source = source
        self.robots = tuple(robots)
        self.first = int(first)
        self.time_limit = time_limit
        skipped: list[str] = []
        runnable: list[tuple[int, ...]] = []
        #: each robot's scenarios (module docstring)
        self.missions = tuple(source.missions(p, j) for j, (_, p) in enumerate(self.robots))
        for (name, profile), missions in zip(self.robots, self.missions, strict=True):
            ok = []
            for i, sc in enumerate(missions):
                fault = start_fault(source.world, self._setup(name, profile, i, sc))
                if fault:
                    skipped.append(f"scenario {i} skipped for {name} ({profile.name}): {fault}")
                else:
                    ok.append(i)
            if not ok:
                first_fault = skipped[-1].split(": ", 1)[1]
                raise FileFormatError(
                    source.origin,
                    f"no scenario can start robot {name} ({profile.name}); e.g. {first_fault}",
                )
            runnable.append(tuple(ok))
        self.skipped = tuple(skipped)
        self.runnable = tuple(runnable)

    def _setup(self, name: str, profile: RobotProfile, index: int, sc: Scenario) -> RobotSetup:
        return RobotSetup(
            name=name,
            profile=profile,
            start=sc.start,
            goal=sc.goal,
            scenario=index,
            time_budget=self.time_limit,
        )

    def setups(self, episode: int) -> list[RobotSetup]:
        """The robots' setups of episode ``episode`` (0-based), in robot order."""
        n = len(self.robots)
        out = []
        for j, (name, profile) in enumerate(self.robots):
            ok = self.runnable[j]
            index = ok[scenario_for(episode, j, n, len(ok), self.first)]
            out.append(self._setup(name, profile, index, self.missions[j][index]))
        return out
