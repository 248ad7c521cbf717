"""The single-stage and dual-stage MENTOR trainers (paper section III-D).

* single-stage: performance F only, for all generations;
* dual-stage: stage 1 maximises (F, G) with NSGA-II ranking for ``stage1_generations``; stage 2
  maximises F only ("direct rank based proportionate selection" = single-objective ranking),
  starting from the best ``stage2_seed_fraction`` of stage 1's final population by F.

Both frameworks see the same scenarios and the same number of evaluations (population size x
generations), so their histories share one axis. A run is a directory (see :class:`RunPaths`);
a checkpoint is written atomically after every generation and ``resume=True`` continues from it,
ending identical to an unbroken run with the same seed.
"""

from __future__ import annotations

import csv
import io
import json
import math
import time
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any, Literal

import numpy as np
import yaml

from mentor_core.atomic import write_json_atomic, write_text_atomic
from mentor_core.complexity import flops_ratio
from mentor_core.config import EvolutionConfig
from mentor_core.errors import ConfigError, FileFormatError, is_number, is_version
from mentor_core.evaluators import Evaluator, InProcessEvaluator
from mentor_core.evolution import Evolution, Mode
from mentor_core.genome import Genome
from mentor_core.genome_io import genome_from_dict, genome_to_dict, save_genome
from mentor_core.problem import OBJECTIVE_NAMES, Evaluation, NavigationProblem
from mentor_core.ranking import non_dominated_ranks
from mentor_core.robots import (
    INPUT_ENCODINGS,
    RobotProfile,
    get_profile,
    sensor_record,
    with_planner,
)
from mentor_core.scenarios import DoEConfig, training_scenarios

