"""The trainer's configuration (paper section III-D): :class:`TrainerConfig`, its YAML files.

A config file is a mapping of :class:`TrainerConfig` fields; its ``evolution`` mapping changes
the robot's paper evolution parameters key by key, its ``doe`` mapping the paper's training-world
layout. A run directory's ``config.yaml`` is such a file plus the run's ``seed``
(:func:`load_config_file`). Validation is pydantic's (``mentor_core.validation``): strict types
(a whole-number field takes no ``12.5``, ``"12"`` or ``true``), unknown keys refused, and every
fault one ConfigError line naming the file and the key path
(``cfg.yaml: evolution.mutation.weight_rate: must be <= 1.0, got 1.5``); an empty file is a
FileFormatError. :func:`config_schema` is the JSON schema of a config file, for editors
(``mentor-train --print-schema``).

A config file may start from another (:func:`read_config`): ``extends: swarm/paper`` (a
shipped config, ``<robot>/<name>``) or ``extends: base.yaml`` (a file, its path relative to
this one), and then list only its departures. Its keys replace the base's key by key, a
mapping (``evolution``, ``doe``) merged key by key too, a list or ``null`` replacing the
base's whole; a base's ``seed`` is not inherited. The chain may be as long as needed; a
cycle is a ConfigError.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import field
from importlib import resources
from pathlib import Path
from typing import Annotated, Any, Literal

from pydantic import Field, model_validator

from mentor_core.controller.rotation_shim import RotationShim
from mentor_core.controller.stage import Stage
from mentor_core.controller.turn_commitment import TurnCommitment
from mentor_core.controller.view_corridor import ViewCorridor
from mentor_core.errors import ConfigError, short_repr
from mentor_core.evolution.config import EvolutionConfig, Robot
from mentor_core.evolution.loop import Mode
from mentor_core.sim.families import family_names_fault
from mentor_core.sim.robots import MAX_MEMORY_UNITS, InputEncoding
from mentor_core.sim.scenarios import DoEConfig
from mentor_core.training.problem import GoalDistanceKind, Guide, SuccessCredit, TurnFrame
from mentor_core.training.refinement import RefinementConfig
from mentor_core.validation import (
    Bool,
    Float,
    Int,
    Str,
    config_dataclass,
    fault,
    json_schema,
    merge_mappings,
    read_yaml_extending,
    to_plain,
    validate,
    with_settings,
)

Framework = Literal["single", "dual"]
PairDistances = Literal["paper", "test"]
#: a seed of numpy's generators: a whole number >= 0
Seed = Annotated[Int, Field(ge=0)]


@config_dataclass
class TrainerConfig:
    """Everything a training run needs besides its seed and output directory.

    Each field's description (the text below it) is also the JSON schema's
    (:func:`config_schema`).
    """

    robot: Robot = "swarm"
    """Robot profile name: "ugv" or "swarm"."""
    framework: Framework = "dual"
    """Either "single" (F only) or "dual" (F and G, then F only)."""
    generations: Annotated[Int, Field(ge=1)] = 50
    """Total generations, both stages together."""
    stage1_generations: Annotated[Int, Field(ge=1)] = 25
    """Multi-objective generations of the dual-stage framework, below generations."""
    stage2_seed_fraction: Annotated[Float, Field(gt=0.0, le=1.0)] = 0.5
    """Share of stage 1's final population (best by F) seeding stage 2."""
    n_scenarios: Annotated[Int, Field(ge=1)] | None = None
    """Training scenarios (null: the profile's train_scenarios)."""
    scenario_seed: Seed = 0
    """Seed of the training worlds and their start/goal pairs."""
    training_worlds: Annotated[Int, Field(ge=1)] = 1
    """Composite worlds the scenarios are spread over (the paper: 1), at most n_scenarios;
    see mentor_core.sim.scenarios.training_scenarios."""
    doe: DoEConfig = field(default_factory=DoEConfig)
    """The training worlds' layout (mentor_core.sim.scenarios.DoEConfig; the paper's by
    default); in a config file a mapping of the fields to change."""
    families: tuple[Str, ...] = ()
    """Structured training worlds besides the DoE's (a curriculum): one world of each named
    family (mentor_core.sim.families) with family_pairs pairs at the unseen test's distances
    (mentor_core.training.curriculum); none by default, as in the paper."""
    family_pairs: Annotated[Int, Field(ge=1)] = 5
    """Start/goal pairs in each family's training world."""
    pair_distances: PairDistances = "paper"
    """Straight start-goal distances of the DoE training pairs: "paper" (from two goal radii
    to the planner's uncapped distance, where the time-budget cap does not cut a straight run
    at its rated speed; 2-6.25 m for a UGV stepping 0.5 m) or "test" (the unseen test's,
    mentor_core.navigation.pairs.distance_range at the test arena, at most what the planner
    can drive within the cap; 3-17 m for the UGV); see docs/algorithm.md "Training worlds"."""
    time_budget: Annotated[Float, Field(gt=0.0)] | None = None
    """Time budget of every training scenario, s (null: the paper's T_tot = min(cap, slack d /
    rated speed), per scenario; the benchmark and the unseen test give every pair 50 s)."""
    goal_distance: GoalDistanceKind = "euclidean"
    """S_f in the performance F of a failed scenario (paper eq. 4): "euclidean", the straight
    distance to the goal (the paper's), or "geodesic", the shortest way round the obstacles
    (mentor_core.training.problem.NavigationProblem); see docs/algorithm.md
    "The final distance `S_f` of a failure in F"."""
    success_credit: SuccessCredit = "time"
    """What a success adds to its 1 in the performance F (paper eq. 4): "time", the share of
    the time budget left (the paper's), or "path", the shortest path's length over the length
    driven (the per-pair term of the benchmark's SPL; not in the paper); see docs/algorithm.md
    "The credit of a success in F"."""
    guide: Guide = "none"
    """The goal the network sees in training: "none", the scenario's goal (the paper's), or
    "waypoint", the direction of the shortest way at the distance still to go, as a global
    plan's carrot shows it (mentor_core.navigation.waypoints; not in the paper): planners
    trained to follow a plan, for a robot with a map (a deployment's scan_map, the planner
    node's global_plan). Training only; see docs/algorithm.md "The goal a network sees in
    training"."""
    guide_share: Annotated[Float, Field(gt=0.0, le=1.0)] = 1.0
    """The share of the training scenarios whose networks are shown the way under guide:
    waypoint (evenly spread over them); the others see their goal."""
    turn_commitment: bool = False
    """Keep turning to one side while the way ahead is blocked (the stage turn_commitment,
    mentor_core.controller.turn_commitment; not in the paper): experiment E024, applied in
    training only."""
    turn_frame: TurnFrame = "body"
    """What the turn output names: a heading change in the body frame ("body", the paper's) or
    a heading relative to the goal's bearing ("goal", mentor_core.sim.goal_frame; not in the
    paper): experiment E024, applied in training only."""
    input_encoding: InputEncoding = "egocentric"
    """The network's goal inputs, "egocentric" or "paper" (mentor_core.sim.observation);
    written into the best genome's metadata so that the planner node and mentor-eval feed the
    network the same way."""
    heading_change_max_deg: Annotated[Float, Field(gt=0.0, le=180.0)] | None = None
    """Limit of the heading-change action, degrees in (0, 180] (null: the robot profile's,
    180 as in the paper); also written into the metadata."""
    step_max: Annotated[Float, Field(gt=0.0)] | None = None
    """The planner's largest step per decision, m, between the robot's step_min and step_max
    (null: the robot's, as in the paper); the time budgets follow it
    (mentor_core.sim.planner_settings.with_planner); also written into the metadata."""
    step_min: Annotated[Float, Field(ge=0.0)] | None = None
    """The planner's smallest step, m, in [0, step_max] (null: the robot's, 0.1 m as in the
    paper); also written into the metadata."""
    proximity_scale: Annotated[Float, Field(gt=0.0)] | None = None
    """When set, the network reads each range r as the proximity exp(-r / proximity_scale), m
    (mentor_core.sim.observation.range_inputs; null: r in m, as in the paper), so that what
    lies far moves its inputs little; also written into the metadata."""
    view_margin: Annotated[Float, Field(gt=0.0)] | None = None
    """When set, the network sees only what lies within this distance of the segment to the
    goal it is shown (the waypoint, in a guided scenario), m; other readings read as nothing
    seen (the stage view_corridor, mentor_core.controller.view_corridor; null: everything, as
    in the paper), as it sees on its scan map when deployed with the corridor; also written
    into the metadata."""
    clearance_margin: Annotated[Float, Field(ge=0.0)] | None = None
    """When set, every step is shortened to the free range read ahead less this margin, m
    (mentor_core.sim.observation.clearance_limit; null: no such limit, as in the paper); also
    written into the metadata."""
    feedback_action: Bool = False
    """The network also reads its previous decision's two action outputs, clipped to [0, 1]
    ((0.5, 0) at the first decision: no turn, the smallest step), as two extra inputs
    (mentor_core.sim.observation; false: as in the paper); also written into the metadata."""
    memory_units: Annotated[Int, Field(ge=0, le=MAX_MEMORY_UNITS)] = 0
    """Memory units, 0 to 8: extra network outputs (in [0, 1]) that are no action but are fed
    back as inputs at the next decision (0 at the first), a context memory NEAT can evolve to
    latch a state, such as the side of a wall it follows (0: none, as in the paper); also
    written into the metadata."""
    rotation_shim_deg: Annotated[Float, Field(gt=0.0, le=180.0)] | None = None
    """When set, a robot with a new goal first turns on the spot onto it until the goal's
    bearing is within this many degrees, then its network drives (Nav2's rotation shim;
    mentor_core.controller.rotation_shim; null: the network drives from the first decision, as in
    the paper); also written into the metadata."""
    control_period: Annotated[Float, Field(gt=0.0)] | None = None
    """When set, the planner decides every this many seconds, at most the robot's period, with
    its pace (step_max per period) and turn rate within the robot's (null: the robot's period,
    1 s as in the paper). The decisions are the same; only the time they take changes: a
    time budget holds the same number of decisions when the config sets none (its rated speed
    follows, mentor_core.sim.planner_settings.with_planner), and ``time_budget`` is in
    seconds. Also written into the metadata."""
    second_objective: Literal["experience_gain", "simplicity"] = "experience_gain"
    """What the dual stage's first stage ranks beside F: the paper's experience gain G, or
    the network's simplicity (its FLOPs complexity negated, mentor_core.objectives.complexity;
    not in the paper: the experience gain's ablation, issue 55). G is computed and recorded
    either way, with the same evaluations."""
    novelty_neighbours: Annotated[Int, Field(ge=1)] | None = None
    """When set, novelty search's sparseness over this many nearest behaviours (the final
    positions in every training scenario; mentor_core.objectives.novelty) is ranked as a third
    objective wherever (F, G) are ranked (null: no novelty, as in the paper; the shipped
    Swarm-Robot config: 15); docs/algorithm.md "Novelty search"."""
    novelty_archive_growth: Annotated[Int, Field(ge=0)] = 5
    """Behaviours of the most novel genomes added to the novelty archive each generation."""
    evolution: EvolutionConfig = field(default_factory=EvolutionConfig)
    """The MENTOR evolution parameters (population, rates, speciation); in a config file a
    mapping of the keys that differ from the robot's paper values (Table I)."""
    refinement: RefinementConfig = field(default_factory=RefinementConfig)
    """After evolution, the best genome's weights refined on fresh training scenarios, goals
    reached held and the path credit raised (mentor_core.training.refinement; not in the
    paper, off by default); in a config file a mapping of the keys to change."""

    @model_validator(mode="after")
    def _consistent(self) -> TrainerConfig:
        # the bounds by the robot's own steps and scenario count are checked by make_problem
        if self.framework == "dual" and self.stage1_generations >= self.generations:
            raise fault(
                "stage1_generations",
                f"must be below generations ({self.generations}) in the dual framework, "
                f"got {self.stage1_generations}",
            )
        why = family_names_fault(self.families)
        if why:
            raise fault("families", why)
        if self.n_scenarios is not None and self.training_worlds > self.n_scenarios:
            raise fault(
                "training_worlds",
                f"must be in [1, n_scenarios] ({self.n_scenarios}), got {self.training_worlds}",
            )
        return self

    def stages(self) -> list[tuple[Mode, int]]:
        """(mode, generations) per stage: "multi" ranks (F, G), "single" ranks F."""
        if self.framework == "single":
            return [("single", self.generations)]
        return [
            ("multi", self.stage1_generations),
            ("single", self.generations - self.stage1_generations),
        ]

    def planner_settings(self) -> dict[str, Any]:
        """The planner settings a network trained with this config acts with, as
        ``mentor_core.sim.planner_settings.with_planner``'s keyword arguments (angles in rad; None:
        the robot's own)."""
        turn = self.heading_change_max_deg
        return {
            "input_encoding": self.input_encoding,
            "heading_change_max": None if turn is None else math.radians(turn),
            "step_max": self.step_max,
            "step_min": self.step_min,
            "clearance_margin": self.clearance_margin,
            "feedback_action": self.feedback_action,
            "memory_units": self.memory_units,
            "control_period": self.control_period,
            "proximity_scale": self.proximity_scale,
        }

    def trained_stages(self) -> tuple[Stage, ...]:
        """The controller's stages a network trained with this config decides through: its
        view corridor (``view_margin``), turn commitment and rotation shim, in that order
        (none in the paper); the corridor and the shim are written into the metadata
        (:func:`mentor_core.controller.deployment.trained_stages` reads them back)."""
        stages: list[Stage] = []
        if self.view_margin is not None:
            stages.append(ViewCorridor(margin=self.view_margin))
        if self.turn_commitment:
            stages.append(TurnCommitment())
        if self.rotation_shim_deg is not None:
            stages.append(RotationShim(threshold_deg=self.rotation_shim_deg))
        return tuple(stages)

    def to_dict(self) -> dict[str, Any]:
        """A plain dict that :meth:`from_dict` turns back into an equal config."""
        plain: dict[str, Any] = to_plain(self)
        return plain

    @classmethod
    def from_dict(cls, data: object, source: str | Path = "<dict>") -> TrainerConfig:
        """Build from a mapping (e.g. YAML): its ``evolution`` mapping changes the robot's
        paper values key by key (a missing or null ``evolution`` or ``doe``: the paper's);
        unknown keys and bad values raise ConfigError naming ``source`` and the key path."""
        if isinstance(data, dict):
            data = dict(data)
            robot = data.get("robot", "swarm")
            base = EvolutionConfig.paper("ugv" if robot == "ugv" else "swarm").to_dict()
            evolution = data.get("evolution")
            if isinstance(evolution, dict):
                merge_mappings(base, evolution)
            if evolution is None or isinstance(evolution, dict):
                data["evolution"] = base
            for key in ("doe", "refinement"):
                if key in data and data[key] is None:
                    data[key] = {}
        return validate(cls, data, source)

    @classmethod
    def from_yaml(cls, path: str | Path) -> TrainerConfig:
        """Load a YAML config file, its ``extends`` resolved (:func:`read_config`;
        FileFormatError if it or a base is missing, empty or not YAML)."""
        return cls.from_dict(read_config(path), path)


