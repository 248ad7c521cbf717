"""The robots of a simulated session and the planner each runs: what the ``demo`` executable
and ``mentor.launch.py`` both start.

One robot per profile entry, named ``<profile>_<i>`` (``ugv ugv swarm``: ``ugv_0``, ``ugv_1``,
``swarm_0``), each planning with its profile's genome (``bags/regression/<profile>_reference_
genome.json`` unless one is given), run as a deployment (the planner node's ``deployment``:
``none``, ``shipped`` or a file; :mod:`mentor_core.controller.deployment`), as
``mentor-bench --deployment`` runs it.

The simulator steps at the period the planners decide at (their genomes' metadata and their
deployment's ``decisions_per_period``). In lockstep every planner must decide at the same
period; in continuous mode (the simulator runs like Gazebo and each planner decides on its own
timer) they may differ, and the simulator steps at the shortest.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from mentor_core.controller.deployment import load_deployment
from mentor_core.errors import FileFormatError, MentorError
from mentor_core.runtime.planner import deployed_genome
from mentor_core.sim.robots import get_profile


def default_genome(profile: str) -> str:
    """The genome a robot of ``profile`` plans with unless told: the regression reference."""
    return f"bags/regression/{profile}_reference_genome.json"


def robot_names(profiles: Sequence[str]) -> list[str]:
    """One namespace per entry of ``profiles``: ``<profile>_<i>``, ``i`` counting that
    profile's robots from 0."""
    return [f"{p}_{profiles[:i].count(p)}" for i, p in enumerate(profiles)]


def parse_genomes(items: Iterable[str]) -> dict[str, str]:
    """``PROFILE=FILE`` items as ``{profile: file}``; MentorError naming an item without
    ``=``, a profile or a file."""
    genomes: dict[str, str] = {}
    for item in items:
        profile, _, path = (part.strip() for part in item.partition("="))
        if not (profile and path):
            raise MentorError(f"genome {item!r}: expected PROFILE=FILE")
        genomes[profile] = path
    return genomes


@dataclass(frozen=True)
class RobotPlanner:
    """One robot of the session and the planner node's parameters for it.

    Attributes:
        namespace: the robot's namespace, without the leading slash.
        profile: the robot profile's name.
        genome: the genome file the planner loads.
        options: the planner node's other parameters (the deployment, the timer).
    """

    namespace: str
    profile: str
    genome: str
    options: Mapping[str, Any] = field(default_factory=dict)

    @property
    def parameters(self) -> dict[str, Any]:
        """The planner node's parameters: ``genome``, ``profile`` and the options."""
        return {"genome": self.genome, "profile": self.profile, **self.options}


def robot_planners(
    profiles: Sequence[str],
    genomes: Mapping[str, str] | None = None,
    *,
    names: Sequence[str] | None = None,
    deployment: str = "none",
    continuous: bool = False,
) -> list[RobotPlanner]:
    """The robots of ``profiles`` (one each) and their planners' parameters (module
    docstring).

    Args:
        profiles: one profile name per robot.
        genomes: genome file per profile; a profile not in it plans with
            :func:`default_genome`.
        names: the robots' namespaces (default :func:`robot_names`).
        deployment: how every planner runs (the planner node's ``deployment``).
        continuous: the planners decide on their own timers (``decide_on_timer``).

    Raises MentorError for no robot, an unknown profile, a count of names that does not
    match, a genome given for a profile no robot has, a genome file that does not exist, or
    a deployment that cannot be read.
    """
    given = dict(genomes or {})
    spare = sorted(set(given) - set(profiles))
    if not profiles:
        raise MentorError("no robot: give at least one profile")
    if spare:
        raise MentorError(f"a genome for {', '.join(spare)}, but no robot of that profile "
                          f"(robots: {', '.join(profiles)})")  # fmt: skip
    spaces = robot_names(profiles) if names is None else [n.strip("/") for n in names]
    if len(spaces) != len(profiles):
        raise MentorError(f"{len(spaces)} robot names for {len(profiles)} profiles")
    planners = []
    for name, profile in zip(spaces, profiles, strict=True):
        get_profile(profile)  # an unknown one: ConfigError naming the known ones
        genome = given.get(profile, default_genome(profile))
        if not Path(genome).is_file():
            raise FileFormatError(genome, f"no such genome file (give one for {profile})")
        options: dict[str, Any] = {}
        if deployment != "none":
            load_deployment(deployment, profile)  # its faults now, not in a node
            options["deployment"] = deployment
        if continuous:
            options["decide_on_timer"] = True
        planners.append(RobotPlanner(name, profile, genome, options))
    return planners


def simulator_period(
    planners: Sequence[RobotPlanner], continuous: bool, continuous_hint: str = "continuous mode"
) -> float:
    """The simulator's control period (s): the one period the planners decide at (their
    genome's as deployed), or with ``continuous`` the shortest. MentorError (naming
    ``continuous_hint``, the way to run them) when planners of different periods would share
    a lockstep simulator, and the genome files' errors
    (:func:`~mentor_core.runtime.planner.deployed_genome`)."""
    periods = [planner_period(p) for p in planners]
    if continuous:
        return min(periods)
    return one_period(periods, f"run them with {continuous_hint}")


def planner_period(planner: RobotPlanner) -> float:
    """The period (s) a planner decides at: its genome's as its deployment runs it."""
    deployment = load_deployment(planner.options.get("deployment", "none"), planner.profile)[0]
    return deployed_genome(planner.genome, planner.profile, deployment)[1].profile.control_period


def one_period(periods: Iterable[float], way_out: str) -> float:
    """The one control period (s) of some planners, for a simulator that steps them all
    together; MentorError naming the periods and ``way_out`` when they differ."""
    distinct = sorted(set(periods))
    if len(distinct) > 1:
        shown = ", ".join(f"{v:g}" for v in distinct)
        raise MentorError(f"the planners decide at different periods ({shown} s); {way_out}")
    return distinct[0]
