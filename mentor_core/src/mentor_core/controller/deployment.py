"""A deployment: how a trained planner is run, as data.

A deployment (Nav2's parameter file is the model) says three things:

* ``decisions_per_period``: decisions in the period the planner was trained to decide in
  (:mod:`~mentor_core.controller.decision_split`; Nav2's ``controller_frequency``);
* ``scan_map``: the goal the network sees is the carrot of a plan on a map of the robot's own
  readings, unknown space free (:mod:`mentor_core.navigation.scan_map`; Nav2's planner
  server), with the plan's settings; absent or null: the goal itself;
* ``stages``: the controller's layers, each under its name with its settings
  (:mod:`~mentor_core.controller.stage`). A built-in stage is named by its name
  (:data:`BUILT_IN`, whose order they run in: :func:`in_order`); any other by ``plugin:
  "module:Class"``, a :class:`Stage` subclass that is imported, as Nav2 loads a controller
  plugin, and runs where the file lists it: one module and one entry add a layer.

``shipped`` names the shipped planners' deployment of a robot (``data/deployments.yaml``),
``none`` the empty one (the network decides alone, as trained), anything else a YAML file.
``KEY=VALUE`` settings go on top (``stages.turn_gain.gain=1``, ``decisions_per_period=1``,
``stages.collision_guard=null`` to drop a stage), read as ``mentor-train --set`` reads them.
Errors are one :class:`~mentor_core.errors.ConfigError` line naming the file and the key.

A genome's metadata may name stages it was trained with (``view_margin``: a view corridor,
``rotation_shim``: a rotation shim); they run under every deployment (:func:`trained_stages`)
unless the deployment names a stage of the same name: its settings then apply, and ``null``
drops it.
"""

from __future__ import annotations

import dataclasses
import importlib
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Annotated, Any

from pydantic import Field

from mentor_core.controller.collision_guard import CollisionGuardStage
from mentor_core.controller.decision_split import at_control_period
from mentor_core.controller.rotation_shim import RotationShim
from mentor_core.controller.stage import Stage
from mentor_core.controller.turn_commitment import TurnCommitment
from mentor_core.controller.turn_gain import TurnGain
from mentor_core.controller.view_corridor import ViewCorridor
from mentor_core.errors import ConfigError, is_number, short_repr
from mentor_core.navigation.guide import GuideConfig
from mentor_core.navigation.scan_map import scan_guide_config
from mentor_core.sim.robots import RobotProfile, get_profile, load_profiles
from mentor_core.validation import (
    Float,
    Int,
    config_dataclass,
    read_yaml,
    validate,
    with_settings,
)

#: the stages a deployment names without a plugin
BUILT_IN: dict[str, type[Stage]] = {
    cls.name: cls
    for cls in (ViewCorridor, TurnGain, TurnCommitment, RotationShim, CollisionGuardStage)
}
_RANK = {cls: rank for rank, cls in enumerate(BUILT_IN.values())}
#: the deployment names that are no file
NAMED = ("shipped", "none")
#: the most decisions a deployment makes in a trained period
MAX_DECISIONS = 16


@config_dataclass
class ScanMapPlan:
    """The plan on the scan map (:func:`~mentor_core.navigation.scan_map.scan_guide_config`;
    null: its default)."""

    lookahead: Annotated[Float, Field(gt=0.0)] | None = None
    """m: the carrot's distance along the plan."""
    resolution: Annotated[Float, Field(gt=0.0)] | None = None
    """m: the map's cells."""
    clearance_cost: Annotated[Float, Field(ge=0.0)] | None = None
    """The weight of the plan's cost for keeping less than the default margin."""
    least_margin: Annotated[Float, Field(ge=0.0)] | None = None
    """m: the least margin the plan keeps with a clearance cost."""
    plan_delay: Annotated[int, Field(ge=0)] = 0
    """Decisions between asking for a plan and following it: a planner's delay simulated (0:
    at once, as the planner node in lockstep; :mod:`mentor_core.navigation.plan_worker`)."""
    whole_scan: bool = False
    """The map marks every ray of a lidar's scan, where the readings come off one (the
    planner node's lidar, IR-SIM's), not only the sensors' readings."""

    def guide(self, profile: RobotProfile, source: str | Path | None = None) -> GuideConfig:
        """The guide's settings for a planner of ``profile``; ConfigError naming ``source``
        and ``scan_map.least_margin`` for a least margin beyond the plan's whole margin."""
        whole = scan_guide_config(profile).margin
        if self.least_margin is not None and self.least_margin > whole:
            raise ConfigError(f"must be at most the plan's whole margin, {whole:g} m (a "
                              f"footprint radius of {profile.name}), got {self.least_margin}",
                              key="scan_map.least_margin", path=source)  # fmt: skip
        config = scan_guide_config(profile, self.lookahead, self.resolution,
                                   self.least_margin, self.clearance_cost)  # fmt: skip
        return dataclasses.replace(config, plan_delay=self.plan_delay,
                                   whole_scan=self.whole_scan)  # fmt: skip


