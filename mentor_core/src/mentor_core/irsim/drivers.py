"""What decides in an IR-SIM episode: a genome as the planner node deploys it, a baseline of
the benchmark, or a pure pursuit in the network's place.

Each is a :class:`Driver`: ``decide(readings, pose, goal) -> (dtheta, ds)`` once a control
period (``profile.control_period``), the readings those of its profile's sensors (m, +inf
out of range), the pose ``(x, y, theta)`` and the goal ``(x, y)`` in the world's frame. A
:class:`DriverSpec` makes a fresh one for each episode (a planner with a memory, a map or a
guard's recollection starts blank), as ``mentor-bench`` makes a fresh policy per run.

- :func:`genome_driver`: the planner node's own chain (``deployed_genome``, then
  :class:`~mentor_core.runtime.planner.GenomePlanner` through the deployment's stages, inside
  :class:`~mentor_core.runtime.guided_planner.ScanGuidedPlanner` where the deployment plans on
  the scan map, the map the arena's square from ``(0, 0)``);
- :func:`baseline_driver`: VFH+ (``vfh``) or Bug2 (``bug``) as ``mentor-bench`` builds them
  (:func:`mentor_core.benchmark.contenders.hand_written` at the shipped planners' action
  limits), ``guard-`` behind the deployment's collision guard, ``mapped-`` steering along the
  plan on its own scan map (``mapped-guard-vfh``: both, the benchmark's order);
- :func:`pursuit_driver`: the pure pursuit of the genome's plan
  (:func:`mentor_core.benchmark.contenders.pursuit_of`): the genome's profile, stages and
  plan, no network.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Literal, Protocol

import numpy as np
from numpy.typing import ArrayLike, NDArray

from mentor_core.benchmark.contenders import (
    GUARDED,
    HAND_WRITTEN,
    MAPPED,
    PolicyMaker,
    hand_written,
)
from mentor_core.benchmark.pursuit import pursuit_policy
from mentor_core.benchmark.suite import shipped_limits
from mentor_core.controller.collision_guard import CollisionGuardStage
from mentor_core.controller.deployment import Deployment
from mentor_core.controller.pipeline import DecisionChain
from mentor_core.controller.stage import Stage
from mentor_core.errors import ConfigError
from mentor_core.navigation.fading_scan_map import FadingScanGuide
from mentor_core.navigation.guide import GuideConfig
from mentor_core.runtime.guided_planner import ScanGuidedPlanner
from mentor_core.runtime.planner import GenomePlanner, deployed_genome
from mentor_core.sim.episode import Policy
from mentor_core.sim.robots import RobotProfile, get_profile
from mentor_core.sim.world import Scenario, World

FloatArray = NDArray[np.float64]
Kind = Literal["evolved", "baseline", "pursuit"]
_ONE = np.zeros(1, dtype=np.int64)
#: the baselines a driver may name (``mentor-bench --baselines``)
BASELINES = tuple(n for n, (kind, _) in HAND_WRITTEN.items() if kind == "baseline")


class Driver(Protocol):
    """One robot's decisions in an episode (module docstring)."""

    def decide(self, ranges: ArrayLike, pose: ArrayLike, goal: ArrayLike) -> tuple[float, float]:
        """``(dtheta, ds)`` (rad, m) for readings, pose and goal."""
        ...


@dataclass(frozen=True)
class DriverSpec:
    """A named maker of fresh drivers of one kind, deciding with ``profile`` (its sensors,
    limits and control period) in an arena of side ``size`` m from ``(0, 0)``."""

    name: str
    kind: Kind
    profile: RobotProfile
    make: Callable[[Scenario], Driver]

    def driver(self, scenario: Scenario) -> Driver:
        """A fresh driver for ``scenario`` (its start and goal; its world is not read)."""
        return self.make(scenario)


class PolicyPlanner:
    """A hand-written policy in a genome's place: the decision chain of
    :class:`~mentor_core.runtime.planner.GenomePlanner` (the same stages, inputs and
    actions), the policy answering instead of a network."""

    def __init__(self, policy: Policy, profile: RobotProfile, stages: tuple[Stage, ...]) -> None:
        self.profile = profile
        self.chain = DecisionChain(profile, stages, 1)
        self._policy = policy

    def decide(self, ranges: ArrayLike, pose: ArrayLike, goal: ArrayLike) -> tuple[float, float]:
        """``(dtheta, ds)`` (rad, m) as :meth:`GenomePlanner.decide`."""
        decision = self.chain.decide(
            _ONE,
            np.asarray(ranges, dtype=np.float64).reshape(1, -1),
            np.asarray(pose, dtype=np.float64).reshape(1, 3),
            np.asarray(goal, dtype=np.float64).reshape(1, 2),
            self._policy,
        )
        return float(decision.dtheta[0]), float(decision.ds[0])

    def reset(self) -> None:
        """Start blank: every stage of the chain forgets (:meth:`GenomePlanner.reset`)."""
        self.chain.reset()


