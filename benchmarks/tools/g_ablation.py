"""Does the experience gain help? The arms of a study side by side, on unseen worlds.

    python benchmarks/tools/g_ablation.py out/study

Reads a ``scripts/study.sh`` folder that trained the shipped config (``paper``) in both
frameworks and ``benchmarks/configs/simplicity`` in the dual stage, and prints one Markdown
table per robot: for each arm -- MENTOR (``paper``, dual: F and the experience gain G, then F),
G removed (``simplicity``, dual: F and the network's simplicity, then F) and the single stage
(``paper``, single: F alone, this implementation's NEAT with one objective) -- the success on
the benchmark's test split (deployed, ``bench_<robot>``; the networks alone,
``bench_<robot>_plain``) and on the unseen bags (plain and deployed), mean ± sd over the
seeds, and the two-sided Mann-Whitney p-value of each arm against MENTOR. Every arm runs the
same evaluations (population x generations x scenarios). Issue 55, point 4; experiment E090.
"""

from __future__ import annotations

import argparse
import math
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from mentor_core.report.significance import compare, p_text
from mentor_core.report.study import Study, load_study

ARMS = (("MENTOR: F and G, dual", "paper", "dual"),
        ("G removed: F and simplicity, dual", "simplicity", "dual"),
        ("F alone: single stage", "paper", "single"))  # fmt: skip


def _bench(doc: dict[str, Any] | None, config: str, framework: str) -> list[float]:
    if doc is None:
        return []
    prefix = f"{config}-{framework}-s"
    found = sorted(
        (int(c["name"][len(prefix):]), c)
        for c in doc["contenders"]
        if c["name"].startswith(prefix) and c["name"][len(prefix):].isdigit()
    )
    values = [c["scores"]["paper"]["overall"]["success"] for _, c in found]
    return [math.nan if v is None else float(v) for v in values]


def columns(study: Study, robot: str, config: str, framework: str) -> list[list[float]]:
    """The arm's success per seed in each column (test deployed, test plain, bags plain, bags
    deployed); an empty list where the study lacks it."""
    bags = [r.summary["success_rate"] for r in study.unseen_runs(config, robot, framework)]
    deployed = [r.summary["success_rate"]
                for r in study.unseen_runs(config, robot, framework, deployed=True)]  # fmt: skip
    return [_bench(study.bench.get(robot), config, framework),
            _bench(study.bench_plain.get(robot), config, framework), bags, deployed]  # fmt: skip


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
    args = p.parse_args(argv)
    study = load_study(args.study)
    for robot, name in (("ugv", "UGV"), ("swarm", "Swarm-Robot")):
        print(f"\n{name}: success within 50 s, mean ± sd over the seeds (p: Mann-Whitney U "
              "against MENTOR, two-sided)\n")  # fmt: skip
        print("\n".join(table(study, robot)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
