"""What carries a deployed planner's result: the deployment with each part taken away.

    python benchmarks/tools/what_carries.py --robot swarm --out out/carries_swarm \
        planners/swarm-paper-dual-s{1,2,3}.json --label dual-s1 --label dual-s2 --label dual-s3

Runs ``mentor-bench`` (no baselines, no oracle) on the given genomes, once per row:

- the shipped deployment, with a pure pursuit of the same plan in the networks' place
  (``--pursuit``: one pursuit, since the seeds share their settings);
- the shipped deployment with one part left out: the plan on the scan map
  (``scan_map=null``), the split decisions (``decisions_per_period=1``), and each of its stages
  (``stages.<name>=null``, which drops a stage the genomes were trained with too);
- the networks alone (``--deployment none``: as trained, with the stages they were trained
  with).

Each run writes ``<out>/<row>/bench.json``; a run whose file is there already is read, not
run again (remove the folder to run it again). Then prints one Markdown table: per row the
success and SPL within the paper's 50 s, mean ± sd over the genomes (seeds), and their
difference to the shipped deployment. The split, pairs per family and workers are
``mentor-bench``'s (defaults: test, 20, 1).
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
from pathlib import Path
from typing import Any

from mentor_core.cli.bench import main as bench_main
from mentor_core.controller.deployment import load_deployment


def rows(robot: str) -> list[tuple[str, list[str]]]:
    """``(row, mentor-bench arguments)`` of each run (module docstring)."""
    shipped = load_deployment("shipped", robot)[0]
    out = [("shipped, and a pure pursuit of its plan", ["--deployment", "shipped", "--pursuit"])]
    leave = [("without the scan map's plan", "scan_map=null"),
             ("deciding once per trained period", "decisions_per_period=1")]  # fmt: skip
    leave += [(f"without the {name.replace('_', ' ')}", f"stages.{name}=null")
              for name in shipped.stages]  # fmt: skip
    out += [(row, ["--deployment", "shipped", "--set", setting]) for row, setting in leave]
    out.append(("the networks alone (as trained)", ["--deployment", "none"]))
    return out


def _scores(doc: dict[str, Any], kind: str) -> list[tuple[float, float]]:
    """(success, SPL) overall within 50 s of each contender of ``kind``."""
    return [(c["scores"]["paper"]["overall"]["success"], c["scores"]["paper"]["overall"]["spl"])
            for c in doc["contenders"] if c["kind"] == kind]  # fmt: skip


def _cell(values: list[float], percent: bool) -> str:
    scale = 100.0 if percent else 1.0
    mean = statistics.fmean(values) * scale
    spread = statistics.stdev(values) * scale if len(values) > 1 else 0.0
    return f"{mean:.1f} ± {spread:.1f} %" if percent else f"{mean:.3f} ± {spread:.3f}"


def table(results: list[tuple[str, dict[str, Any]]]) -> list[str]:
    """The Markdown table of the runs' ``bench.json`` documents (module docstring)."""
    lines = ["| run | success | SPL | success - shipped | SPL - shipped |",
             "| --- | --- | --- | --- | --- |"]  # fmt: skip
    base = _scores(results[0][1], "evolved")
    base_success = statistics.fmean(s for s, _ in base)
    base_spl = statistics.fmean(p for _, p in base)
    for row, doc in results:
        for kind, name in (("evolved", row), ("pursuit", "a pure pursuit of the same plan")):
            scores = _scores(doc, kind)
            if not scores:
                continue
            success = [s for s, _ in scores]
            spl = [p for _, p in scores]
            lines.append(
                f"| {name} | {_cell(success, True)} | {_cell(spl, False)} | "
                f"{100.0 * (statistics.fmean(success) - base_success):+.1f} | "
                f"{statistics.fmean(spl) - base_spl:+.3f} |"
            )
    return lines


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("genomes", nargs="+")
    p.add_argument("--robot", required=True)
    p.add_argument("--label", action="append", default=[])
    p.add_argument("--out", type=Path, required=True)
    p.add_argument("--split", default="test")
    p.add_argument("--pairs-per-family", default="20")
    p.add_argument("--workers", default="1")
    args = p.parse_args(argv)
    labels = [x for label in args.label for x in ("--label", label)]
    results = []
    for k, (row, extra) in enumerate(rows(args.robot)):
        folder = args.out / f"run{k}"
        if not (folder / "bench.json").is_file():
            code = bench_main([*args.genomes, *labels, "--robot", args.robot, "--split",
                               args.split, "--pairs-per-family", args.pairs_per_family,
                               "--workers", args.workers, "--baselines", "none", "--no-oracle",
                               *extra, "--out", str(folder), "--force"])  # fmt: skip
            if code:
                return code
        results.append((row, json.loads((folder / "bench.json").read_text())))
    print(f"{args.robot}, {args.split} split, {args.pairs_per_family} pairs per family, "
          f"within 50 s; mean ± sd over {len(args.genomes)} genomes")
    print("\n".join(table(results)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