def genome_driver(
    path: str | Path, robot: str, size: float, deployment: Deployment | None = None,
    name: str = "", fading: int | None = None,
) -> DriverSpec:  # fmt: skip
    """The genome in ``path`` on ``robot`` as the planner node deploys it (module
    docstring; ``deployment`` None: as trained). ``fading``: the scan map forgets what
    appeared in space seen free after that many decisions without a new hit
    (:class:`~mentor_core.navigation.fading_scan_map.FadingScanMap`, experiment E098; not
    a setting of the planner node). The errors of ``deployed_genome``."""
    genome, deployed = deployed_genome(path, robot, deployment)
    guide = deployed.guide

    def make(scenario: Scenario) -> Driver:
        planner = GenomePlanner(genome, deployed.profile, str(path), stages=deployed.stages)
        if guide is None:
            return planner
        guided = ScanGuidedPlanner(planner, guide, size)
        if fading is not None:
            guided.scan = FadingScanGuide(size, guide, (0.0, 0.0), fading)
        return guided

    make(Scenario(World(size), (size / 2, size / 2, 0.0), (size / 2, size / 2)))  # checks
    return DriverSpec(name or Path(path).stem, "evolved", deployed.profile, make)


def pursuit_driver(
    path: str | Path, robot: str, size: float, deployment: Deployment | None = None
) -> DriverSpec:
    """The pure pursuit of the genome's plan in its network's place (module docstring)."""
    _, deployed = deployed_genome(path, robot, deployment)
    return _policy_spec(f"pursuit-{Path(path).stem}", "pursuit", pursuit_policy,
                        deployed.profile, deployed.stages, deployed.guide, size)  # fmt: skip


def baseline_driver(name: str, robot: str, size: float, deployment: Deployment) -> DriverSpec:
    """The baseline ``name`` (``[mapped-][guard-](vfh|bug)``; module docstring) on
    ``robot`` at its shipped planners' action limits, its guard and plan those of
    ``deployment``. ConfigError for an unknown name, or a guard or plan the deployment
    lacks."""
    rest = name
    mapped = rest.startswith(MAPPED)
    rest = rest.removeprefix(MAPPED)
    guarded = rest.startswith(GUARDED)
    rest = rest.removeprefix(GUARDED)
    if rest not in BASELINES:
        raise ConfigError(f"unknown baseline {name!r} (known: [{MAPPED}][{GUARDED}]"
                          f"{'|'.join(BASELINES)})", key="baseline")  # fmt: skip
    limits = shipped_limits(get_profile(robot))
    stages: tuple[Stage, ...] = ()
    if guarded:
        guards = [s for s in deployment.build() if isinstance(s, CollisionGuardStage)]
        if not guards:
            raise ConfigError(f"{name}: the deployment has no collision guard", key="baseline")
        stages = (guards[0],)
    guide = None
    if mapped:
        if deployment.scan_map is None:
            raise ConfigError(f"{name}: the deployment plans on no scan map", key="baseline")
        guide = deployment.scan_map.guide(limits)
    maker = hand_written(rest, limits).make_policy
    return _policy_spec(name, "baseline", maker, limits, stages, guide, size)


def _policy_spec(
    name: str, kind: Kind, maker: PolicyMaker, profile: RobotProfile,
    stages: tuple[Stage, ...], guide: GuideConfig | None, size: float,
) -> DriverSpec:  # fmt: skip
    """A spec whose drivers are ``maker``'s policy in a :class:`PolicyPlanner` (steering on
    its scan map, as :class:`~mentor_core.runtime.guided_planner.ScanGuidedPlanner` steers a
    genome, with a ``guide``)."""

    def make(scenario: Scenario) -> Driver:
        planner = PolicyPlanner(maker([scenario], profile), profile, stages)
        return planner if guide is None else ScanGuidedPlanner(planner, guide, size)

    return DriverSpec(name, kind, profile, make)


__all__ = [
    "BASELINES",
    "Driver",
    "DriverSpec",
    "PolicyPlanner",
    "baseline_driver",
    "genome_driver",
    "pursuit_driver",
]
