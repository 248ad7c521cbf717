"""The planners the benchmark compares: evolved genomes, the baselines and the oracle.

A :class:`Contender` is a name, a kind, the profile it acts with (sensors, action limits,
input encoding) and a maker of its policy for a list of scenarios (a fresh one per run, so a
planner with a memory starts blank). Every contender runs through the same engine and the
same input and action functions (``mentor_core.sim.episode.run_episodes``).
"""

from __future__ import annotations

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
from mentor_core.runtime.planner import planner_profile
from mentor_core.sim.episode import Policy
from mentor_core.sim.robots import RobotProfile
from mentor_core.sim.world import Scenario
from mentor_core.training.assessment import check_compatible

Kind = Literal["evolved", "baseline", "oracle"]
PolicyMaker = Callable[[Sequence[Scenario], RobotProfile], Policy]
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

    def policy(self, scenarios: Sequence[Scenario]) -> Policy:
        """A fresh policy for robot ``i`` on ``scenarios[i]``."""
        return self.make_policy(scenarios, self.profile)


#: the hand-written planners: name -> (kind, policy maker)
HAND_WRITTEN: dict[str, tuple[Kind, PolicyMaker]] = {
    "vfh": ("baseline", reactive_policy),
    "bug": ("baseline", bug_policy),
    "oracle": ("oracle", oracle_policy),
}


def hand_written(name: str, reference: RobotProfile) -> Contender:
    """The baseline or oracle ``name`` acting with the reference planner's limits."""
    kind, maker = HAND_WRITTEN[name]
    return Contender(name, kind, reference, maker)


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