@config_dataclass
class _RunSeed:
    seed: Seed | None = None


def load_config_file(
    path: str | Path, robot: str | None = None
) -> tuple[TrainerConfig, int | None]:
    """A config file, or a run directory's ``config.yaml`` (the resolved config plus the run's
    ``seed``): the config and that seed (None when the file has none). With ``robot`` (a
    command line's ``--robot``), the file's ``robot`` must be that one or absent (then it is
    that one, with its robot's evolution defaults). FileFormatError or ConfigError naming the
    file as :meth:`TrainerConfig.from_yaml`."""
    data = read_config(path)
    seed = None
    if isinstance(data, dict):
        data = dict(data)
        if "seed" in data:
            seed = validate(_RunSeed, {"seed": data.pop("seed")}, path).seed
        if robot is not None:
            if data.setdefault("robot", robot) != robot:
                given = short_repr(data["robot"])
                raise ConfigError(f"the config is for {given}, not --robot {robot}", "robot", path)
    return TrainerConfig.from_dict(data, path), seed


#: the configs shipped with mentor_core, ``configs/train_<robot>_<name>.yaml``
SHIPPED = ("quick", "paper", "original")


def shipped_config(robot: str, name: str = "paper") -> TrainerConfig:
    """The shipped config ``name`` (one of :data:`SHIPPED`) of ``robot``; ValueError for a
    name or robot without one."""
    try:
        path = _shipped_path(f"{robot}/{name}")
    except ValueError:
        raise ValueError(f"no shipped config {name!r} for robot {robot!r}") from None
    return TrainerConfig.from_yaml(path)


