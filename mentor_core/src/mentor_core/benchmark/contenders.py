"""The planners the benchmark compares: evolved genomes, the baselines and the oracle.

A :class:`Contender` is a name, a kind, the profile it acts with (sensors, action limits,
input encoding) and a maker of its policy for a list of scenarios (a fresh one per run, so a
planner with a memory starts blank). Every contender runs through the same engine and the
same input and action functions (``mentor_core.sim.episode.run_episodes``). A contender may
also steer to goals of its own (:func:`on_scan_map`: the carrot of a plan on the map of what
its sensors read), instead of the scenario's goal.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from mentor_core.benchmark.bug import bug_policy
from mentor_core.benchmark.oracle import oracle_policy
from mentor_core.benchmark.reactive import reactive_policy
from mentor_core.errors import FileFormatError
from mentor_core.evolution.genome import Genome
from mentor_core.evolution.network import FeedForwardNetwork
from mentor_core.files.genome_file import load_genome_and_metadata
from mentor_core.navigation.guide import GuideConfig
from mentor_core.navigation.scan_map import scan_guide_config, scan_guided_goals
from mentor_core.runtime.planner import (
    DEPLOYED_SHIM_DEG,
    deployed_control_period,
    deployed_turn_gain,
    deployed_view_margin,
    planner_profile,
)
from mentor_core.sim.decision_split import at_control_period
from mentor_core.sim.episode import InputGoals, Policy
from mentor_core.sim.planner_settings import with_planner
from mentor_core.sim.robots import RobotProfile
from mentor_core.sim.view_corridor import set_view_margin
from mentor_core.sim.world import Scenario
from mentor_core.training.assessment import check_compatible

Kind = Literal["evolved", "baseline", "oracle"]
PolicyMaker = Callable[[Sequence[Scenario], RobotProfile], Policy]
GoalsMaker = Callable[[Sequence[Scenario], RobotProfile], InputGoals]
#: prefix of the name of a contender on its scan map (the ``-s<seed>`` suffix stays last)
MAPPED = "mapped-"
#: prefix of the name of an evolved contender behind a rotation shim
SHIMMED = "shim-"
#: prefix of the name of a contender behind a collision guard
GUARDED = "guard-"
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

    def policy(self, scenarios: Sequence[Scenario]) -> Policy:
        """A fresh policy for robot ``i`` on ``scenarios[i]``."""
        return self.make_policy(scenarios, self.profile)

    def input_goals(self, scenarios: Sequence[Scenario]) -> InputGoals | None:
        """Fresh goals its networks see (``run_episodes``' ``input_goals``); None: the
        scenarios' goals."""
        return None if self.make_goals is None else self.make_goals(scenarios, self.profile)


def on_scan_map(
    contender: Contender, lookahead: float | None = None, clearance_cost: float | None = None,
    least_margin: float | None = None,
) -> Contender:  # fmt: skip
    """``contender`` steering to the carrot of a plan on the map of what its own sensors have
    read (:func:`mentor_core.navigation.scan_map.scan_guided_goals`, unknown space free),
    named ``mapped-<name>``: memory of where the obstacles are, with nothing of the world
    known beforehand. ``lookahead`` (m): the carrot's distance along the plan;
    ``clearance_cost`` and ``least_margin`` (m): the plan's clearance cost (each default
    :func:`~mentor_core.navigation.scan_map.scan_guide_config`'s)."""
    config = scan_guide_config(contender.profile, lookahead, least_margin=least_margin,
                               clearance_cost=clearance_cost)  # fmt: skip

    def make(scenarios: Sequence[Scenario], profile: RobotProfile) -> InputGoals:
        return scan_guided_goals(scenarios, profile, config)[0]

    return Contender(MAPPED + contender.name, contender.kind, contender.profile,
                     contender.make_policy, contender.source, make, config)  # fmt: skip


def behind_rotation_shim(contender: Contender, threshold: float) -> Contender:
    """``contender`` (an evolved planner) turning on the spot onto each new goal until its
    bearing is within ``threshold`` (rad), then driving as trained
    (:mod:`mentor_core.sim.rotation_shim`), named ``shim-<name>``. ConfigError for a
    threshold outside ``(0, pi]``."""
    profile = with_planner(contender.profile, rotation_shim=threshold, source="rotation shim")
    return dataclasses.replace(contender, name=SHIMMED + contender.name, profile=profile)


def with_turn_gain(contender: Contender, gain: float) -> Contender:
    """``contender`` (an evolved planner) with its network's turn scaled by ``gain``
    (:mod:`mentor_core.sim.turn_gain`), its name unchanged (``bench.json`` lists the gain
    among its settings). ConfigError for a gain outside ``(0, 1]``."""
    profile = with_planner(contender.profile, turn_gain=gain, source="turn gain")
    return dataclasses.replace(contender, profile=profile)


def with_view_margin(contender: Contender, margin: float | None) -> Contender:
    """``contender`` (an evolved planner) whose network sees only what lies within ``margin``
    (m) of its way to its goal (:mod:`mentor_core.sim.view_corridor`; None: as it was, ``inf``:
    everything), its name unchanged (``bench.json`` lists the margin among its settings).
    ConfigError for a margin that is not positive."""
    profile = set_view_margin(contender.profile, margin, "view corridor")
    return dataclasses.replace(contender, profile=profile)


def with_control_period(contender: Contender, period: float | None) -> Contender:
    """``contender`` (an evolved planner) deciding every ``period`` s, each decision that share
    of its trained period's step and turn (:mod:`mentor_core.sim.decision_split`; None: as
    trained), its name unchanged (``bench.json`` lists the period among its settings).
    ConfigError for a period longer than its own."""
    profile = at_control_period(contender.profile, period, contender.source or contender.name)
    return dataclasses.replace(contender, profile=profile)


def behind_collision_guard(contender: Contender) -> Contender:
    """``contender`` with a collision guard vetting its decisions against what its sensors
    read lately (:mod:`mentor_core.sim.collision_guard`), named ``guard-<name>``."""
    profile = with_planner(contender.profile, collision_guard=True, source="collision guard")
    return dataclasses.replace(contender, name=GUARDED + contender.name, profile=profile)


def as_deployed(
    contender: Contender, lookahead: float | None = None, turn_gain: float | None = None,
    view_margin: float | None = None, control_period: float | None = None,
    clearance_cost: float | None = None, least_margin: float | None = None,
) -> Contender:  # fmt: skip
    """``contender`` (an evolved planner) as the shipped planners are deployed and scored
    (experiment E018, "Where it stands"): deciding every ``control_period`` s
    (default its robot's: :func:`~mentor_core.runtime.planner.deployed_control_period`) on
    its scan map (:func:`on_scan_map`, ``lookahead``, ``clearance_cost``, ``least_margin``),
    behind the collision guard and a
    rotation shim of :data:`DEPLOYED_SHIM_DEG`, with ``turn_gain`` on its network's turn
    (default its robot's: :func:`~mentor_core.runtime.planner.deployed_turn_gain`) and a
    view corridor of ``view_margin`` (default its robot's, if any:
    :func:`~mentor_core.runtime.planner.deployed_view_margin`; ``inf``: none), named
    ``mapped-guard-shim-<name>`` (``mentor-bench --deployed``; the planner node's
    ``control_period``, ``scan_map``, ``rotation_shim_deg``, ``collision_guard``,
    ``turn_gain`` and ``view_margin``)."""
    gain = deployed_turn_gain(contender.profile) if turn_gain is None else turn_gain
    margin = deployed_view_margin(contender.profile) if view_margin is None else view_margin
    if control_period is None:
        control_period = deployed_control_period(contender.profile)
    split = with_control_period(contender, control_period)
    gained = with_view_margin(with_turn_gain(split, gain), margin)
    shimmed = behind_rotation_shim(gained, math.radians(DEPLOYED_SHIM_DEG))
    return on_scan_map(behind_collision_guard(shimmed), lookahead, clearance_cost, least_margin)


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


def evolved(path: str | Path, robot: RobotProfile, name: str = "") -> Contender:
    """The genome in ``path`` with the planner settings of its metadata (as ``mentor-eval``
    runs it) on ``robot`` (its robot-file profile). FileFormatError or ConfigError naming the
    file for a bad genome, or one that does not fit the robot."""
    genome, metadata = load_genome_and_metadata(path)
    profile = planner_profile(robot, metadata, path)
    try:
        return from_genome(genome, profile, name or str(path), str(path))
    except ValueError as err:
        raise FileFormatError(path, str(err)) from None


def from_genome(genome: Genome, profile: RobotProfile, name: str, source: str = "") -> Contender:
    """A genome in memory (e.g. one of a run's population) acting with ``profile``, the
    planner profile it was trained with (``mentor_core.runtime.planner.planner_profile`` of
    its metadata, or the trainer's ``make_problem(config).profile``). ValueError when its
    inputs and outputs do not fit the profile."""
    check_compatible(genome, profile)
    network = FeedForwardNetwork.from_genome(genome)

    def make(scenarios: Sequence[Scenario], profile: RobotProfile) -> Policy:
        return network.episode_policy(len(scenarios))

    return Contender(name, "evolved", profile, make, source)
