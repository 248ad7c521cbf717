"""The planners the benchmark compares: evolved genomes, the baselines and the oracle.

A :class:`Contender` is a name, a kind, the profile it acts with (sensors, action limits,
input encoding) and a maker of its policy for a list of scenarios (a fresh one per run, so a
planner with a memory starts blank). Every contender runs through the same engine and the
same decision chain (``mentor_core.controller.episodes.run_episodes``) through its stages. An
evolved contender runs as a deployment (:mod:`mentor_core.controller.deployment`), which may
steer it to goals of its own (:func:`on_scan_map`: the carrot of a plan on the map of what its
sensors read) instead of the scenario's goal; a baseline may be run on its scan map and behind
the collision guard too, to show what those carry.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from mentor_core.benchmark.bug import bug_policy
from mentor_core.benchmark.oracle import oracle_policy
from mentor_core.benchmark.pursuit import pursuit_policy
from mentor_core.benchmark.reactive import reactive_policy
from mentor_core.controller.collision_guard import CollisionGuardStage
from mentor_core.controller.deployment import Deployment
from mentor_core.controller.stage import Stage
from mentor_core.errors import FileFormatError
from mentor_core.evolution.genome import Genome
from mentor_core.evolution.network import FeedForwardNetwork
from mentor_core.navigation.guide import GuideConfig
from mentor_core.navigation.scan_map import scan_guided_goals
from mentor_core.runtime.planner import deployed_genome
from mentor_core.sim.episode import InputGoals, Policy
from mentor_core.sim.robots import RobotProfile
from mentor_core.sim.world import Scenario
from mentor_core.training.assessment import check_compatible

Kind = Literal["evolved", "baseline", "oracle", "pursuit"]
PolicyMaker = Callable[[Sequence[Scenario], RobotProfile], Policy]
GoalsMaker = Callable[[Sequence[Scenario], RobotProfile], InputGoals]
#: prefix of the name of a baseline on its scan map (the ``-s<seed>`` suffix stays last)
MAPPED = "mapped-"
#: prefix of the name of a baseline behind a collision guard
GUARDED = "guard-"
#: prefix of the name of a pure pursuit in an evolved planner's place
PURSUIT = "pursuit-"
FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]


@dataclass(frozen=True)
class Contender:
    """One planner of the benchmark (module docstring); ``source`` names its genome file."""

    name: str
    kind: Kind
    profile: RobotProfile
    make_policy: PolicyMaker
    source: str = ""
    make_goals: GoalsMaker | None = None
    #: the guide of a planner on its scan map (:func:`on_scan_map`), None for the others
    guide: GuideConfig | None = None
    #: the controller's stages its decisions pass (:mod:`mentor_core.controller`)
    stages: tuple[Stage, ...] = ()

    def policy(self, scenarios: Sequence[Scenario]) -> Policy:
        """A fresh policy for robot ``i`` on ``scenarios[i]``."""
        return self.make_policy(scenarios, self.profile)

    def input_goals(self, scenarios: Sequence[Scenario]) -> InputGoals | None:
        """Fresh goals its networks see (``run_episodes``' ``input_goals``); None: the
        scenarios' goals."""
        return None if self.make_goals is None else self.make_goals(scenarios, self.profile)


def on_scan_map(contender: Contender, config: GuideConfig, rename: bool = True) -> Contender:
    """``contender`` steering to the carrot of a plan on the map of what its own sensors have
    read (:func:`mentor_core.navigation.scan_map.scan_guided_goals`, unknown space free), the
    plan's settings ``config``; named ``mapped-<name>`` with ``rename``: memory of where the
    obstacles are, with nothing of the world known beforehand."""

    def make(scenarios: Sequence[Scenario], profile: RobotProfile) -> InputGoals:
        return scan_guided_goals(scenarios, profile, config)[0]

    name = MAPPED + contender.name if rename else contender.name
    return dataclasses.replace(contender, name=name, make_goals=make, guide=config)


def behind_collision_guard(contender: Contender, guard: CollisionGuardStage) -> Contender:
    """``contender`` (a baseline) with the collision guard ``guard`` vetting its decisions
    against what its sensors read lately (:mod:`mentor_core.controller.collision_guard`),
    named ``guard-<name>``."""
    return dataclasses.replace(contender, name=GUARDED + contender.name,
                               stages=(*contender.stages, guard))  # fmt: skip


def pursuit_of(contender: Contender) -> Contender:
    """``contender`` (an evolved planner, as deployed) with a pure pursuit of the goal its
    network is shown in the network's place (:mod:`mentor_core.benchmark.pursuit`): the same
    profile, stages and plan, named ``pursuit-<name>``, of kind ``pursuit``."""
    return dataclasses.replace(contender, name=PURSUIT + contender.name, kind="pursuit",
                               make_policy=pursuit_policy, source="")  # fmt: skip


#: the hand-written planners: name -> (kind, policy maker)
HAND_WRITTEN: dict[str, tuple[Kind, PolicyMaker]] = {
    "vfh": ("baseline", reactive_policy),
    "bug": ("baseline", bug_policy),
    "oracle": ("oracle", oracle_policy),
}


def hand_written(name: str, limits: RobotProfile, label: str = "") -> Contender:
    """The baseline or oracle ``name`` acting within the action limits of ``limits`` (the
    benchmark's reference planner, or the shipped planners': ``benchmark.suite``), named
    ``label`` (default ``name``)."""
    kind, maker = HAND_WRITTEN[name]
    return Contender(label or name, kind, limits, maker)


def evolved(
    path: str | Path, robot: RobotProfile, name: str = "", deployment: Deployment | None = None
) -> Contender:
    """The genome in ``path`` on ``robot`` (its robot-file profile), run as ``deployment``
    (:mod:`mentor_core.controller.deployment`; None: as trained, as ``mentor-eval`` runs it),
    named ``name`` (default its path). FileFormatError or ConfigError naming the file for a bad
    genome, or one that does not fit the robot."""
    genome, deployed = deployed_genome(path, robot.name, deployment)
    try:
        contender = from_genome(genome, deployed.profile, name or str(path), str(path),
                                deployed.stages)  # fmt: skip
    except ValueError as err:
        raise FileFormatError(path, str(err)) from None
    if deployed.guide is None:
        return contender
    return on_scan_map(contender, deployed.guide, rename=False)


def from_genome(
    genome: Genome, profile: RobotProfile, name: str, source: str = "",
    stages: tuple[Stage, ...] = (),
) -> Contender:  # fmt: skip
    """A genome in memory (e.g. one of a run's population) acting with ``profile``, the
    planner profile it was trained with (``mentor_core.runtime.planner.planner_profile`` of
    its metadata, or the trainer's ``make_problem(config).profile``) through ``stages``.
    ValueError when its inputs and outputs do not fit the profile."""
    check_compatible(genome, profile)
    network = FeedForwardNetwork.from_genome(genome)

    def make(scenarios: Sequence[Scenario], profile: RobotProfile) -> Policy:
        return network.episode_policy(len(scenarios))

    return Contender(name, "evolved", profile, make, source, stages=stages)
