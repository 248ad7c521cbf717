"""Run directories and evaluation files read from disk, validated (paper section IV).

:func:`load_run` reads a finished run directory (see
:class:`mentor_core.training.run_files.RunPaths`) into a :class:`RunData`, :func:`load_eval` a
``mentor-eval`` JSON file into an :class:`EvalData`; a missing or corrupt file raises
FileFormatError naming it.
"""

from __future__ import annotations

import csv
import io
import json
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from mentor_core.errors import FileFormatError, is_version, one_line
from mentor_core.evolution.genome import Genome
from mentor_core.files.genome_file import load_genome_and_metadata
from mentor_core.runtime.planner import planner_profile
from mentor_core.sim.robots import get_profile
from mentor_core.training.run_files import (
    HISTORY_FIELDS,
    GenerationRecord,
    RunPaths,
    record_from_row,
)
from mentor_core.validation import read_yaml


@dataclass(frozen=True)
class RunData:
    """A finished training run: its config, history, final population and best genome."""

    path: Path
    robot: str
    framework: str
    seed: int
    generations: int
    history: list[GenerationRecord]
    members: list[dict[str, Any]]  # population.json members (genome dicts, objectives, ...)
    pareto_points: np.ndarray  # (n, 2) [F, G] of the Pareto file's population
    pareto_front: list[int]  # indices into pareto_points
    pareto_stage: int
    best_genome: Genome
    input_encoding: str = "paper"  # of the best genome (its metadata)
    feedback_action: bool = False  # of the best genome (its metadata)
    config: Mapping[str, Any] = field(default_factory=dict)  # the run's config.yaml

    @property
    def label(self) -> str:
        """A short label: robot, framework and seed."""
        return f"{self.robot} {self.framework} s{self.seed}"


@dataclass(frozen=True)
class EpisodeResult:
    """One episode of an evaluation (a start/goal pair driven by one genome)."""

    scenario: int
    reached: bool
    collided: bool
    timed_out: bool
    time: float  # s
    final_distance: float  # m
    trajectory: np.ndarray  # (m, 3) poses [x, y, theta], m, rad

    @property
    def outcome(self) -> str:
        """ "reached", "collided" or "timed out"."""
        return "reached" if self.reached else "collided" if self.collided else "timed out"


@dataclass(frozen=True)
class EvalRun:
    """One genome's results in an evaluation file."""

    label: str
    path: str
    results: list[EpisodeResult]
    summary: dict[str, float]  # success_rate, collision_rate, survivability, mean_time_reached


@dataclass(frozen=True)
class EvalData:
    """A ``mentor-eval`` file: the unseen world, its start/goal pairs and the runs on it."""

    path: Path
    robot: str
    source: str
    world_size: float  # m
    obstacles: np.ndarray  # (k, 4) [xmin, ymin, xmax, ymax], m
    starts: np.ndarray  # (n, 3) [x, y, theta]
    goals: np.ndarray  # (n, 2)
    goal_radius: float  # m
    time_limit: float  # s
    runs: list[EvalRun]


def _read_json(path: Path) -> Any:
    try:
        return json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise FileFormatError(path, "no such file") from None
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as err:
        raise FileFormatError(path, f"not valid JSON ({one_line(err)})") from None


def _check_format(path: Path, data: Any, fmt: str) -> dict[str, Any]:
    if not isinstance(data, dict) or data.get("format") != fmt:
        raise FileFormatError(path, f"not a {fmt} file")
    if not is_version(data.get("version"), 1):
        raise FileFormatError(path, f"unsupported version {data.get('version')!r}")
    return data


def _read_config(path: Path) -> dict[str, Any]:
    data = read_yaml(path)
    if not isinstance(data, dict):
        raise FileFormatError(path, "not a mapping")
    for key, kind in (("robot", str), ("framework", str), ("seed", int), ("generations", int)):
        if not isinstance(data.get(key), kind):
            raise FileFormatError(path, f"missing or bad key {key!r}")
    return data


def read_history(path: str | Path) -> list[GenerationRecord]:
    """Parse ``history.csv`` (columns :data:`mentor_core.training.run_files.HISTORY_FIELDS`)."""
    p = Path(path)
    try:
        text = p.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise FileFormatError(p, "no such file") from None
    except (OSError, UnicodeDecodeError) as err:
        raise FileFormatError(p, f"unreadable ({one_line(err)})") from None
    reader = csv.DictReader(io.StringIO(text))
    missing = [f for f in HISTORY_FIELDS if f not in (reader.fieldnames or ())]
    if missing:
        raise FileFormatError(p, f"missing columns {', '.join(missing)}")
    records: list[GenerationRecord] = []
    for line, row in enumerate(reader, start=2):
        try:
            records.append(record_from_row(row))
        except (TypeError, ValueError) as err:
            raise FileFormatError(p, f"line {line}: {one_line(err)}") from None
    if not records:
        raise FileFormatError(p, "no generations recorded")
    return records


def is_finished(run_dir: str | Path) -> bool:
    """Whether a run directory holds its final population and best genome (the trainer writes
    the best genome last, after refining its weights where the config asks)."""
    paths = RunPaths(Path(run_dir))
    return paths.population.is_file() and paths.best_genome.is_file()


