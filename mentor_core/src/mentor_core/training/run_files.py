"""What a training run directory holds (:class:`RunPaths`), and its files' formats.

``config.yaml`` (:mod:`mentor_core.training.config`), ``checkpoint.json`` (the trainer's
state), ``history.csv`` (one :class:`GenerationRecord` per generation, columns
:data:`HISTORY_FIELDS`), ``population.json`` (``mentor-population``: the final population),
``pareto.json`` (``mentor-pareto``: the non-dominated set by (F, G) of dual stage 1's last
population, or of the single-stage framework's final one) and ``best_genome.json``
(:mod:`mentor_core.files.genome_file`). :mod:`mentor_core.training.trainer` writes them, as
one writer (:mod:`mentor_core.training.run_directory`).
"""

from __future__ import annotations

import csv
import io
import json
import math
from collections.abc import Sequence
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import numpy as np

from mentor_core.errors import FileFormatError, one_line
from mentor_core.evolution.genome import Genome
from mentor_core.evolution.genome_codec import genome_from_dict, genome_to_dict
from mentor_core.evolution.ranking import non_dominated_ranks
from mentor_core.objectives.complexity import flops_ratio
from mentor_core.training.problem import OBJECTIVE_NAMES, Evaluation

HISTORY_FIELDS = (
    "generation", "stage", "mode", "evaluations", "best_F", "mean_F", "best_G", "mean_G",
    "species", "largest_niche_share", "niche_sizes", "best_success_rate",
    "mean_complexity", "best_complexity", "seconds",
)  # fmt: skip


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

    @property
    def files(self) -> tuple[Path, ...]:
        """Every file a run writes here (besides the lock the writer holds)."""
        return (
            self.config, self.checkpoint, self.history, self.population, self.pareto,
            self.best_genome,
        )  # fmt: skip


@dataclass(frozen=True)
class GenerationRecord:
    """One row of the per-generation history (what reporters receive). ``best_G`` and
    ``mean_G`` are NaN (empty in the CSV) in a generation that ranks F alone: only its best
    genome's G is computed there (``NavigationProblem.evaluate``, ``gains="best"``)."""

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
        """The CSV row (niche sizes as compact JSON; a value not computed, NaN, empty)."""
        d = asdict(self)
        d["niche_sizes"] = json.dumps({str(k): v for k, v in sorted(self.niche_sizes.items())})
        return {k: "" if isinstance(v, float) and math.isnan(v) else v for k, v in d.items()}


def history_csv(records: Sequence[GenerationRecord]) -> str:
    """The ``history.csv`` text of ``records`` (header :data:`HISTORY_FIELDS`)."""
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


def record_from_row(row: dict[str, Any]) -> GenerationRecord:
    """One row of ``history.csv`` (a ``csv.DictReader`` row) as a record; KeyError,
    TypeError or ValueError when it is corrupt."""
    niches = json.loads(row["niche_sizes"])
    if not isinstance(niches, dict):
        raise ValueError("niche_sizes is not a JSON object")
    sizes = {int(k): int(v) for k, v in niches.items()}
    return GenerationRecord(
        generation=int(row["generation"]),
        stage=int(row["stage"]),
        mode=str(row["mode"]),
        evaluations=int(row["evaluations"]),
        species=int(row["species"]),
        niche_sizes=sizes,
        **{k: math.nan if row[k] == "" else float(row[k]) for k in _FLOAT_FIELDS},
    )


def history_from_csv(text: str) -> list[GenerationRecord]:
    """The records of :func:`history_csv`'s text (KeyError, TypeError or ValueError if it is
    corrupt)."""
    return [record_from_row(r) for r in csv.DictReader(io.StringIO(text))]


def population_json(
    genomes: Sequence[Genome], evaluation: Evaluation, labels: Sequence[int]
) -> dict[str, Any]:
    """The ``population.json`` of a population: per member its genome, objectives, success and
    collision rates, species label and complexity."""
    return {
        "format": "mentor-population",
        "version": 1,
        "members": [
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
        ],
    }


def pareto_json(
    genomes: Sequence[Genome], evaluation: Evaluation, stage: int
) -> dict[str, Any]:
    """The ``pareto.json`` of a population: all its (F, G) points, the indices of its first
    non-dominated front and that front's genomes."""
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


def load_json(path: Path) -> dict[str, Any]:
    """A JSON file's object (every file of a run directory is one); FileFormatError naming
    ``path`` if missing, not JSON or not a JSON object."""
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise FileFormatError(path, "no such file") from None
    except (json.JSONDecodeError, UnicodeDecodeError) as err:
        raise FileFormatError(path, f"not valid JSON ({one_line(err)})") from None
    if not isinstance(data, dict):
        kind = {list: "an array", str: "a string", bool: "a boolean", type(None): "null"}
        got = kind.get(type(data), "a number")
        raise FileFormatError(path, f"expected a JSON object, got {got}")
    return data


def load_population(path: str | Path) -> list[tuple[Genome, dict[str, Any]]]:
    """Read ``population.json``: (genome, its record) per member."""
    p = Path(path)
    data = load_json(p)
    if not isinstance(data, dict) or data.get("format") != "mentor-population":
        raise FileFormatError(p, "not a mentor-population file")
    try:
        return [(genome_from_dict(m["genome"], str(p)), m) for m in data["members"]]
    except (KeyError, TypeError) as err:
        raise FileFormatError(p, f"corrupt population ({one_line(err)})") from None


__all__ = [
    "HISTORY_FIELDS",
    "GenerationRecord",
    "RunPaths",
    "history_csv",
    "history_from_csv",
    "load_json",
    "load_population",
    "pareto_json",
    "population_json",
]
