"""Which scenario each simulated robot runs in each episode.

The simulator node takes its scenarios from a world file
(:func:`mentor_core.sim.world.load_world`), a scenario bag
(:func:`mentor_core.files.bags.read_scenario_bag`) or, when given neither, the training DoE of
its first robot's profile (:func:`mentor_core.sim.scenarios.training_scenarios` with a seed).
:class:`ScenarioPlan` screens every scenario for every robot profile (a start whose body
overlaps an obstacle or a wall cannot be run by that robot: it is skipped with a one-line
reason) and hands out the rest: in episode ``e`` robot ``j`` of ``n`` runs its
``(first + e n + j)``-th runnable scenario, cyclically
(:func:`mentor_core.runtime.simulator.scenario_for`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from mentor_core.errors import ConfigError, FileFormatError
from mentor_core.files.bags import read_scenario_bag
from mentor_core.runtime.simulator import RobotSetup, scenario_for, start_fault
from mentor_core.sim.robots import RobotProfile
from mentor_core.sim.scenarios import training_scenarios
from mentor_core.sim.world import Scenario, World, load_world


@dataclass(frozen=True)
class ScenarioSource:
    """A world and its scenarios; ``origin`` names where they came from (for messages)."""

    world: World
    scenarios: tuple[Scenario, ...]
    origin: str


def load_scenario_source(
    world_file: str | Path = "",
    scenario_bag: str | Path = "",
    profile: RobotProfile | None = None,
    seed: int = 0,
) -> ScenarioSource:
    """Scenarios from a world file, a scenario bag, or (neither given) the training DoE of
    ``profile`` with ``seed``.

    ConfigError when both files are given (or neither and no profile); FileFormatError
    naming the file for a missing, corrupt or foreign file, or one without scenarios.
    """
    if str(world_file) and str(scenario_bag):
        raise ConfigError("give a world file or a scenario bag, not both", key="world")
    if str(world_file):
        world, scenarios = load_world(world_file)
        origin = str(world_file)
    elif str(scenario_bag):
        world, scenarios, _, _ = read_scenario_bag(scenario_bag)
        origin = str(scenario_bag)
    else:
        if profile is None:
            raise ConfigError("no world file, no scenario bag and no profile to sample for")
        scenarios = training_scenarios(profile, seed)
        world = scenarios[0].world
        origin = f"training scenarios of {profile.name!r}, seed {seed}"
    if not scenarios:
        raise FileFormatError(origin, "holds no scenarios (start/goal pairs)")
    return ScenarioSource(world, tuple(scenarios), origin)


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
        for name, profile in self.robots:
            ok = []
            for i, sc in enumerate(source.scenarios):
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
            out.append(self._setup(name, profile, index, self.source.scenarios[index]))
        return out
