"""How long the generalisation benchmark takes (mentor-bench, issue 15).

    .venv/bin/python benchmarks/perf/generalisation_bench.py [--split validation]
        [--pairs-per-family 20] [--genome ugv=PATH --genome swarm=PATH]

Per robot: building the suite (worlds, solvable pairs, shortest paths), then one run of each
planner on it: an evolved genome (default: the shipped regression reference genomes), the
baselines and the oracle. Times are wall-clock seconds in this process (numba kernels warmed
up first, on a two-pair suite).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from mentor_core.benchmark.contenders import HAND_WRITTEN, evolved, hand_written
from mentor_core.benchmark.runner import run_contender
from mentor_core.benchmark.suite import build_suite
from mentor_core.sim.robots import get_profile

ROOT = Path(__file__).resolve().parents[2]
DEFAULT_GENOMES = {r: ROOT / "bags" / "regression" / f"{r}_reference_genome.json"
                   for r in ("ugv", "swarm")}  # fmt: skip


def chosen_genomes(items: list[str]) -> dict[str, Path]:
    """The genome per robot: the regression reference genomes, each ``ROBOT=PATH`` of
    ``--genome`` in its robot's place."""
    genomes = dict(DEFAULT_GENOMES)
    for item in items:
        robot, _, path = item.partition("=")
        genomes[robot] = Path(path)
    return genomes


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--split", default="validation")
    p.add_argument("--pairs-per-family", type=int, default=20)
    p.add_argument("--genome", action="append", default=[], metavar="ROBOT=PATH")
    args = p.parse_args(argv)
    genomes = chosen_genomes(args.genome)
    print(f"| robot | pairs | suite s | {' s | '.join(['evolved', *HAND_WRITTEN])} s |")
    print("|---|---|---|" + "---|" * (1 + len(HAND_WRITTEN)))
    for robot, path in genomes.items():
        profile = get_profile(robot)
        warm = build_suite(profile, args.split, ["doe"], 2)
        run_contender(warm, evolved(path, profile))
        t0 = time.perf_counter()
        suite = build_suite(profile, args.split, pairs_per_family=args.pairs_per_family)
        cells = [f"{time.perf_counter() - t0:.1f}"]
        for contender in [evolved(path, profile)] + [hand_written(n, suite.reference)
                                                     for n in HAND_WRITTEN]:  # fmt: skip
            t0 = time.perf_counter()
            result = run_contender(suite, contender)
            overall = result.scores["paper"]["overall"]["success"]
            cells.append(f"{time.perf_counter() - t0:.1f} ({overall:.0%})")
        print(f"| {robot} | {len(suite.pairs)} | " + " | ".join(cells) + " |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
