"""``mentor-xor``: the XOR benchmark of NEAT (Stanley & Miikkulainen 2002) run with MENTOR.

Each run evolves a population (default ``configs/xor.yaml``: 150 genomes, at most 100
generations) in single-objective mode on fitness ``4 - sum of squared errors`` over the four
XOR cases (output through the sigmoid). A genome solves XOR when all four outputs lie on the
right side of 0.5. The evaluation count of a run counts every genome of every generation
evaluated up to and including the first generation that holds a solver: the reference's
accounting (NEAT: 100 of 100 runs solved, 4,755 evaluations on average, 2.35 hidden nodes).

Run ``i`` uses seed ``seed + i``; runs are independent, so ``--workers`` gives the same JSON as
a serial run. Prints one JSON object::

    {"runs", "solved", "evaluations": {"mean", "median", "max"}, "hidden_nodes_mean", ...}

with the evaluation statistics over the solved runs.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from collections.abc import Sequence
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from mentor_core.cli.arguments import Parser, seed
from mentor_core.errors import MentorError
from mentor_core.evolution.config import EvolutionConfig
from mentor_core.evolution.genome import Genome
from mentor_core.evolution.loop import Evolution
from mentor_core.evolution.network import FeedForwardNetwork

XOR_INPUTS = np.array([[0.0, 0.0], [0.0, 1.0], [1.0, 0.0], [1.0, 1.0]])
XOR_TARGETS = np.array([0.0, 1.0, 1.0, 0.0])
#: NEAT's published XOR result (Stanley & Miikkulainen 2002), for comparison in the output.
REFERENCE = {"runs": 100, "solved": 100, "evaluations_mean": 4755, "hidden_nodes_mean": 2.35}


def xor_outputs(genome: Genome) -> np.ndarray:
    """The genome's output on the four XOR cases, shape (4,)."""
    return FeedForwardNetwork.from_genome(genome).activate(XOR_INPUTS)[:, 0]


def xor_fitness(outputs: np.ndarray) -> float:
    """``4 - sum of squared errors`` (4 is perfect)."""
    return float(4.0 - np.sum((outputs - XOR_TARGETS) ** 2))


def xor_solved(outputs: np.ndarray) -> bool:
    """All four outputs strictly on the right side of 0.5 (> 0.5 for 1, < 0.5 for 0)."""
    return bool(np.all(np.where(XOR_TARGETS > 0.5, outputs > 0.5, outputs < 0.5)))


@dataclass(frozen=True)
class XorRun:
    """Outcome of one seeded run."""

    seed: int
    solved: bool
    generations: int  # generations evaluated (including the solving one)
    evaluations: int  # genomes evaluated
    fitness: float  # of the first solver (or the best genome if unsolved)
    hidden_nodes: int  # of the same genome
    enabled_connections: int


def run_xor(config: EvolutionConfig, seed: int, max_generations: int | None = None) -> XorRun:
    """One XOR run: evolve until a generation holds a solver or the generation limit."""
    evolution = Evolution(config, n_inputs=2, n_outputs=1, seed=seed, objectives=1)
    limit = config.generations if max_generations is None else max_generations
    best: tuple[float, Genome] | None = None
    for _ in range(limit):
        genomes = evolution.ask()
        outputs = [xor_outputs(g) for g in genomes]
        fitness = np.array([xor_fitness(o) for o in outputs])
        solvers = [i for i, o in enumerate(outputs) if xor_solved(o)]
        evolution.tell(fitness[:, None], mode="single")
        if solvers:
            # the fittest solver of the generation (lowest index on ties)
            i = max(solvers, key=lambda k: (fitness[k], -k))
            return XorRun(
                seed=seed,
                solved=True,
                generations=evolution.generation,
                evaluations=evolution.evaluations,
                fitness=float(fitness[i]),
                hidden_nodes=len(genomes[i].hidden_nodes),
                enabled_connections=len(genomes[i].enabled_connections),
            )
        i = int(np.argmax(fitness))
        if best is None or fitness[i] > best[0]:
            best = (float(fitness[i]), genomes[i])
    if best is None:
        raise ValueError(f"max_generations must be >= 1, got {limit}")
    return XorRun(
        seed=seed,
        solved=False,
        generations=evolution.generation,
        evaluations=evolution.evaluations,
        fitness=best[0],
        hidden_nodes=len(best[1].hidden_nodes),
        enabled_connections=len(best[1].enabled_connections),
    )


