"""The trainer's configuration (paper section III-D): :class:`TrainerConfig`, its YAML files.

A config file is a mapping of :class:`TrainerConfig` fields; its ``evolution`` mapping changes
the robot's paper evolution parameters key by key, its ``doe`` mapping the paper's training-world
layout. A run directory's ``config.yaml`` is such a file plus the run's ``seed``
(:func:`load_config_file`). Every fault is a ConfigError or FileFormatError naming the file.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any, Literal

import yaml

from mentor_core.errors import ConfigError, FileFormatError, is_number, one_line
from mentor_core.evolution.config import EvolutionConfig
from mentor_core.evolution.loop import Mode
from mentor_core.sim.families import FAMILIES
from mentor_core.sim.robots import INPUT_ENCODINGS
from mentor_core.sim.scenarios import DoEConfig

Framework = Literal["single", "dual"]


@dataclass(frozen=True)
class TrainerConfig:
    """Everything a training run needs besides its seed and output directory.

    Attributes:
        robot: robot profile name ("ugv" or "swarm").
        framework: "single" (F only) or "dual" (F and G, then F only).
        generations: total generations, both stages together.
        stage1_generations: multi-objective generations of the dual-stage framework.
        stage2_seed_fraction: share of stage 1's final population (best by F) seeding stage 2.
        n_scenarios: training scenarios (default: the profile's ``train_scenarios``).
        scenario_seed: seed of the training worlds and their start/goal pairs.
        training_worlds: composite worlds the scenarios are spread over (the paper: 1);
            see ``mentor_core.sim.scenarios.training_scenarios``.
        doe: the training worlds' layout (``mentor_core.sim.scenarios.DoEConfig``; the paper's
            by default); in a config file a mapping of the fields to change.
        families: structured training worlds besides the DoE's (a curriculum): one world of
            each named family (``mentor_core.sim.families``) with ``family_pairs`` pairs at
            the unseen test's distances (``mentor_core.training.curriculum``); none by default,
            as in the paper.
        family_pairs: start/goal pairs in each family's training world.
        input_encoding: the network's goal inputs, ``"egocentric"`` (default) or ``"paper"``
            (``mentor_core.sim.observation``); written into the best genome's metadata so that
            the planner node and mentor-eval feed the network the same way.
        heading_change_max_deg: limit of the heading-change action, degrees in (0, 180]
            (None: the robot profile's, 180 as in the paper); also written into the metadata.
        step_max: the planner's largest step per decision, m, between the robot's step_min
            and step_max (None: the robot's, as in the paper); the time budgets follow it
            (``mentor_core.sim.robots.with_planner``); also written into the metadata.
        step_min: the planner's smallest step, m, in [0, step_max] (None: the robot's, 0.1 m
            as in the paper); also written into the metadata.
        clearance_margin: when set, every step is shortened to the free range read ahead less
            this margin, m (``mentor_core.sim.observation.clearance_limit``; None: no such limit,
            as in the paper); also written into the metadata.
        evolution: the MENTOR evolution parameters (population, rates, speciation).
    """

    robot: str = "swarm"
    framework: Framework = "dual"
    generations: int = 50
    stage1_generations: int = 25
    stage2_seed_fraction: float = 0.5
    n_scenarios: int | None = None
    scenario_seed: int = 0
    training_worlds: int = 1
    doe: DoEConfig = field(default_factory=DoEConfig)
    families: tuple[str, ...] = ()
    family_pairs: int = 5
    input_encoding: str = "egocentric"
    heading_change_max_deg: float | None = None
    step_max: float | None = None
    step_min: float | None = None
    clearance_margin: float | None = None
    evolution: EvolutionConfig = field(default_factory=EvolutionConfig)

    def __post_init__(self) -> None:
        if self.robot not in ("ugv", "swarm"):
            raise ConfigError("must be 'ugv' or 'swarm'", key="robot")
        if self.framework not in ("single", "dual"):
            raise ConfigError("must be 'single' or 'dual'", key="framework")
        if self.generations < 1:
            raise ConfigError("must be at least 1", key="generations")
        if self.framework == "dual" and not 1 <= self.stage1_generations < self.generations:
            raise ConfigError("must be in [1, generations)", key="stage1_generations")
        if not 0.0 < self.stage2_seed_fraction <= 1.0:
            raise ConfigError("must be in (0, 1]", key="stage2_seed_fraction")
        if self.n_scenarios is not None and self.n_scenarios < 1:
            raise ConfigError("must be at least 1", key="n_scenarios")
        # the bound by the robot's own scenario count is checked by make_problem
        if (
            isinstance(self.training_worlds, bool)
            or not isinstance(self.training_worlds, int)
            or self.training_worlds < 1
            or (self.n_scenarios is not None and self.training_worlds > self.n_scenarios)
        ):
            raise ConfigError("must be in [1, n_scenarios]", key="training_worlds")
        if not all(isinstance(f, str) and f in FAMILIES for f in self.families) or len(
            set(self.families)
        ) != len(self.families):
            raise ConfigError(
                f"must be distinct world families of {', '.join(FAMILIES)}", key="families"
            )
        if (
            isinstance(self.family_pairs, bool)
            or not isinstance(self.family_pairs, int)
            or self.family_pairs < 1
        ):
            raise ConfigError("must be a whole number >= 1", key="family_pairs")
        _check_optional(
            self.heading_change_max_deg, lambda v: 0.0 < v <= 180.0, "in (0, 180] degrees",
            "heading_change_max_deg",
        )  # fmt: skip
        # their bounds by the robot's own steps are checked by make_problem (with_planner)
        _check_optional(self.step_max, lambda v: v > 0.0, "a positive number of m", "step_max")
        _check_optional(self.step_min, lambda v: v >= 0.0, "a number >= 0 m", "step_min")
        _check_optional(
            self.clearance_margin, lambda v: 0.0 <= v < math.inf, "a number >= 0 m",
            "clearance_margin",
        )  # fmt: skip
        if self.input_encoding not in INPUT_ENCODINGS:
            raise ConfigError(
                f"must be one of {', '.join(INPUT_ENCODINGS)}", key="input_encoding"
            )

    def stages(self) -> list[tuple[Mode, int]]:
        """(mode, generations) per stage: "multi" ranks (F, G), "single" ranks F."""
        if self.framework == "single":
            return [("single", self.generations)]
        return [
            ("multi", self.stage1_generations),
            ("single", self.generations - self.stage1_generations),
        ]

    def to_dict(self) -> dict[str, Any]:
        """A plain dict that :meth:`from_dict` turns back into an equal config."""
        d = asdict(self)
        d["evolution"] = self.evolution.to_dict()
        d["doe"] = self.doe.to_dict()
        d["families"] = list(self.families)
        return d

    @classmethod
    def from_dict(cls, data: dict[str, Any], source: str = "<dict>") -> TrainerConfig:
        """Build from a dict (e.g. YAML); unknown keys and bad values raise ConfigError."""
        if not isinstance(data, dict):
            raise ConfigError("must be a mapping", path=source)
        known = {f for f in cls.__dataclass_fields__}
        for key in data:
            if key not in known:
                raise ConfigError("unknown key", key=key, path=source)
        kwargs = dict(data)
        robot = str(kwargs.get("robot", cls.robot))
        evo = kwargs.pop("evolution", None)
        base = EvolutionConfig.paper("ugv" if robot == "ugv" else "swarm")
        if evo is not None:
            merged = base.to_dict()
            _deep_update(merged, evo)
            kwargs["evolution"] = EvolutionConfig.from_dict(merged, source)
        else:
            kwargs["evolution"] = base
        if "doe" in kwargs:
            kwargs["doe"] = DoEConfig.from_dict(kwargs["doe"] or {}, source)
        if "families" in kwargs:
            names = kwargs["families"]
            if not isinstance(names, list):
                raise ConfigError("must be a list of world families", key="families", path=source)
            kwargs["families"] = tuple(names)
        try:
            return cls(**kwargs)
        except ConfigError as err:
            raise ConfigError(str(err).split(": ", 1)[-1], key=err.key, path=source) from None
        except TypeError as err:
            raise ConfigError(str(err), path=source) from None

    @classmethod
    def from_yaml(cls, path: str | Path) -> TrainerConfig:
        """Load a YAML config file (FileFormatError if missing or not YAML)."""
        return cls.from_dict(_read_yaml(Path(path)), str(path))


def load_config_file(path: str | Path) -> tuple[TrainerConfig, int | None]:
    """A config file, or a run directory's ``config.yaml`` (the resolved config plus the run's
    ``seed``): the config and that seed (None when the file has none). FileFormatError or
    ConfigError naming the file as :meth:`TrainerConfig.from_yaml`."""
    data = _read_yaml(Path(path))
    seed = data.pop("seed", None) if isinstance(data, dict) else None
    if seed is not None and not (isinstance(seed, int) and not isinstance(seed, bool)):
        raise ConfigError("must be a whole number", key="seed", path=str(path))
    return TrainerConfig.from_dict(data, str(path)), seed


def _read_yaml(path: Path) -> Any:
    try:
        data = yaml.safe_load(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise FileFormatError(path, "no such file") from None
    except yaml.YAMLError as err:
        raise FileFormatError(path, f"not valid YAML ({one_line(err)})") from None
    return {} if data is None else data


def _deep_update(base: dict[str, Any], extra: dict[str, Any]) -> None:
    for key, value in extra.items():
        if isinstance(value, dict) and isinstance(base.get(key), dict):
            _deep_update(base[key], value)
        else:
            base[key] = value


def _check_optional(value: object, ok: Callable[[float], bool], allowed: str, key: str) -> None:
    """ConfigError for ``key`` unless ``value`` is None or a number (not a bool) ``ok`` takes."""
    if value is None:
        return
    if not is_number(value) or not ok(float(value)):
        raise ConfigError(f"must be null or {allowed}", key=key)


__all__ = ["Framework", "TrainerConfig", "load_config_file"]
