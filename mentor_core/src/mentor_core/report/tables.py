"""The numbers and Markdown tables of the report: per-run numbers, genome tables, and the
formatting helpers of table cells."""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from mentor_core.evolution.genome import Genome
from mentor_core.report.figures import node_labels
from mentor_core.report.runs import RunData


def _fmt(x: float, digits: int = 3) -> str:
    return "-" if x is None or not math.isfinite(x) else f"{x:.{digits}f}"


def _pct(x: float) -> str:
    return "-" if not math.isfinite(x) else f"{100 * x:.0f}%"


def _spread(values: Sequence[float], fmt: Callable[[float], str]) -> str:
    v = np.asarray([x for x in values if math.isfinite(x)], dtype=np.float64)
    if not v.size:
        return "-"
    if v.size == 1:
        return fmt(float(v[0]))
    return f"{fmt(float(v.mean()))} ± {fmt(float(v.std(ddof=1)))}"


def _md_table(header: Sequence[str], rows: Sequence[Sequence[str]]) -> list[str]:
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(r) + " |" for r in rows]
    return [*lines, ""]


@dataclass(frozen=True)
class RunNumbers:
    """The numbers the report gives for one run."""

    evaluations: int
    best_F: float
    best_G: float
    best_success_rate: float
    species: int
    max_niche_share: float


def run_numbers(run: RunData) -> RunNumbers:
    """Final evaluations, best F and G (last generation), best success rate, final species
    count and the largest niche share over all generations."""
    last = run.history[-1]
    return RunNumbers(
        evaluations=last.evaluations,
        best_F=last.best_F,
        best_G=last.best_G,
        best_success_rate=last.best_success_rate,
        species=last.species,
        max_niche_share=max(r.largest_niche_share for r in run.history),
    )


def genome_tables(
    genome: Genome, encoding: str = "paper", feedback_action: bool = False
) -> list[str]:
    """Markdown tables of a genome's nodes and connection genes."""
    labels = node_labels(genome, encoding, feedback_action)
    lines = _md_table(
        ["node", "name", "kind", "activation"],
        [[str(n.id), labels[n.id], n.kind, n.activation] for n in genome.nodes],
    )
    lines += _md_table(
        ["innovation", "from", "to", "weight", "enabled"],
        [
            [str(c.innovation), labels[c.in_node], labels[c.out_node], f"{c.weight:+.4f}",
             "yes" if c.enabled else "no"]
            for c in genome.connections
        ],
    )  # fmt: skip
    return lines


__all__ = [
    "genome_tables",
    "run_numbers",
]
