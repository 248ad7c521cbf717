"""Where a planner's SPL goes: to the pairs it fails, or to the length of the paths it takes.

SPL (Anderson et al. 2018) factors exactly into the success rate and a path efficiency ``E``:

    SPL = (1 / N) sum_i S_i l_i / max(p_i, l_i) = (n_S / N) E,
    E = (1 / n_S) sum_{i : S_i} l_i / max(p_i, l_i)

(``l_i`` the shortest path, ``p_i`` the path taken, ``n_S`` the pairs reached), so a planner
level with a baseline on success but behind it on SPL is behind it on ``E``: its paths are
longer. ``E`` alone does not tell whether every path is a little longer or a few are much
longer. Over the reached pairs, the median of ``max(p_i, l_i) / l_i`` says the first, the
share beyond :data:`DETOUR` times the shortest the second.

A planner that fails the hard pairs has its ``E`` over the easy ones, so two planners'
paths are compared on the pairs both reached (:func:`paired_efficiency`): each evolved
planner (its seeds pooled, each seed on the pairs it and the baseline reached) against the
baseline that sets the head to head's SPL bar in each family
(:mod:`~mentor_core.report.head_to_head`). experiment E077, "Twice the population,
..., and where the UGV's sparse-forest SPL goes", has what it showed.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from mentor_core.report.head_to_head import _families, head_to_head, per_pair
from mentor_core.report.seed_groups import evolved_planners
from mentor_core.report.tables import _md_table

#: a reached pair's path counts as a detour beyond this many times its shortest path
DETOUR = 1.25


@dataclass(frozen=True)
class PathEfficiency:
    """How long the paths of some reached pairs were.

    Attributes:
        reached: the pairs reached.
        efficiency: ``E``, the mean of ``l / max(p, l)`` over them (module docstring); NaN
            where none was reached.
        median_ratio: the median of ``max(p, l) / l`` over them (NaN where none).
        detour_share: the share of them with ``max(p, l) / l > DETOUR`` (NaN where none).
    """

    reached: int
    efficiency: float
    median_ratio: float
    detour_share: float


@dataclass(frozen=True)
class PairedEfficiency:
    """An evolved planner's paths and a baseline's, on the pairs of one family (or
    ``overall``) that both reached."""

    family: str
    baseline: str
    mine: PathEfficiency
    theirs: PathEfficiency


def path_efficiency(success: ArrayLike, spl_terms: ArrayLike) -> PathEfficiency:
    """The :class:`PathEfficiency` of pairs with per-pair ``success`` (bool or 0/1) and SPL
    terms ``S_i l_i / max(p_i, l_i)`` (``benchmark.scores.spl``; 1 for a reached pair with
    ``l = 0``)."""
    ok = np.asarray(success, dtype=bool)
    terms = np.asarray(spl_terms, dtype=np.float64)[ok]
    if terms.size == 0:
        return PathEfficiency(0, math.nan, math.nan, math.nan)
    ratios = 1.0 / terms  # max(p, l) / l: a reached pair's term is in (0, 1]
    return PathEfficiency(
        reached=int(terms.size), efficiency=float(terms.mean()),
        median_ratio=float(np.median(ratios)), detour_share=float(np.mean(ratios > DETOUR)),
    )  # fmt: skip


def paired_efficiency(
    doc: Mapping[str, Any], limit: str = "paper"
) -> dict[str, list[PairedEfficiency]]:
    """Per evolved planner of a ``mentor-bench`` document (keys as ``head_to_head``'s), a
    :class:`PairedEfficiency` per family and ``overall`` against the baseline of the highest
    SPL there, under ``limit`` (module docstring). Planners or baselines whose per-pair
    results do not add up to their scores (``head_to_head.per_pair``: a document of an older
    version) are left out; empty without a baseline."""
    contenders = doc["contenders"]
    by_name = {str(c["name"]): c for c in contenders}
    planners = evolved_planners(contenders)
    families = _families(doc)
    baselines: dict[str, Any] = {}  # a baseline's per-pair results, once for all planners
    out: dict[str, list[PairedEfficiency]] = {}
    for name, matches in head_to_head(doc, limit).items():
        found = [per_pair(doc, contenders[i], limit) for i in planners[name]]
        seeds = [v for v in found if v is not None]
        if len(seeds) < len(found):
            continue
        rows = []
        for m in matches:
            if m.best_spl_by in by_name and m.best_spl_by not in baselines:
                baselines[m.best_spl_by] = per_pair(doc, by_name[m.best_spl_by], limit)
            theirs = baselines.get(m.best_spl_by)
            if theirs is None:
                continue
            where = np.ones(families.size, bool) if m.family == "overall" else (
                families == m.family)  # fmt: skip
            both = [where & (v["success"] > 0) & (theirs["success"] > 0) for v in seeds]
            mine = np.concatenate([v["spl"][b] for v, b in zip(seeds, both, strict=True)])
            base = np.concatenate([theirs["spl"][b] for b in both])
            rows.append(PairedEfficiency(m.family, m.best_spl_by, path_efficiency(
                mine > 0, mine), path_efficiency(base > 0, base)))
        if rows:
            out[name] = rows
    return out


def _cell(e: PathEfficiency) -> str:
    if e.reached == 0:
        return "-"
    return f"{e.efficiency:.2f} · {e.median_ratio:.2f} · {100 * e.detour_share:.0f} %"


def efficiency_markdown(doc: Mapping[str, Any], limit: str = "paper") -> list[str]:
    """:func:`paired_efficiency` as Markdown lines, a table per evolved planner (none where
    there is nothing to compare): per family, the pairs both reached (over the planner's
    seeds), then each one's ``E · median path / shortest · share of detours`` on them."""
    md: list[str] = []
    for name, rows in paired_efficiency(doc, limit).items():
        md += _md_table(
            ["family", "pairs both reached", f"`{name}`", "baseline of the highest SPL"],
            [[f"**{r.family}**" if r.family == "overall" else r.family, str(r.mine.reached),
              _cell(r.mine), f"{_cell(r.theirs)} ({r.baseline})"] for r in rows],
        )  # fmt: skip
    return md


__all__ = ["DETOUR", "PairedEfficiency", "PathEfficiency", "efficiency_markdown",
           "paired_efficiency", "path_efficiency"]