@config_dataclass
class Deployment:
    """A deployment (module docstring), validated."""

    decisions_per_period: Annotated[Int, Field(ge=1, le=MAX_DECISIONS)] = 1
    """Decisions in the period the planner was trained to decide in, each that share of its
    step and turn."""
    scan_map: ScanMapPlan | None = None
    """The plan on the map of the robot's own readings the network steers along (null:
    straight to the goal)."""
    stages: dict[str, dict[str, Any] | None] = field(default_factory=dict)
    """The controller's stages in order: name -> settings (plugin: "module:Class" for one
    that is not built in); null: none."""

    def build(self, source: str | Path | None = None) -> tuple[Stage, ...]:
        """The stages, each validated, in order (:func:`in_order`); ConfigError naming
        ``source`` and the key."""
        return in_order([_stage(name, settings or {}, source) for name, settings in
                         self.stages.items() if settings is not None])  # fmt: skip


def in_order(stages: Sequence[Stage]) -> tuple[Stage, ...]:
    """``stages`` with the built-in ones in the order of :data:`BUILT_IN` (a gain on the turn
    before a rotation shim, which then keeps its full turn, whatever order a file or ``--set``
    gave them), each plugin where it was listed among them."""
    slots = [i for i, s in enumerate(stages) if type(s) in _RANK]
    ranked = sorted((stages[i] for i in slots), key=lambda s: _RANK[type(s)])
    out = list(stages)
    for i, stage in zip(slots, ranked, strict=True):
        out[i] = stage
    return tuple(out)


def _stage(name: str, settings: Mapping[str, Any], source: str | Path | None) -> Stage:
    """The stage ``name`` with ``settings`` (module docstring)."""
    values = dict(settings)
    plugin = values.pop("plugin", None)
    key = f"stages.{name}"
    if plugin is None:
        if name not in BUILT_IN:
            raise ConfigError(f"no such stage (built in: {', '.join(BUILT_IN)}; another needs "
                              "plugin: \"module:Class\")", key=key, path=source)  # fmt: skip
        cls = BUILT_IN[name]
    else:
        cls = _plugin(plugin, f"{key}.plugin", source)
    return validate(cls, values, source, prefix=key)


def _plugin(ref: object, key: str, source: str | Path | None) -> type[Stage]:
    """The Stage subclass ``module:Class`` names; ConfigError naming ``key`` otherwise."""
    module, colon, name = str(ref).partition(":")
    if not (isinstance(ref, str) and colon and module and name):
        raise ConfigError(f"expected \"module:Class\", got {short_repr(ref)}", key, source)
    try:
        found = getattr(importlib.import_module(module), name)
    except Exception as err:  # a plugin's module may fail in any way: one line, not a trace
        raise ConfigError(f"cannot load {ref!r}: {type(err).__name__}: {err}", key,
                          source) from None  # fmt: skip
    if not (isinstance(found, type) and issubclass(found, Stage)):
        raise ConfigError(f"{ref!r} is not a Stage (mentor_core.controller.Stage)", key, source)
    if not hasattr(found, "__pydantic_validator__"):
        raise ConfigError(f"{ref!r} is not a config dataclass (decorate it with "
                          "mentor_core.config_dataclass)", key, source)  # fmt: skip
    return found