def _run_task(args: tuple[EvolutionConfig, int, int | None]) -> XorRun:
    return run_xor(*args)


def benchmark(
    config: EvolutionConfig,
    runs: int,
    seed: int = 0,
    workers: int = 1,
    max_generations: int | None = None,
) -> list[XorRun]:
    """``runs`` independent runs with seeds ``seed .. seed + runs - 1``, in seed order."""
    tasks = [(config, seed + i, max_generations) for i in range(runs)]
    if workers <= 1:
        return [_run_task(t) for t in tasks]
    with ProcessPoolExecutor(max_workers=workers) as pool:
        return list(pool.map(_run_task, tasks))


def summarize(results: Sequence[XorRun]) -> dict[str, Any]:
    """The benchmark's JSON summary (evaluation and topology statistics over solved runs)."""
    solved = [r for r in results if r.solved]
    evaluations = np.array([r.evaluations for r in solved], dtype=np.float64)

    def stat(values: np.ndarray, fn: Any) -> float | None:
        return float(fn(values)) if values.size else None

    return {
        "runs": len(results),
        "solved": len(solved),
        "evaluations": {
            "mean": stat(evaluations, np.mean),
            "median": stat(evaluations, np.median),
            "max": stat(evaluations, np.max),
            "min": stat(evaluations, np.min),
        },
        "generations_mean": stat(np.array([r.generations for r in solved], float), np.mean),
        "hidden_nodes_mean": stat(np.array([r.hidden_nodes for r in solved], float), np.mean),
        "enabled_connections_mean": stat(
            np.array([r.enabled_connections for r in solved], float), np.mean
        ),
        "fitness_mean": stat(np.array([r.fitness for r in solved], float), np.mean),
        "unsolved_seeds": [r.seed for r in results if not r.solved],
        "reference": REFERENCE,
    }


def _parser() -> argparse.ArgumentParser:
    parser = Parser(
        prog="mentor-xor", description="XOR benchmark of MENTOR (NEAT's classic test)."
    )
    parser.add_argument("--runs", type=int, default=100, help="number of runs (default 100)")
    parser.add_argument(
        "--seed", type=seed, default=0, help="seed of run 0, >= 0 (run i: seed + i)"
    )
    parser.add_argument(
        "--workers", type=int, default=1, help="worker processes (same result as serial)"
    )
    parser.add_argument(
        "--config", type=Path, default=None, help="evolution config YAML (default: xor.yaml)"
    )
    parser.add_argument(
        "--generations", type=int, default=None, help="generation limit (default: config)"
    )
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of ``mentor-xor``: print the JSON summary; exit 2 on bad input."""
    args = _parser().parse_args(argv)
    if args.runs < 1 or args.workers < 1:
        print("mentor-xor: --runs and --workers must be >= 1", file=sys.stderr)
        return 2
    if args.generations is not None and args.generations < 1:
        print("mentor-xor: --generations must be >= 1", file=sys.stderr)
        return 2
    try:
        config = (
            EvolutionConfig.packaged("xor")
            if args.config is None
            else EvolutionConfig.from_yaml(args.config)
        )
    except MentorError as err:
        print(f"mentor-xor: {err}", file=sys.stderr)
        return 2
    start = time.perf_counter()
    results = benchmark(config, args.runs, args.seed, args.workers, args.generations)
    summary = summarize(results)
    summary["seconds"] = round(time.perf_counter() - start, 1)
    print(json.dumps(summary))
    return 0


if __name__ == "__main__":
    sys.exit(main())