Framework = Literal["single", "dual"]
CHECKPOINT_FORMAT = "mentor-train-checkpoint"
CHECKPOINT_VERSION = 1
# config keys added after checkpoint version 1 came out, with the value their absence meant
_CONFIG_KEYS_ADDED: dict[str, Any] = {
    "training_worlds": 1, "step_max": None, "step_min": None, "clearance_margin": None,
    "doe": DoEConfig().to_dict(),
}
HISTORY_FIELDS = (
    "generation", "stage", "mode", "evaluations", "best_F", "mean_F", "best_G", "mean_G",
    "species", "largest_niche_share", "niche_sizes", "best_success_rate",
    "mean_complexity", "best_complexity", "seconds",
)  # fmt: skip


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
            see ``mentor_core.scenarios.training_scenarios``.
        doe: the training worlds' layout (``mentor_core.scenarios.DoEConfig``; the paper's
            by default); in a config file a mapping of the fields to change.
        input_encoding: the network's goal inputs, ``"egocentric"`` (default) or ``"paper"``
            (``mentor_core.observation``); written into the best genome's metadata so that
            the planner node and mentor-eval feed the network the same way.
        heading_change_max_deg: limit of the heading-change action, degrees in (0, 180]
            (None: the robot profile's, 180 as in the paper); also written into the metadata.
        step_max: the planner's largest step per decision, m, between the robot's step_min
            and step_max (None: the robot's, as in the paper); the time budgets follow it
            (``mentor_core.robots.with_planner``); also written into the metadata.
        step_min: the planner's smallest step, m, in [0, step_max] (None: the robot's, 0.1 m
            as in the paper); also written into the metadata.
        clearance_margin: when set, every step is shortened to the free range read ahead less
            this margin, m (``mentor_core.observation.clearance_limit``; None: no such limit,
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
        raise FileFormatError(path, f"not valid YAML ({_one_line(err)})") from None
    return {} if data is None else data


def _deep_update(base: dict[str, Any], extra: dict[str, Any]) -> None:
    for key, value in extra.items():
        if isinstance(value, dict) and isinstance(base.get(key), dict):
            _deep_update(base[key], value)
        else:
            base[key] = value


def _one_line(err: BaseException) -> str:
    return " ".join(str(err).split())


@dataclass(frozen=True)
class RunPaths:
    """The files of a run directory."""

    root: Path

    @property
    def config(self) -> Path:
        return self.root / "config.yaml"

    @property
    def checkpoint(self) -> Path:
        return self.root / "checkpoint.json"

    @property
    def history(self) -> Path:
        return self.root / "history.csv"

    @property
    def population(self) -> Path:
        return self.root / "population.json"

    @property
    def pareto(self) -> Path:
        return self.root / "pareto.json"

    @property
    def best_genome(self) -> Path:
        return self.root / "best_genome.json"


@dataclass(frozen=True)
class GenerationRecord:
    """One row of the per-generation history (what reporters receive)."""

    generation: int
    stage: int
    mode: str
    evaluations: int
    best_F: float
    mean_F: float
    best_G: float
    mean_G: float
    species: int
    largest_niche_share: float
    niche_sizes: dict[int, int]
    best_success_rate: float
    mean_complexity: float
    best_complexity: float
    seconds: float

    def row(self) -> dict[str, Any]:
        """The CSV row (niche sizes as compact JSON)."""
        d = asdict(self)
        d["niche_sizes"] = json.dumps({str(k): v for k, v in sorted(self.niche_sizes.items())})
        return d


@dataclass(frozen=True)
class TrainResult:
    """What :func:`train` returns: the run directory, its history and the best genome."""

    paths: RunPaths
    history: list[GenerationRecord]
    best_genome: Genome
    best_objectives: tuple[float, float]


Callback = Callable[[GenerationRecord], None]


def _history_csv(records: Sequence[GenerationRecord]) -> str:
    buf = io.StringIO()
    writer = csv.DictWriter(buf, fieldnames=list(HISTORY_FIELDS), lineterminator="\n")
    writer.writeheader()
    for rec in records:
        writer.writerow(rec.row())
    return buf.getvalue()


_FLOAT_FIELDS = (
    "best_F", "mean_F", "best_G", "mean_G", "largest_niche_share",
    "best_success_rate", "mean_complexity", "best_complexity", "seconds",
)  # fmt: skip


def _record_from_row(row: dict[str, Any]) -> GenerationRecord:
    sizes = {int(k): int(v) for k, v in json.loads(row["niche_sizes"]).items()}
    return GenerationRecord(
        generation=int(row["generation"]),
        stage=int(row["stage"]),
        mode=str(row["mode"]),
        evaluations=int(row["evaluations"]),
        species=int(row["species"]),
        niche_sizes=sizes,
        **{k: float(row[k]) for k in _FLOAT_FIELDS},
    )


def _check_optional(value: object, ok: Callable[[float], bool], allowed: str, key: str) -> None:
    """ConfigError for ``key`` unless ``value`` is None or a number (not a bool) ``ok`` takes."""
    if value is None:
        return
    if not is_number(value) or not ok(float(value)):
        raise ConfigError(f"must be null or {allowed}", key=key)


def make_problem(
    config: TrainerConfig, profile: RobotProfile | None = None, source: str = "trainer config"
) -> NavigationProblem:
    """The training problem of a config: its robot's scenarios from ``scenario_seed``, the
    network fed with the config's input encoding (``profile`` defaults to the shipped one).

    ConfigError naming ``source`` (the config file) for planner settings outside the robot's
    own ranges and more training worlds than scenarios."""
    limit = config.heading_change_max_deg
    prof = with_planner(
        profile or get_profile(config.robot),
        input_encoding=config.input_encoding,
        heading_change_max=None if limit is None else math.radians(limit),
        step_max=config.step_max,
        step_min=config.step_min,
        clearance_margin=config.clearance_margin,
        source=source,
    )
    count = config.n_scenarios or prof.train_scenarios
    if config.training_worlds > count:
        raise ConfigError(
            f"{count} training scenarios cannot cover {config.training_worlds} worlds",
            key="training_worlds",
            path=source,
        )
    scenarios = training_scenarios(
        prof, config.scenario_seed, count, cfg=config.doe, worlds=config.training_worlds
    )
    return NavigationProblem(prof, scenarios)


def _population_json(
    genomes: Sequence[Genome], evaluation: Evaluation, labels: Sequence[int]
) -> list[dict[str, Any]]:
    return [
        {
            "genome": genome_to_dict(g),
            "objectives": dict(
                zip(OBJECTIVE_NAMES, map(float, evaluation.objectives[i]), strict=True)
            ),
            "success_rate": float(evaluation.success_rate[i]),
            "collision_rate": float(evaluation.collision_rate[i]),
            "species": int(labels[i]),
            "complexity": flops_ratio(g),
        }
        for i, g in enumerate(genomes)
    ]


def _pareto_json(
    genomes: Sequence[Genome], evaluation: Evaluation, stage: int
) -> dict[str, Any]:
    ranks = non_dominated_ranks(evaluation.objectives, maximize=True)
    front = np.flatnonzero(ranks == 0)
    return {
        "format": "mentor-pareto",
        "version": 1,
        "stage": stage,
        "objectives": list(OBJECTIVE_NAMES),
        "points": evaluation.objectives.tolist(),
        "front": [int(i) for i in front],
        "genomes": [genome_to_dict(genomes[int(i)]) for i in front],
    }


class _Run:
    """The mutable state of one training run (kept out of the configs)."""

    def __init__(self, config: TrainerConfig, seed: int, problem: NavigationProblem) -> None:
        self.config = config
        self.seed = seed
        self.problem = problem
        self.evolution = Evolution(
            config.evolution, problem.n_inputs, 2, seed=seed, objectives=2
        )
        self.generation = 0
        self.history: list[GenerationRecord] = []

    def stage_of(self, generation: int) -> tuple[int, Mode, bool]:
        """(stage index, mode, is this the stage's last generation) of a generation."""
        start = 0
        for index, (mode, count) in enumerate(self.config.stages()):
            if generation < start + count:
                return index, mode, generation == start + count - 1
            start += count
        raise IndexError(generation)

    def to_state(self) -> dict[str, Any]:
        return {
            "format": CHECKPOINT_FORMAT,
            "version": CHECKPOINT_VERSION,
            "seed": self.seed,
            "config": self.config.to_dict(),
            "sensors": sensor_record(self.problem.profile),
            "generation": self.generation,
            "evolution": self.evolution.to_state(),
            "history": _history_csv(self.history),
        }

    def load_state(self, state: dict[str, Any], path: Path) -> None:
        if state.get("format") != CHECKPOINT_FORMAT:
            raise FileFormatError(path, f"not a {CHECKPOINT_FORMAT} file")
        if not is_version(state.get("version"), CHECKPOINT_VERSION):
            raise FileFormatError(path, f"unsupported version {state.get('version')!r}")
        # keys added since a checkpoint was written, whose absence meant these values
        saved = {**_CONFIG_KEYS_ADDED, **(state.get("config") or {})}
        if saved != self.config.to_dict() or state.get("seed") != self.seed:
            raise FileFormatError(path, "checkpoint was written by a different config or seed")
        sensors = state.get("sensors")  # absent in checkpoints written before the record
        if sensors is not None and sensors != sensor_record(self.problem.profile):
            raise FileFormatError(path, "checkpoint was written with other robot sensors")
        try:
            self.evolution = Evolution.from_state(state["evolution"])
            self.generation = int(state["generation"])
            rows = csv.DictReader(io.StringIO(state["history"]))
            self.history = [_record_from_row(r) for r in rows]
        except (KeyError, TypeError, ValueError) as err:
            raise FileFormatError(path, f"corrupt checkpoint ({_one_line(err)})") from None


def _load_json(path: Path) -> Any:
    try:
        return json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise FileFormatError(path, "no such file") from None
    except (json.JSONDecodeError, UnicodeDecodeError) as err:
        raise FileFormatError(path, f"not valid JSON ({_one_line(err)})") from None


def train(
    config: TrainerConfig,
    out_dir: str | Path,
    *,
    seed: int = 0,
    evaluator: Evaluator | None = None,
    resume: bool = False,
    callbacks: Sequence[Callback] = (),
    stop_after: int | None = None,
) -> TrainResult:
    """Train a planner; returns when all generations ran (or ``stop_after`` generations).

    Steps per generation: ask the evolution for its population; evaluate it (F, G); tell the
    evolution (ranking by (F, G) in stage 1 of dual-stage, by F otherwise), which speciates,
    sizes the niches and breeds; at the end of dual stage 1, reseed from its best by F;
    record the history row; write the checkpoint atomically; call the callbacks.
    """
    paths = RunPaths(Path(out_dir))
    problem = evaluator.problem if evaluator is not None else make_problem(config)
    own_evaluator = evaluator is None
    evaluator = evaluator or InProcessEvaluator(problem)
    run = _Run(config, seed, problem)
    if resume and paths.checkpoint.exists():
        run.load_state(_load_json(paths.checkpoint), paths.checkpoint)
    elif paths.checkpoint.exists():
        raise FileFormatError(paths.root, "already holds a run; pass resume=True to continue it")
    paths.root.mkdir(parents=True, exist_ok=True)
    write_text_atomic(paths.config, yaml.safe_dump({"seed": seed, **config.to_dict()}))

    total = config.generations
    last_eval: Evaluation | None = None
    last_genomes: list[Genome] = []
    labels: list[int] = []
    try:
        done = 0
        while run.generation < total and (stop_after is None or done < stop_after):
            t0 = time.perf_counter()
            stage, mode, stage_end = run.stage_of(run.generation)
            genomes = run.evolution.ask()
            evaluation = evaluator.evaluate(genomes)
            stats = run.evolution.tell(evaluation.objectives, mode=mode)
            labels = list(stats.labels)
            if stage_end and mode == "multi":
                # stage 1 -> 2: keep the Pareto set, then seed stage 2 from the best by F
                write_json_atomic(paths.pareto, _pareto_json(genomes, evaluation, stage))
                keep = max(1, math.ceil(config.stage2_seed_fraction * len(genomes)))
                order = np.argsort(-evaluation.objectives[:, 0], kind="stable")[:keep]
                run.evolution.reseed([genomes[int(i)] for i in order])
            complexity = np.array([flops_ratio(g) for g in genomes])
            best = int(np.argmax(evaluation.objectives[:, 0]))
            sizes = stats.niche_sizes
            record = GenerationRecord(
                generation=run.generation,
                stage=stage,
                mode=mode,
                evaluations=(run.generation + 1) * len(genomes),
                best_F=float(evaluation.objectives[best, 0]),
                mean_F=float(evaluation.objectives[:, 0].mean()),
                best_G=float(evaluation.objectives[:, 1].max()),
                mean_G=float(evaluation.objectives[:, 1].mean()),
                species=len(sizes),
                largest_niche_share=max(sizes.values()) / max(1, sum(sizes.values())),
                niche_sizes=dict(sizes),
                best_success_rate=float(evaluation.success_rate[best]),
                mean_complexity=float(complexity.mean()),
                best_complexity=float(complexity[best]),
                seconds=time.perf_counter() - t0,
            )
            run.history.append(record)
            run.generation += 1
            done += 1
            write_json_atomic(paths.checkpoint, run.to_state())
            write_text_atomic(paths.history, _history_csv(run.history))
            last_eval, last_genomes = evaluation, genomes
            for callback in callbacks:
                callback(record)
    finally:
        if own_evaluator:
            evaluator.close()

    best_genome, best_obj = run.evolution.best()
    if run.generation >= total:
        save_genome(
            best_genome,
            paths.best_genome,
            metadata={
                "robot": config.robot,
                # what the network was trained with (the evaluator's problem), for planners
                "input_encoding": problem.profile.input_encoding,
                "heading_change_max": problem.profile.heading_change_max,
                "step_max": problem.profile.step_max,
                "step_min": problem.profile.step_min,
                "clearance_margin": problem.profile.clearance_margin,
                "sensors": sensor_record(problem.profile),
                "framework": config.framework,
                "seed": seed,
                "objectives": dict(zip(OBJECTIVE_NAMES, map(float, best_obj), strict=False)),
            },
        )
        if last_eval is not None:
            write_json_atomic(
                paths.population,
                {
                    "format": "mentor-population",
                    "version": 1,
                    "members": _population_json(last_genomes, last_eval, labels),
                },
            )
            if config.framework == "single":
                write_json_atomic(paths.pareto, _pareto_json(last_genomes, last_eval, 0))
    return TrainResult(
        paths=paths,
        history=list(run.history),
        best_genome=best_genome,
        best_objectives=(float(best_obj[0]), float(best_obj[1]) if len(best_obj) > 1 else 0.0),
    )


def load_population(path: str | Path) -> list[tuple[Genome, dict[str, Any]]]:
    """Read ``population.json``: (genome, its record) per member."""
    p = Path(path)
    data = _load_json(p)
    if not isinstance(data, dict) or data.get("format") != "mentor-population":
        raise FileFormatError(p, "not a mentor-population file")
    try:
        return [(genome_from_dict(m["genome"], str(p)), m) for m in data["members"]]
    except (KeyError, TypeError) as err:
        raise FileFormatError(p, f"corrupt population ({_one_line(err)})") from None


__all__ = [
    "GenerationRecord",
    "RunPaths",
    "TrainResult",
    "TrainerConfig",
    "load_population",
    "make_problem",
    "train",
]
