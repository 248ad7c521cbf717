"""The experience gain's share of a whole training run, measured inside the run.

    NUMBA_NUM_THREADS=2 .venv/bin/python benchmarks/perf/g_share.py --seed 1 --out out/g_share \\
        [-- mentor-train options, default: --robot ugv --framework dual --config paper]

Runs ``mentor-train`` in this process with the trainer's
:func:`~mentor_core.objectives.experience.experience_gains_packed` wrapped in a wall-clock
timer, then prints the seconds spent in it against the run's generations (``history.csv``'s
``seconds``), per stage: in a dual run's stage 1 every genome's G is ranked; in stage 2 (and
every generation of the single framework) only the best genome's is computed, and the last
generation computes every G for the final files (``docs/algorithm.md``, "G where it is
ranked"). ``benchmarks/perf/generation_bench.py`` times one generation of evolved-looking genomes
instead; this is the share in a real run, whose genomes' experience grows as they learn.
It switches off the in-process evaluator's overlap (``training.gain_overlap``), so that every G
is computed after its simulation, in the calling thread, where the timer sees it;
``benchmarks/perf/g_overlap.py`` measures G's cost with the overlap.
"""

from __future__ import annotations

import argparse
import csv
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import mentor_core.training.problem as problem
from mentor_core.cli.train import main as mentor_train
from mentor_core.training.gain_overlap import GainOverlap


def run(seed: int, out: Path, train_args: Sequence[str]) -> list[tuple[int, float, int]]:
    """Train into ``out``; the timed calls as (point sets, seconds, points)."""
    calls: list[tuple[int, float, int]] = []
    inner = problem.experience_gains_packed

    def timed(points: Any, offsets: Any, *args: Any, **kwargs: Any) -> Any:
        start = time.perf_counter()
        gains = inner(points, offsets, *args, **kwargs)
        calls.append((len(offsets) - 1, time.perf_counter() - start,
                      int(offsets[-1]) - int(offsets[0])))
        return gains

    problem.experience_gains_packed = timed  # type: ignore[assignment]
    available = GainOverlap.__dict__["available"]  # the staticmethod itself
    GainOverlap.available = staticmethod(lambda: False)  # type: ignore[method-assign]
    try:
        mentor_train([*train_args, "--seed", str(seed), "--out", str(out), "--quiet"])
    except SystemExit as stop:
        if stop.code:
            raise
    finally:
        problem.experience_gains_packed = inner
        GainOverlap.available = available
    return calls


def main(argv: Sequence[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--out", type=Path, required=True, help="a new run directory")
    parser.add_argument("train", nargs="*",
                        default=["--robot", "ugv", "--framework", "dual", "--config", "paper"],
                        help="mentor-train options (after --)")  # fmt: skip
    args = parser.parse_args(argv)
    calls = run(args.seed, args.out, args.train)
    with open(args.out / "history.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    stages: dict[str, float] = {}
    for row in rows:
        stages[row["stage"]] = stages.get(row["stage"], 0.0) + float(row["seconds"])
    total = sum(stages.values())
    spent = sum(s for _, s, _ in calls)
    full = [(n, s, p) for n, s, p in calls[:-1] if n > 1]  # the last call: the final files
    ranked = sum(s for _, s, _ in full)
    print(f"generations {total:.1f} s; experience gain {spent:.2f} s "
          f"({100 * spent / total:.1f} %) in {len(calls)} calls")
    if len(stages) > 1:
        first = stages[rows[0]["stage"]]
        points = sum(p for _, _, p in full) / max(1, sum(n for n, _, _ in full))
        print(f"stage 1: {ranked:.2f} s of {first:.1f} s ({100 * ranked / first:.1f} %), "
              f"{points:.0f} points a genome; best-only calls "
              f"{sum(s for n, s, _ in calls if n == 1):.2f} s; final generation's "
              f"{calls[-1][1]:.2f} s ({calls[-1][2] / calls[-1][0]:.0f} points a genome)")


if __name__ == "__main__":
    main()