def load_run(run_dir: str | Path) -> RunData:
    """Read and validate a finished run directory (FileFormatError naming file and fault;
    ConfigError naming the best genome when it was trained with other sensors, or planner
    settings, than the robot file in use allows)."""
    paths = RunPaths(Path(run_dir))
    if not paths.root.is_dir():
        raise FileFormatError(paths.root, "no such run directory")
    config = _read_config(paths.config)
    history = read_history(paths.history)

    population = _check_format(paths.population, _read_json(paths.population), "mentor-population")
    members = population.get("members")
    if not isinstance(members, list) or not members:
        raise FileFormatError(paths.population, "no members")
    for i, m in enumerate(members):
        try:
            float(m["objectives"]["performance"])
            float(m["objectives"]["experience_gain"])
            float(m["complexity"])
        except (KeyError, TypeError, ValueError) as err:
            raise FileFormatError(paths.population, f"member {i}: bad {one_line(err)}") from None

    pareto = _check_format(paths.pareto, _read_json(paths.pareto), "mentor-pareto")
    try:
        points = np.asarray(pareto["points"], dtype=np.float64)
        front = [int(i) for i in pareto["front"]]
        stage = int(pareto.get("stage", 0))
    except (KeyError, TypeError, ValueError) as err:
        raise FileFormatError(paths.pareto, f"corrupt ({one_line(err)})") from None
    if points.ndim != 2 or points.shape[1] != 2 or not points.size:
        raise FileFormatError(paths.pareto, "points must be a non-empty list of [F, G]")
    if any(not 0 <= i < len(points) for i in front):
        raise FileFormatError(paths.pareto, "front index out of range")

    genome, genome_meta = load_genome_and_metadata(paths.best_genome)
    # a genome trained with other sensors than the robot file's now is refused (ConfigError
    # naming the file), as mentor-eval and the planner node refuse it
    planner = planner_profile(get_profile(str(config["robot"])), genome_meta, paths.best_genome)
    return RunData(
        path=paths.root,
        robot=str(config["robot"]),
        framework=str(config["framework"]),
        seed=int(config["seed"]),
        generations=int(config["generations"]),
        history=history,
        members=members,
        pareto_points=points,
        pareto_front=front,
        pareto_stage=stage,
        best_genome=genome,
        input_encoding=planner.input_encoding,
        feedback_action=planner.feedback_action,
        config=config,
    )


def _episode(path: Path, where: str, r: Any) -> EpisodeResult:
    try:
        traj = np.asarray(r["trajectory"], dtype=np.float64).reshape(-1, 3)
        return EpisodeResult(
            scenario=int(r["scenario"]),
            reached=bool(r["reached"]),
            collided=bool(r["collided"]),
            timed_out=bool(r["timed_out"]),
            time=float(r["time"]),
            final_distance=float(r["final_distance"]),
            trajectory=traj,
        )
    except (KeyError, TypeError, ValueError) as err:
        raise FileFormatError(path, f"{where}: bad result ({one_line(err)})") from None


def _summary_value(v: Any) -> float:
    return math.nan if v is None else float(v)


def load_eval(path: str | Path) -> EvalData:
    """Read and validate a ``mentor-eval`` JSON file (FileFormatError naming file and fault)."""
    p = Path(path)
    data = _check_format(p, _read_json(p), "mentor-eval")
    try:
        world = data["world"]
        obstacles = np.asarray(world["obstacles"], dtype=np.float64).reshape(-1, 4)
        starts = np.asarray([s["start"] for s in data["scenarios"]], np.float64).reshape(-1, 3)
        goals = np.asarray([s["goal"] for s in data["scenarios"]], np.float64).reshape(-1, 2)
        runs = []
        for k, run in enumerate(data["runs"]):
            results = [_episode(p, f"run {k}", r) for r in run["results"]]
            summary = {
                key: _summary_value(run["summary"][key])
                for key in ("success_rate", "collision_rate", "survivability", "mean_time_reached")
            }
            runs.append(EvalRun(str(run["genome"]), str(run.get("path", "")), results, summary))
        out = EvalData(
            path=p,
            robot=str(data["robot"]),
            source=str(data.get("source", "")),
            world_size=float(world["size"]),
            obstacles=obstacles,
            starts=starts,
            goals=goals,
            goal_radius=float(data.get("goal_radius", 0.0)),
            time_limit=float(data.get("time_limit", math.nan)),
            runs=runs,
        )
    except FileFormatError:
        raise
    except (KeyError, TypeError, ValueError) as err:
        raise FileFormatError(p, f"corrupt ({one_line(err)})") from None
    for run in out.runs:
        for r in run.results:
            if not 0 <= r.scenario < len(out.starts):
                raise FileFormatError(p, f"{run.label}: scenario {r.scenario} out of range")
    return out


__all__ = [
    "EpisodeResult",
    "EvalData",
    "EvalRun",
    "RunData",
    "load_eval",
    "load_run",
    "read_history",
]