def load_deployment(
    ref: str | Path, robot: str, settings: Sequence[str] = (), settings_from: str = "--set"
) -> tuple[Deployment, str]:
    """The deployment ``ref`` names for a robot named ``robot`` (module docstring), with the
    ``KEY=VALUE`` ``settings`` on top (given by ``settings_from``: ``--set``, or the planner
    node's ``deployment_set``), and the source its errors name; its stages are built once to
    check them. ConfigError (or FileFormatError for a file that cannot be read) in one line
    naming the file and the key."""
    text = str(ref)
    if text == "none":
        data: Any = {}
        source = "deployment none"
    elif text == "shipped":
        data = shipped_deployments().get(robot)
        source = f"the shipped deployment of {robot}"
        if data is None:
            raise ConfigError(f"no shipped deployment for robot {robot!r} (shipped: "
                              f"{', '.join(shipped_deployments())})", key="shipped")
    else:
        data = read_yaml(text)
        source = text
        if not isinstance(data, dict):
            raise ConfigError(f"expected a mapping of deployment keys, got {short_repr(data)}",
                              path=text)  # fmt: skip
    if settings:
        data = with_settings(data, settings, settings_from)
        source = f"{source} with {settings_from}"
    deployment = validate(Deployment, data, source)
    deployment.build(source)
    if deployment.scan_map is not None and robot in load_profiles():
        deployment.scan_map.guide(get_profile(robot), source)
    return deployment, source


def shipped_deployments() -> dict[str, Any]:
    """The shipped deployments' file, robot name -> deployment mapping."""
    with resources.as_file(resources.files("mentor_core") / "data" / "deployments.yaml") as p:
        data = read_yaml(p)
    return dict(data)


def trained_stages(metadata: Mapping[str, Any], source: str | Path = "") -> tuple[Stage, ...]:
    """The stages a genome was trained with, from its metadata (module docstring):
    ``view_margin`` (m) and ``rotation_shim`` (rad). ConfigError naming ``source`` and the key
    for a bad value."""
    stages: list[Stage] = []
    for key, make in (("view_margin", lambda v: ViewCorridor(margin=v)),
                      ("rotation_shim", lambda v: RotationShim(threshold_deg=math.degrees(v)))):
        value = metadata.get(key)
        if value is None:
            continue
        if key == "rotation_shim" and not (is_number(value) and 0.0 < value <= math.pi):
            raise ConfigError(f"must be a number in (0, pi] rad, got {short_repr(value)}",
                              key=key, path=source or None)  # fmt: skip
        try:
            stages.append(make(value))
        except ConfigError as err:
            raise ConfigError(err.message, key=key, path=source or None) from None
    return tuple(stages)


@dataclass(frozen=True)
class Deployed:
    """A planner as deployed: its profile (deciding at the deployment's period), its stages
    in order and its plan's guide (None: it steers to the goal)."""

    profile: RobotProfile
    stages: tuple[Stage, ...] = ()
    guide: GuideConfig | None = None



def deploy(
    profile: RobotProfile, trained: Sequence[Stage], deployment: Deployment,
    source: str | Path = "",
) -> Deployed:  # fmt: skip
    """A planner of ``profile`` (its trained profile) trained with the stages ``trained``, run
    as ``deployment`` (module docstring). ConfigError naming ``source``."""
    split = at_control_period(
        profile, profile.control_period / deployment.decisions_per_period, source
    )
    listed = deployment.build(source)
    named = {stage.name for stage in listed} | set(deployment.stages)  # null drops one too
    stages = in_order([s for s in trained if s.name not in named] + list(listed))
    guide = None if deployment.scan_map is None else deployment.scan_map.guide(split, source)
    return Deployed(split, stages, guide)


__all__ = [
    "BUILT_IN",
    "Deployed",
    "Deployment",
    "ScanMapPlan",
    "deploy",
    "in_order",
    "load_deployment",
    "shipped_deployments",
    "trained_stages",
]