def read_config(path: str | Path) -> Any:
    """The YAML document of config file ``path`` with its ``extends`` chain resolved (module
    docstring; :func:`mentor_core.validation.read_yaml_extending`): a base's ``seed`` is not
    inherited. FileFormatError naming the file (this one or a base) that is missing, empty or
    not YAML; ConfigError naming the file whose ``extends`` is bad or closes a cycle."""
    return read_yaml_extending(path, _shipped_path, ("seed",))


def _shipped_path(ref: str) -> Path:
    """The shipped config file that ``extends: <robot>/<name>`` names."""
    robot, _, name = ref.partition("/")
    file = Path(str(resources.files("mentor_core") / "configs" / f"train_{robot}_{name}.yaml"))
    if name not in SHIPPED or "/" in name or not file.is_file():
        raise ValueError(
            f"no shipped config {ref!r} (<robot>/<name>: ugv or swarm, one of "
            f"{', '.join(SHIPPED)}; a file's path ends in .yaml)"
        )
    return file


#: keys a command line sets with options of their own, not with ``--set``
_OWN_OPTIONS = {"robot": "--robot", "framework": "--framework", "seed": "--seed"}


def with_overrides(data: dict[str, Any], overrides: Sequence[str]) -> dict[str, Any]:
    """A copy of ``data`` (a config's mapping) with each ``KEY=VALUE`` of ``overrides`` set
    (:func:`~mentor_core.yaml_reading.with_settings`, naming ``--set``); ``robot``,
    ``framework`` and ``seed`` are refused: a command line sets them with options of their
    own."""
    return with_settings(data, overrides, "--set", _OWN_OPTIONS)


def config_schema() -> dict[str, Any]:
    """The JSON schema (draft 2020-12) of a training config file, ``seed`` included (a run
    directory's ``config.yaml``), for editors and CI checks of config files."""
    schema = json_schema(TrainerConfig)
    schema["properties"]["extends"] = {
        "type": "string",
        "description": "Start from a shipped config (<robot>/<name>, e.g. swarm/paper) or "
        "another config file (a path relative to this one, ending in .yaml) and change only "
        "the keys given here (mappings key by key).",
    }
    schema["properties"]["seed"] = {
        "anyOf": [{"type": "integer", "minimum": 0}, {"type": "null"}],
        "default": None,
        "description": "The evolution seed (a run directory's config.yaml has it); "
        "mentor-train --seed overrides it.",
    }
    return {
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "title": "mentor-train config",
        **{k: v for k, v in schema.items() if k != "title"},
    }


__all__ = [
    "Framework",
    "TrainerConfig",
    "config_schema",
    "load_config_file",
    "read_config",
    "with_overrides",
]
