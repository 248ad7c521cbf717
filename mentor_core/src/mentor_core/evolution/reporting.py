"""Reporters: observers of an evolution run (neat-python's ``reporting.py``).

Side effects (printing, CSV history, checkpoints, progress bars) live in reporters, never in the
evolution loop. A reporter overrides the events it cares about; the base methods do nothing.
:class:`ReporterSet` fans every event out to its reporters in the order they were added.

Events, in the order one generation emits them:

1. ``start_generation(generation)`` -- the population of ``generation`` is about to be evaluated
   (emitted by ``Evolution.ask`` the first time it is called for that generation);
2. ``end_generation(stats)`` -- the generation was ranked, speciated and the next population
   bred (emitted by ``Evolution.tell``; the evolution is then in a resumable state, which is
   when a checkpointer saves);
3. ``found_solution(generation, genome, objectives)`` -- ``Evolution.run`` reached its fitness
   threshold;
4. ``info(message)`` -- free text (stage changes, reseeding).
"""

from __future__ import annotations

import json
import math
import sys
from collections.abc import Iterable, Iterator, Mapping
from dataclasses import dataclass
from typing import Any, TextIO

import numpy as np

from mentor_core.evolution.genome import Genome


def json_floats(values: Iterable[float]) -> list[float | None]:
    """``values`` as a JSON list, NaN (an objective not computed) as null."""
    return [None if math.isnan(v) else float(v) for v in values]


def _float(value: Any) -> float:
    return math.nan if value is None else float(value)


@dataclass(frozen=True)
class GenerationStats:
    """What one generation of evolution looked like (returned by ``Evolution.tell``).

    ``best_objectives`` and ``mean_objectives`` have one entry per objective column told;
    ``niche_sizes`` is the number of members of each species (niche) in the evaluated
    population, ``niche_targets`` the sizes N'_i (paper eq. 2) the next population was bred
    with (0: the niche went extinct); ``labels`` the species id of each evaluated genome.
    ``best_index`` is the index, in the evaluated population, of the genome with the highest
    objective 0 (first one on ties). ``evaluations`` counts every genome told so far.
    """

    generation: int
    evaluations: int
    mode: str
    best_objectives: tuple[float, ...]
    mean_objectives: tuple[float, ...]
    species_count: int
    niche_sizes: Mapping[int, int]
    niche_targets: Mapping[int, int]
    labels: tuple[int, ...]
    largest_niche_share: float
    best_index: int
    threshold: float
    mean_hidden_nodes: float
    mean_enabled_connections: float

    def to_dict(self) -> dict[str, Any]:
        """JSON-serialisable form (species ids become string keys)."""
        return {
            "generation": self.generation,
            "evaluations": self.evaluations,
            "mode": self.mode,
            "best_objectives": json_floats(self.best_objectives),
            "mean_objectives": json_floats(self.mean_objectives),
            "species_count": self.species_count,
            "niche_sizes": {str(k): v for k, v in sorted(self.niche_sizes.items())},
            "niche_targets": {str(k): v for k, v in sorted(self.niche_targets.items())},
            "labels": list(self.labels),
            "largest_niche_share": self.largest_niche_share,
            "best_index": self.best_index,
            "threshold": self.threshold,
            "mean_hidden_nodes": self.mean_hidden_nodes,
            "mean_enabled_connections": self.mean_enabled_connections,
        }

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> GenerationStats:
        """Inverse of :meth:`to_dict` (raises ``KeyError``/``TypeError`` on a malformed dict)."""
        return cls(
            generation=int(d["generation"]),
            evaluations=int(d["evaluations"]),
            mode=str(d["mode"]),
            best_objectives=tuple(_float(v) for v in d["best_objectives"]),
            mean_objectives=tuple(_float(v) for v in d["mean_objectives"]),
            species_count=int(d["species_count"]),
            niche_sizes={int(k): int(v) for k, v in d["niche_sizes"].items()},
            niche_targets={int(k): int(v) for k, v in d["niche_targets"].items()},
            labels=tuple(int(v) for v in d["labels"]),
            largest_niche_share=float(d["largest_niche_share"]),
            best_index=int(d["best_index"]),
            threshold=float(d["threshold"]),
            mean_hidden_nodes=float(d["mean_hidden_nodes"]),
            mean_enabled_connections=float(d["mean_enabled_connections"]),
        )


class Reporter:
    """Base observer: every method does nothing; override the events you need."""

    def start_generation(self, generation: int) -> None:
        """The population of ``generation`` is about to be evaluated."""

    def end_generation(self, stats: GenerationStats) -> None:
        """A generation was ranked and the next population bred."""

    def found_solution(self, generation: int, genome: Genome, objectives: np.ndarray) -> None:
        """``genome`` (with its objective vector) reached the run's fitness threshold."""

    def info(self, message: str) -> None:
        """Free-text note from the run (stage change, reseeding)."""


class ReporterSet:
    """Dispatches every event to a list of reporters, in order."""

    def __init__(self, reporters: Iterable[Reporter] = ()) -> None:
        self._reporters: list[Reporter] = list(reporters)

    def add(self, reporter: Reporter) -> None:
        """Append a reporter."""
        self._reporters.append(reporter)

    def remove(self, reporter: Reporter) -> None:
        """Remove a reporter (``ValueError`` if it is not there)."""
        self._reporters.remove(reporter)

    def __iter__(self) -> Iterator[Reporter]:
        return iter(self._reporters)

    def __len__(self) -> int:
        return len(self._reporters)

    def start_generation(self, generation: int) -> None:
        for reporter in self._reporters:
            reporter.start_generation(generation)

    def end_generation(self, stats: GenerationStats) -> None:
        for reporter in self._reporters:
            reporter.end_generation(stats)

    def found_solution(self, generation: int, genome: Genome, objectives: np.ndarray) -> None:
        for reporter in self._reporters:
            reporter.found_solution(generation, genome, objectives)

    def info(self, message: str) -> None:
        for reporter in self._reporters:
            reporter.info(message)


class StdOutReporter(Reporter):
    """One line per generation on a text stream (default ``sys.stdout``)."""

    def __init__(self, stream: TextIO | None = None) -> None:
        self._stream = stream

    def _write(self, text: str) -> None:
        print(text, file=self._stream if self._stream is not None else sys.stdout)

    def end_generation(self, stats: GenerationStats) -> None:
        # "-": an objective not computed in this generation (NaN)
        best = ", ".join("-" if math.isnan(v) else f"{v:.4g}" for v in stats.best_objectives)
        mean = ", ".join("-" if math.isnan(v) else f"{v:.4g}" for v in stats.mean_objectives)
        self._write(
            f"gen {stats.generation:4d}  evals {stats.evaluations:7d}  best [{best}]  "
            f"mean [{mean}]  species {stats.species_count:3d}  "
            f"largest {stats.largest_niche_share:.2f}"
        )

    def found_solution(self, generation: int, genome: Genome, objectives: np.ndarray) -> None:
        self._write(f"solution in generation {generation}: objectives {objectives.tolist()}")

    def info(self, message: str) -> None:
        self._write(message)


class HistoryReporter(Reporter):
    """Keeps every generation's stats; ``to_json()`` gives them as a JSON list."""

    def __init__(self) -> None:
        self.history: list[GenerationStats] = []

    def end_generation(self, stats: GenerationStats) -> None:
        self.history.append(stats)

    def to_json(self) -> str:
        return json.dumps([s.to_dict() for s in self.history], allow_nan=False)
