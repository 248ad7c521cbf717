"""The experience gain's cost to a training generation, with and without the overlap.

    NUMBA_NUM_THREADS=2 python benchmarks/perf/g_overlap.py --seed 1 --out out/g_overlap \\
        [--robot ugv] [--framework dual] [--config paper]

Trains in this process. In every generation that computes every genome's G (a dual run's
stage 1 and the final generation), the evaluator evaluates the same genomes three ways, in an
order that rotates from one generation to the next: as shipped, G on background threads while
the rest is simulated (``training.gain_overlap``; the run goes on with this result); G after
the simulation, in the calling thread on all of numba's threads (as before the overlap); and the
simulation alone, without G. The three evaluations give the same objectives (checked). Per
generation, G's cost is an evaluation's time less the simulation's, and a generation's time is
its ``history.csv`` seconds less the two extra measurements. Prints, for the stage-1
generations, the medians and G's share of a generation both ways, side by side on the same
genomes in the same minutes.
"""

from __future__ import annotations

import argparse
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from mentor_core.cli.train import resolve_run
from mentor_core.evolution.genome import Genome
from mentor_core.training.evaluators import InProcessEvaluator
from mentor_core.training.problem import Evaluation, GainScope, NavigationProblem
from mentor_core.training.run_files import history_from_csv
from mentor_core.training.trainer import make_problem, train


class Measuring(InProcessEvaluator):
    """The in-process evaluator that also times the two other ways (module docstring)."""

    def __init__(self, problem: NavigationProblem) -> None:
        super().__init__(problem)
        self.rows: list[dict[str, float]] = []

    def evaluate(self, genomes: Sequence[Genome], gains: GainScope = "all") -> Evaluation:
        if gains != "all" or self._overlap is None:
            return super().evaluate(genomes, gains)
        ways: dict[str, Any] = {
            "overlap": lambda: self.problem.evaluate(genomes, gains, self._overlap),
            "after": lambda: self.problem.evaluate(genomes, gains),
            "simulation": lambda: self.problem.simulate(genomes),
        }
        names = list(ways)
        turn = len(self.rows) % len(names)
        row: dict[str, float] = {}
        results: dict[str, Any] = {}
        for name in names[turn:] + names[:turn]:
            start = time.perf_counter()
            results[name] = ways[name]()
            row[name] = time.perf_counter() - start
        if not np.array_equal(results["overlap"].objectives, results["after"].objectives):
            raise AssertionError("the overlap changed the objectives")
        self.rows.append(row)
        overlapped: Evaluation = results["overlap"]
        return overlapped


def main(argv: Sequence[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--out", type=Path, required=True, help="a new run directory")
    parser.add_argument("--robot", default="ugv")
    parser.add_argument("--framework", default="dual")
    parser.add_argument("--config", default="paper")
    args = parser.parse_args(argv)
    config, _ = resolve_run(args.robot, args.framework, args.config, [])
    problem = make_problem(config, source=args.config)
    evaluator = Measuring(problem)
    if evaluator._overlap is None:
        raise SystemExit("g_overlap: the overlap needs numba and NUMBA_NUM_THREADS >= 2")
    with evaluator:
        train(config, args.out, seed=args.seed, evaluator=evaluator)
    history = history_from_csv((args.out / "history.csv").read_text())
    seconds = [r.seconds for r in history]
    # the rows are the generations of every G: stage 1's, then the final generation's
    stage1 = evaluator.rows[:-1]
    gens = [s - r["after"] - r["simulation"] for s, r in zip(seconds, stage1, strict=False)]
    after = [g - r["overlap"] + r["after"] for g, r in zip(gens, stage1, strict=True)]
    cost_overlap = [r["overlap"] - r["simulation"] for r in stage1]
    cost_after = [r["after"] - r["simulation"] for r in stage1]

    def med(values: Sequence[float]) -> float:
        return float(np.median(values))

    share_o = [c / g for c, g in zip(cost_overlap, gens, strict=True)]
    share_a = [c / g for c, g in zip(cost_after, after, strict=True)]
    print(f"{len(stage1)} stage-1 generations, medians (s):")
    print(f"  simulation alone {med([r['simulation'] for r in stage1]):.3f}")
    print(f"  evaluation, G after the simulation {med([r['after'] for r in stage1]):.3f}; "
          f"G's cost {med(cost_after):.3f}; generation {med(after):.3f}; "
          f"G's share {100 * med(share_a):.1f} %")
    print(f"  evaluation, G overlapped {med([r['overlap'] for r in stage1]):.3f}; "
          f"G's cost {med(cost_overlap):.3f}; generation {med(gens):.3f}; "
          f"G's share {100 * med(share_o):.1f} %")
    print(f"  generation after / overlapped: {med(after) / med(gens):.3f}")


if __name__ == "__main__":
    main()
