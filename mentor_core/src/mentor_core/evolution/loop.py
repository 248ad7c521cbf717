"""The MENTOR evolution loop, ask/tell style (pymoo's ``Algorithm``; neat-python's ``Population``).

:class:`Evolution` owns all run state of the evolution side: the population to evaluate, the
one ``np.random.Generator`` made from the seed (passed down to every operator), the innovation
tracker, the species representatives and the compatibility threshold, the generation and
evaluation counters and the best genome seen. Configuration (:class:`EvolutionConfig`) never
changes. The whole state round-trips through :meth:`Evolution.to_state` /
:meth:`Evolution.from_state` as plain JSON, the generator's ``bit_generator.state`` included,
so a resumed run continues exactly as an unbroken one.

One generation::

    genomes = evolution.ask()            # the population to evaluate
    objectives = evaluate(genomes)       # (N, m), higher is better in every column
    stats = evolution.tell(objectives)   # rank, speciate, breed the next population

``tell(..., mode="multi")`` ranks by NSGA-II over all columns (non-dominated front first,
crowding distance second: ``ranking.scalar_fitness``); ``mode="single"`` ranks by column 0
alone (the second stage of the dual-stage framework, and plain single-objective runs).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np

from mentor_core.errors import FileFormatError, is_version
from mentor_core.evolution.config import EvolutionConfig
from mentor_core.evolution.genome import Genome, minimal_genome
from mentor_core.evolution.genome_codec import genome_from_dict, genome_to_dict
from mentor_core.evolution.innovation import InnovationTracker
from mentor_core.evolution.mutation import mutate
from mentor_core.evolution.ranking import scalar_fitness
from mentor_core.evolution.reporting import (
    GenerationStats,
    Reporter,
    ReporterSet,
    json_floats,
)
from mentor_core.evolution.reproduction import reproduce
from mentor_core.evolution.species import adjust_threshold, speciate

Mode = Literal["multi", "single"]
MODES: tuple[str, ...] = ("multi", "single")
STATE_FORMAT = "mentor-evolution"
STATE_VERSION = 1
_BIT_GENERATORS: Mapping[str, Callable[[], np.random.BitGenerator]] = {
    "PCG64": np.random.PCG64,
    "PCG64DXSM": np.random.PCG64DXSM,
    "Philox": np.random.Philox,
    "SFC64": np.random.SFC64,
    "MT19937": np.random.MT19937,
}


@dataclass(frozen=True)
class RunResult:
    """What :meth:`Evolution.run` returns: the best genome seen and the run's history."""

    best_genome: Genome
    best_objectives: np.ndarray
    history: tuple[GenerationStats, ...]
    solved: bool
    generations: int
    evaluations: int


