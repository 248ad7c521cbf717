"""The planner: an evolved genome deciding for one robot, and when to decide.

:class:`GenomePlanner` is the decision chain of the batched episodes
(:class:`mentor_core.controller.pipeline.DecisionChain`) for a single robot, through the stages
of its deployment (:func:`deployed_genome`), and its Twist
(:func:`mentor_core.sim.observation.twist_from_action`). The planner node calls nothing else.

The planner node's bookkeeping of when to decide is
:class:`~mentor_core.runtime.decision_gate.DecisionGate`.

A planner with a context (a memory of its previous outputs, ``RobotProfile.n_context``) or
a recurrent network (recurrent connection genes: its previous node values) decides from what
it decided before: :meth:`GenomePlanner.reset` starts it blank.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from mentor_core.controller.deployment import Deployed, Deployment, deploy, trained_stages
from mentor_core.controller.pipeline import DecisionChain
from mentor_core.controller.stage import Stage
from mentor_core.errors import ConfigError, short_repr
from mentor_core.evolution.genome import Genome
from mentor_core.evolution.network import FeedForwardNetwork
from mentor_core.files.genome_file import load_genome_and_metadata
from mentor_core.runtime.footprint import Box, with_footprint
from mentor_core.sim import observation
from mentor_core.sim.planner_settings import with_planner
from mentor_core.sim.robots import (
    ROBOTS_ENV,
    RobotProfile,
    get_profile,
    load_profiles,
    sensor_record,
)

FloatArray = NDArray[np.float64]
_ONE = np.zeros(1, dtype=np.int64)  # the one robot of a planner's decision chain


def planner_profile(
    profile: RobotProfile, metadata: Mapping[str, Any], source: str | Path = ""
) -> RobotProfile:
    """``profile`` as the genome was trained to use it: its metadata's ``input_encoding``
    (``"paper"`` for a genome saved before the key existed), ``heading_change_max`` (rad),
    ``step_max`` and ``step_min`` (m; each the profile's when absent),
    ``clearance_margin`` (m; absent: none), ``feedback_action``, ``memory_units`` and
    ``proximity_scale`` (m) (absent: off, as every genome saved before they existed) and
    ``control_period`` (s; absent: the robot's). The stages it was trained with are
    :func:`~mentor_core.controller.deployment.trained_stages`'.

    ConfigError naming ``source`` for a bad value, and for metadata whose ``sensors`` record
    (:func:`mentor_core.sim.robots.sensor_record`; absent in genomes saved before it existed)
    differs from the profile's: such a genome was trained with other sensors.
    """
    trained_for = metadata.get("robot", profile.name)  # absent in hand-made genomes
    if trained_for != profile.name:
        known = sorted(load_profiles())
        fault = (
            f"the genome was trained for robot {trained_for!r}, not {profile.name!r}"
            if trained_for in known
            else f"{short_repr(trained_for)} is no known robot (known: {', '.join(known)})"
        )
        raise ConfigError(fault, key="robot", path=source or None)
    trained = metadata.get("sensors")
    if trained is not None and trained != sensor_record(profile):
        raise ConfigError(
            f"the genome was trained with other sensors than robot {profile.name!r} has now "
            f"(mounts, range or beam); use the robot file it was trained with (${ROBOTS_ENV} "
            "names the file in use)",
            key="sensors",
            path=source or None,
        )
    return with_planner(
        profile,
        input_encoding=metadata.get("input_encoding", "paper"),
        heading_change_max=metadata.get("heading_change_max"),
        step_max=metadata.get("step_max"),
        step_min=metadata.get("step_min"),
        clearance_margin=metadata.get("clearance_margin"),
        feedback_action=metadata.get("feedback_action"),
        memory_units=metadata.get("memory_units"),
        control_period=metadata.get("control_period"),
        proximity_scale=metadata.get("proximity_scale"),
        source=source,
    )


def genome_profile(genome_path: str | Path, profile_name: str) -> RobotProfile:
    """The profile of robot ``profile_name`` as the genome in ``genome_path`` was trained to
    use it (:func:`planner_profile` of its metadata). The same errors as
    :meth:`GenomePlanner.load`."""
    _, metadata = load_genome_and_metadata(genome_path)
    return planner_profile(get_profile(profile_name), metadata, genome_path)


def genome_control_period(genome_path: str | Path, profile_name: str) -> float:
    """The control period (s) the genome in ``genome_path`` decides at on robot
    ``profile_name``: its metadata's ``control_period``, the robot's where absent. The same
    errors as :meth:`GenomePlanner.load`."""
    return genome_profile(genome_path, profile_name).control_period


def deployed_genome(
    genome_path: str | Path, profile_name: str, deployment: Deployment | None = None,
    footprint: Box | None = None,
) -> tuple[Genome, Deployed]:  # fmt: skip
    """The genome in ``genome_path`` and how it runs on robot ``profile_name`` as
    ``deployment`` (None: as trained, with the stages its metadata names), its body the box
    ``footprint`` (:func:`~mentor_core.runtime.footprint.footprint_box`; None: the
    profile's). FileFormatError
    (corrupt or missing genome), ConfigError (unknown profile, a genome for another robot, a
    bad setting), each one line naming the file or key."""
    genome, metadata = load_genome_and_metadata(genome_path)
    profile = planner_profile(get_profile(profile_name), metadata, genome_path)
    profile = with_footprint(profile, footprint)
    trained = trained_stages(metadata, genome_path)
    return genome, deploy(profile, trained, deployment or Deployment(), genome_path)


class GenomePlanner:
    """One robot's decisions from an evolved genome, exactly as in training and in the
    benchmark: the decision chain of one robot
    (:class:`~mentor_core.controller.pipeline.DecisionChain`) through ``stages``.

    A planner with a context (``profile.n_context``), a recurrent network or a stage that
    remembers (a rotation shim: whether it has turned onto its goal yet; a collision guard:
    the last decisions' readings) is stateful, as in an episode of training, until
    :meth:`reset`. A collision guard counts only what was read as an obstacle unless
    ``arena`` (m) names the side of the simulated arena the robot drives in, whose border it
    then counts as known, as the batched episodes do.

    Raises ConfigError when the genome's inputs/outputs do not fit the profile.
    """

    def __init__(
        self, genome: Genome, profile: RobotProfile, source: str = "<genome>",
        arena: float | None = None, stages: tuple[Stage, ...] = (),
    ) -> None:  # fmt: skip
        fault = profile.network_mismatch(genome.n_inputs, genome.n_outputs)
        if fault:
            raise ConfigError(fault, path=source)
        self.genome = genome
        self.profile = profile
        self.network = FeedForwardNetwork.from_genome(genome)
        self.chain = DecisionChain(profile, stages, 1, arena)
        self._memory = self.network.new_memory(1)

    @property
    def stages(self) -> tuple[Stage, ...]:
        """The stages its decisions pass, in order."""
        return self.chain.stages

    def reset(self) -> None:
        """Start blank: the next decision reads the context of a first decision (a new goal or
        episode; :func:`mentor_core.sim.observation.initial_context`) and a zero memory, and
        every stage forgets (a rotation shim turns onto the goal again, a collision guard
        forgets what it read)."""
        self.chain.reset()
        self._memory = self.network.new_memory(1)

    @classmethod
    def load(
        cls, genome_path: str | Path, profile_name: str, deployment: Deployment | None = None,
        arena: float | None = None,
    ) -> GenomePlanner:  # fmt: skip
        """Planner of a genome JSON file for a named profile, run as ``deployment`` (None:
        as trained; :func:`deployed_genome`; its plan is the caller's to follow). The errors
        of :func:`deployed_genome`, and ConfigError for a genome that does not fit the
        profile."""
        genome, deployed = deployed_genome(genome_path, profile_name, deployment)
        return cls(genome, deployed.profile, str(genome_path), arena, deployed.stages)

    def decide(
        self, ranges: ArrayLike, pose: ArrayLike, goal: ArrayLike
    ) -> tuple[float, float]:
        """Decision ``(dtheta, ds)`` (rad, m) for readings (k,) (m, +inf out of range), pose
        (x, y, theta) and goal (x, y) in ``map``. ValueError for NaN or malformed input (the
        planner is then left as it was). Behind a collision guard ``ds`` may be negative (a
        step back)."""
        memory = self._memory.copy()  # kept as it was if the decision fails

        def policy(inputs: FloatArray, robots: NDArray[np.int64]) -> FloatArray:
            return self.network.activate(inputs, memory)

        decision = self.chain.decide(
            _ONE,
            np.asarray(ranges, dtype=np.float64).reshape(1, -1),
            np.asarray(pose, dtype=np.float64).reshape(1, 3),
            np.asarray(goal, dtype=np.float64).reshape(1, 2),
            policy,
        )
        self._memory = memory
        return float(decision.dtheta[0]), float(decision.ds[0])

    def command(
        self, ranges: ArrayLike, pose: ArrayLike, goal: ArrayLike, dt: float | None = None
    ) -> tuple[float, float]:
        """Twist of the decision, ``(linear_x, angular_z) = (ds / dt, dtheta / dt)`` (m/s,
        rad/s); ``dt`` defaults to the profile's control period."""
        dtheta, ds = self.decide(ranges, pose, goal)
        period = self.profile.control_period if dt is None else dt
        angular_z, linear_x = observation.twist_from_action(dtheta, ds, period)
        return float(linear_x), float(angular_z)
