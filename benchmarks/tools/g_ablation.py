"""Does the experience gain help? The arms of a study side by side, on unseen worlds.

    STUDY_PAIRS=0 scripts/study.sh out/study "1 2 3 4 5" 2 \
        "original paper benchmarks/configs/simplicity:dual"
    python benchmarks/tools/g_ablation.py out/study --bench --pairs-per-family 20 --workers 2

Reads a ``scripts/study.sh`` folder that trained the shipped config (``paper``) in both
frameworks and ``benchmarks/configs/simplicity`` in the dual stage, and prints one Markdown
table per robot: for each arm -- MENTOR (``paper``, dual: F and the experience gain G, then F),
G removed (``simplicity``, dual: F and the network's simplicity, then F) and the single stage
(``paper``, single: F alone, this implementation's NEAT with one objective) -- the success on
the benchmark's test split (as deployed, ``--deployment shipped``, and the networks alone) and
on the unseen bags (the study's ``eval_unseen_<robot>.json``, plain and deployed), mean ± sd
over the seeds, and the two-sided Mann-Whitney p-value of each arm against MENTOR. Every arm
runs the same evaluations (population x generations x scenarios).

``--bench`` first runs ``mentor-bench`` on the arms' genomes (no baselines: the headline table
of ``benchmarks/RESULTS.md`` has them on the same split) into
``<study>/ablation_<robot>/{deployed,plain}``; a folder whose ``bench.json`` is there already
is read, not run again. Issue 55, point 4; experiment E090.
"""

from __future__ import annotations

import argparse
import math
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from mentor_core.benchmark.document import load_bench
from mentor_core.cli.bench import main as bench_main
from mentor_core.report.significance import compare, p_text
from mentor_core.report.study import ROBOTS, Study, bench_success, load_study

ARMS = (("MENTOR: F and G, dual", "paper", "dual"),
        ("G removed: F and simplicity, dual", "simplicity", "dual"),
        ("F alone: single stage", "paper", "single"))  # fmt: skip
RUNS = {"deployed": ["--deployment", "shipped"], "plain": []}


def _label(config: str, framework: str, seed: int) -> str:
    return f"{config}-{framework}-s{seed}"


def run_benches(study: Study, robot: str, pairs: int, workers: int) -> None:
    """``mentor-bench`` of every arm's genomes, deployed and plain (module docstring)."""
    genomes: list[str] = []
    labels: list[str] = []
    for _, config, framework in ARMS:
        for run in study.group(config, robot, framework):
            genomes.append(str(run.path / "best_genome.json"))
            labels += ["--label", _label(config, framework, run.seed)]
    args = [*genomes, *labels]
    for name, flags in RUNS.items():
        out = study.root / f"ablation_{robot}" / name
        if (out / "bench.json").is_file():
            continue
        code = bench_main([*args, "--robot", robot, "--split", "test", "--pairs-per-family",
                           str(pairs), "--baselines", "none", "--no-oracle", "--workers",
                           str(workers), *flags, "--out", str(out)])  # fmt: skip
        if code:
            raise SystemExit(code)


def columns(study: Study, robot: str, config: str, framework: str) -> list[list[float]]:
    """The arm's success per seed in each column (test deployed, test plain, bags plain, bags
    deployed); an empty list where the study lacks it."""
    docs = {name: _read(study.root / f"ablation_{robot}" / name / "bench.json")
            for name in RUNS}  # fmt: skip
    bags = [r.summary["success_rate"] for r in study.unseen_runs(config, robot, framework)]
    deployed = [r.summary["success_rate"]
                for r in study.unseen_runs(config, robot, framework, deployed=True)]  # fmt: skip
    return [bench_success(docs["deployed"], config, framework),
            bench_success(docs["plain"], config, framework), bags, deployed]  # fmt: skip


def _read(path: Path) -> dict[str, Any] | None:
    return load_bench(path) if path.is_file() else None


def _cell(values: Sequence[float], mentor: Sequence[float], first: bool) -> str:
    v = np.asarray([x for x in values if math.isfinite(x)])
    if not v.size:
        return "-"
    text = f"{100 * v.mean():.1f} ± {100 * v.std(ddof=1) if v.size > 1 else 0.0:.1f} %"
    return text if first else f"{text} ({p_text(compare(values, mentor))})"


def table(study: Study, robot: str) -> list[str]:
    """The Markdown table of one robot (module docstring)."""
    header = ["arm", "seeds", "test split, deployed", "test split, network alone",
              "unseen bags, plain", "unseen bags, deployed"]  # fmt: skip
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    mentor = columns(study, robot, "paper", "dual")
    for k, (name, config, framework) in enumerate(ARMS):
        cols = columns(study, robot, config, framework)
        seeds = ", ".join(str(r.seed) for r in study.group(config, robot, framework)) or "-"
        cells = [_cell(c, m, k == 0) for c, m in zip(cols, mentor, strict=True)]
        lines.append("| " + " | ".join([name, seeds, *cells]) + " |")
    return lines


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("study", type=Path)
    p.add_argument("--bench", action="store_true", help="run the benchmarks first")
    p.add_argument("--pairs-per-family", type=int, default=20)
    p.add_argument("--workers", type=int, default=1)
    p.add_argument("--robot", choices=ROBOTS, action="append", help="(default: both)")
    args = p.parse_args(argv)
    study = load_study(args.study)
    for robot in args.robot or ROBOTS:
        if args.bench:
            run_benches(study, robot, args.pairs_per_family, args.workers)
        print(f"\n{robot}: success within 50 s, mean ± sd over the seeds (p: Mann-Whitney U "
              "against MENTOR, two-sided)\n")  # fmt: skip
        print("\n".join(table(study, robot)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