class Evolution:
    """Run state and main loop of one MENTOR evolution (see the module docstring).

    Args:
        config: the evolution parameters.
        n_inputs, n_outputs: network inputs (bias excluded) and outputs.
        seed: seed of the run's one ``np.random.Generator``.
        objectives: number of objective columns that ``tell`` expects in ``"multi"`` mode.
        reporters: observers of the run (:class:`~mentor_core.evolution.reporting.Reporter`).
    """

    def __init__(
        self,
        config: EvolutionConfig,
        n_inputs: int,
        n_outputs: int,
        seed: int,
        objectives: int = 1,
        reporters: Iterable[Reporter] = (),
    ) -> None:
        if isinstance(objectives, bool) or not isinstance(objectives, int) or objectives < 1:
            raise ValueError(f"objectives must be a positive int, got {objectives!r}")
        self.config = config
        self.n_inputs = n_inputs
        self.n_outputs = n_outputs
        self.n_objectives = objectives
        self.seed = int(seed)
        self.reporters = ReporterSet(reporters)
        self.rng = np.random.default_rng(self.seed)
        self.tracker = InnovationTracker(next_node_id=n_inputs + 1 + n_outputs)
        self.threshold = float(config.speciation.threshold)
        self.representatives: dict[int, Genome] = {}
        self.next_species_id = 0
        self.generation = 0
        self.evaluations = 0
        self.history: list[GenerationStats] = []
        self._population: list[Genome] = [
            minimal_genome(
                n_inputs,
                n_outputs,
                self.tracker,
                self.rng,
                weight_sigma=config.initial_weight_sigma,
                hidden_activation=config.hidden_activation,
                output_activation=config.output_activation,
            )
            for _ in range(config.population_size)
        ]
        self._best: tuple[Genome, np.ndarray] | None = None
        self._last: _Evaluated | None = None
        self._announced = -1

    # ------------------------------------------------------------------ accessors
    @property
    def population(self) -> list[Genome]:
        """The genomes of the current generation (those :meth:`ask` returns)."""
        return list(self._population)

    @property
    def labels(self) -> np.ndarray | None:
        """Species labels of the last evaluated population (None before the first tell)."""
        return None if self._last is None else self._last.labels.copy()

    @property
    def evaluated_population(self) -> list[Genome]:
        """The genomes of the last generation told (empty before the first tell)."""
        return [] if self._last is None else list(self._last.genomes)

    @property
    def evaluated_objectives(self) -> np.ndarray | None:
        """Objectives of the last generation told, (N, m) (None before the first tell)."""
        return None if self._last is None else self._last.objectives.copy()

    @property
    def fitness(self) -> np.ndarray | None:
        """Scalar fitness of the last generation told (None before the first tell)."""
        return None if self._last is None else self._last.fitness.copy()

    def best(self) -> tuple[Genome, np.ndarray]:
        """The genome with the highest objective 0 seen in any generation, and its objectives.

        The earliest one wins ties. ``RuntimeError`` before the first :meth:`tell`.
        """
        if self._best is None:
            raise RuntimeError("no generation has been evaluated yet")
        return self._best[0], self._best[1].copy()

    # ------------------------------------------------------------------ ask / tell
    def ask(self) -> list[Genome]:
        """The population to evaluate this generation (the same list until :meth:`tell`)."""
        if self._announced != self.generation:
            self._announced = self.generation
            self.reporters.start_generation(self.generation)
        return list(self._population)

    def tell(self, objectives: np.ndarray, mode: Mode = "multi") -> GenerationStats:
        """Rank, speciate and breed from the objectives of the population :meth:`ask` gave.

        Steps: check the (N, m) objectives (finite, higher is better; in ``"single"`` mode
        the columns after the first may be NaN, not computed); speciate against the
        previous representatives and adjust the threshold toward the target species count;
        scalar fitness by NSGA-II over all columns (``"multi"``) or column 0 (``"single"``);
        update the best genome; breed the next population (``reproduction.reproduce``);
        advance the generation; report ``end_generation``.
        """
        values = self._check_objectives(objectives, mode)
        genomes = self._population
        labels, self.representatives, self.next_species_id = speciate(
            genomes,
            self.representatives,
            self.threshold,
            self.config.speciation,
            self.next_species_id,
        )
        labels = np.asarray(labels, dtype=np.int64)
        species = np.unique(labels)
        self.threshold = float(
            adjust_threshold(self.threshold, len(species), self.config.speciation)
        )
        ranked = values if mode == "multi" else values[:, :1]
        fitness = np.asarray(scalar_fitness(ranked), dtype=np.float64)
        self.evaluations += len(genomes)
        best_index = int(np.argmax(values[:, 0]))
        if self._best is None or values[best_index, 0] > self._best[1][0]:
            self._best = (genomes[best_index], values[best_index].copy())
        offspring = reproduce(genomes, fitness, labels, self.config, self.tracker, self.rng)
        self._last = _Evaluated(tuple(genomes), values, labels, fitness)
        sizes = {int(s): int(np.count_nonzero(labels == s)) for s in species}
        stats = GenerationStats(
            generation=self.generation,
            evaluations=self.evaluations,
            mode=mode,
            best_objectives=tuple(float(v) for v in values.max(axis=0)),
            mean_objectives=tuple(float(v) for v in values.mean(axis=0)),
            species_count=len(species),
            niche_sizes=sizes,
            niche_targets=dict(offspring.niche_targets),
            labels=tuple(int(v) for v in labels),
            largest_niche_share=max(sizes.values()) / len(genomes),
            best_index=best_index,
            threshold=self.threshold,
            mean_hidden_nodes=float(np.mean([len(g.hidden_nodes) for g in genomes])),
            mean_enabled_connections=float(
                np.mean([len(g.enabled_connections) for g in genomes])
            ),
        )
        self._population = list(offspring.genomes)
        self.history.append(stats)
        self.generation += 1
        self.reporters.end_generation(stats)
        return stats

    def reseed(self, genomes: Sequence[Genome]) -> None:
        """Start a new stage from ``genomes`` (e.g. part of the previous stage's population).

        The next population is ``genomes`` (at most N of them, in order) filled up to N with
        mutated copies of them, taken in turn. Tracker, species representatives, threshold,
        counters and the best genome carry on.
        """
        seeds = list(genomes)
        if not seeds:
            raise ValueError("reseed needs at least one genome")
        for g in seeds:
            if (g.n_inputs, g.n_outputs) != (self.n_inputs, self.n_outputs):
                raise ValueError(
                    f"genome has {g.n_inputs} inputs / {g.n_outputs} outputs, the run "
                    f"{self.n_inputs} / {self.n_outputs}"
                )
        size = self.config.population_size
        population = seeds[:size]
        for k in range(size - len(population)):
            population.append(
                mutate(seeds[k % len(seeds)], self.config.mutation, self.tracker, self.rng)
            )
        self._population = population
        self.reporters.info(
            f"generation {self.generation}: reseeded from {len(seeds)} genomes"
        )

    def run(
        self,
        evaluate: Callable[[list[Genome]], np.ndarray],
        generations: int | None = None,
        fitness_threshold: float | None = None,
        mode: Mode = "multi",
    ) -> RunResult:
        """Evolve for ``generations`` (default ``config.generations``) more generations.

        Steps per generation: ``ask``; ``evaluate`` the genomes into (N, m) objectives;
        ``tell``; stop early once the best objective 0 of a generation reaches
        ``fitness_threshold`` (reporters get ``found_solution``).
        """
        count = self.config.generations if generations is None else generations
        solved = False
        start = len(self.history)
        for _ in range(count):
            genomes = self.ask()
            objectives = np.asarray(evaluate(genomes), dtype=np.float64)
            stats = self.tell(objectives, mode=mode)
            if fitness_threshold is not None and stats.best_objectives[0] >= fitness_threshold:
                solved = True
                i = stats.best_index
                self.reporters.found_solution(stats.generation, genomes[i], objectives[i])
                break
        genome, values = self.best()
        return RunResult(
            best_genome=genome,
            best_objectives=values,
            history=tuple(self.history[start:]),
            solved=solved,
            generations=self.generation,
            evaluations=self.evaluations,
        )

    # ------------------------------------------------------------------ state
    def to_state(self) -> dict[str, Any]:
        """JSON-serialisable state; :meth:`from_state` rebuilds an evolution that continues
        exactly as this one would (reporters are not part of the state)."""
        last = None
        if self._last is not None:
            last = {
                "genomes": [genome_to_dict(g) for g in self._last.genomes],
                "objectives": _plain(self._last.objectives),
                "labels": self._last.labels.tolist(),
                "fitness": self._last.fitness.tolist(),
            }
        best = None
        if self._best is not None:
            best = {"genome": genome_to_dict(self._best[0]), "objectives": _plain(self._best[1])}
        return {
            "format": STATE_FORMAT,
            "version": STATE_VERSION,
            "config": self.config.to_dict(),
            "n_inputs": self.n_inputs,
            "n_outputs": self.n_outputs,
            "n_objectives": self.n_objectives,
            "seed": self.seed,
            "rng": _jsonable(self.rng.bit_generator.state),
            "tracker": self.tracker.to_state(),
            "threshold": self.threshold,
            "representatives": [
                [sid, genome_to_dict(g)] for sid, g in sorted(self.representatives.items())
            ],
            "next_species_id": self.next_species_id,
            "generation": self.generation,
            "evaluations": self.evaluations,
            "announced": self._announced,
            "population": [genome_to_dict(g) for g in self._population],
            "best": best,
            "last": last,
            "history": [s.to_dict() for s in self.history],
        }

    @classmethod
    def from_state(
        cls,
        d: Mapping[str, Any],
        source: str = "<state>",
        reporters: Iterable[Reporter] = (),
    ) -> Evolution:
        """Rebuild from :meth:`to_state`'s dict; ``FileFormatError(source, fault)`` if bad."""
        if not isinstance(d, Mapping):
            raise FileFormatError(source, "evolution state is not a mapping")
        if d.get("format") != STATE_FORMAT or not is_version(d.get("version"), STATE_VERSION):
            raise FileFormatError(
                source,
                f"evolution state format/version {d.get('format')!r}/{d.get('version')!r} "
                f"is not {STATE_FORMAT!r}/{STATE_VERSION}",
            )
        try:
            evo = cls.__new__(cls)
            evo.config = EvolutionConfig.from_dict(d["config"], source)
            evo.n_inputs = _int(d["n_inputs"])
            evo.n_outputs = _int(d["n_outputs"])
            evo.n_objectives = _int(d["n_objectives"])
            evo.seed = _int(d["seed"])
            evo.reporters = ReporterSet(reporters)
            name = d["rng"]["bit_generator"]
            if name not in _BIT_GENERATORS:
                raise FileFormatError(source, f"unknown bit generator {name!r}")
            bit_generator = _BIT_GENERATORS[name]()
            bit_generator.state = d["rng"]
            evo.rng = np.random.Generator(bit_generator)
            evo.tracker = InnovationTracker.from_state(d["tracker"], source)
            evo.threshold = float(d["threshold"])
            evo.representatives = {
                _int(sid): genome_from_dict(g, source) for sid, g in d["representatives"]
            }
            evo.next_species_id = _int(d["next_species_id"])
            evo.generation = _int(d["generation"])
            evo.evaluations = _int(d["evaluations"])
            evo._announced = _int(d["announced"])
            evo._population = [genome_from_dict(g, source) for g in d["population"]]
            best = d["best"]
            evo._best = (
                None
                if best is None
                else (
                    genome_from_dict(best["genome"], source),
                    np.asarray(best["objectives"], dtype=np.float64),
                )
            )
            last = d["last"]
            evo._last = (
                None
                if last is None
                else _Evaluated(
                    tuple(genome_from_dict(g, source) for g in last["genomes"]),
                    np.asarray(last["objectives"], dtype=np.float64),
                    np.asarray(last["labels"], dtype=np.int64),
                    np.asarray(last["fitness"], dtype=np.float64),
                )
            )
            evo.history = [GenerationStats.from_dict(s) for s in d["history"]]
        except FileFormatError:
            raise
        except (KeyError, TypeError, ValueError, AttributeError, IndexError) as err:
            raise FileFormatError(source, f"bad evolution state: {err!r}") from None
        if len(evo._population) != evo.config.population_size:
            raise FileFormatError(source, "population size does not match the config")
        return evo

    # ------------------------------------------------------------------ helpers
    def _check_objectives(self, objectives: np.ndarray, mode: str) -> np.ndarray:
        if mode not in MODES:
            raise ValueError(f"mode must be 'multi' or 'single', got {mode!r}")
        values = np.array(objectives, dtype=np.float64)
        if values.ndim == 1:
            values = values.reshape(-1, 1)
        n = len(self._population)
        if values.ndim != 2 or values.shape[0] != n or values.shape[1] < 1:
            raise ValueError(f"objectives: expected shape ({n}, m), got {values.shape}")
        if mode == "multi" and values.shape[1] != self.n_objectives:
            raise ValueError(
                f"objectives: 'multi' mode expects {self.n_objectives} columns, "
                f"got {values.shape[1]}"
            )
        # a "single" generation ranks column 0 only; the others may be NaN (not computed)
        ranked = values if mode == "multi" else values[:, :1]
        if not np.all(np.isfinite(ranked)) or np.isinf(values).any():
            raise ValueError("objectives must be finite (NaN only in unranked columns)")
        return values


def _plain(values: np.ndarray) -> list[Any]:
    """``values`` (1-D or 2-D) as JSON lists, NaN (an objective not computed) as null; read
    back as NaN (numpy turns None into NaN in a float array)."""
    if values.ndim == 1:
        return json_floats(values.tolist())
    return [json_floats(row) for row in values.tolist()]


@dataclass(frozen=True)
class _Evaluated:
    """The last population told, with what was computed for it."""

    genomes: tuple[Genome, ...]
    objectives: np.ndarray
    labels: np.ndarray
    fitness: np.ndarray


def _int(value: Any) -> int:
    if isinstance(value, bool) or not isinstance(value, int):
        raise TypeError(f"expected an int, got {value!r}")
    return value


def _jsonable(value: Any) -> Any:
    """Numpy scalars in a nested dict/list (the bit generator state) as plain Python."""
    if isinstance(value, Mapping):
        return {str(k): _jsonable(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_jsonable(v) for v in value]
    if isinstance(value, np.integer):
        return int(value)
    if isinstance(value, np.floating):
        return float(value)
    if isinstance(value, float) and not math.isfinite(value):
        raise ValueError("non-finite value in state")
    return value
