"""The paper's Figs. 7-18 redrawn from a study, one PNG per figure, one panel per config.

Each function takes, per config, the runs of one robot (and framework) and returns a figure
whose panels sit side by side (the configs in the order given), so a reader holds it beside
the paper's figure of the same number:

* :func:`pareto_panels` -- Figs. 7 and 13: F against G of the dual stage's first stage, every
  seed's front;
* :func:`convergence_panels` -- Figs. 8 and 14: best F against evaluations, single and dual
  stage, the mean over the seeds and their range;
* :func:`niche_panels` -- Figs. 9-10 and 15-16: the first seed's niche sizes (stacked), every
  seed's largest share, and the paper's range shaded;
* :func:`complexity_panels` -- Figs. 11-12 and 17-18: F of every seed's final population per
  complexity bin.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import matplotlib as mpl
import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from mentor_core.report.figures import _figure, complexity_bins, niche_share_matrix
from mentor_core.report.paper_claims import NICHE_RANGE, final_population
from mentor_core.report.runs import RunData

Panels = Mapping[str, Sequence[RunData]]
_FRAMEWORK_COLOURS = {"single": "tab:blue", "dual": "tab:orange"}


def _panels(n: int, title: str) -> tuple[Figure, list[Axes]]:
    fig = _figure(5.2 * max(n, 1), 4.2)
    axes = [fig.add_subplot(1, max(n, 1), k + 1) for k in range(max(n, 1))]
    fig.suptitle(title)
    return fig, axes


def pareto_panels(panels: Panels, title: str) -> Figure:
    """F against G of each dual run's Pareto file, every seed's first front joined."""
    fig, axes = _panels(len(panels), title)
    for ax, (config, runs) in zip(axes, panels.items(), strict=False):
        colours = mpl.colormaps["viridis"](np.linspace(0.1, 0.85, max(len(runs), 1)))
        for colour, run in zip(colours, runs, strict=True):
            pts = run.pareto_points
            ax.scatter(pts[:, 1], pts[:, 0], s=8, color=colour, alpha=0.3)
            front = pts[run.pareto_front]
            order = np.argsort(front[:, 1])
            ax.plot(front[order, 1], front[order, 0], "-o", color=colour, ms=4, lw=1.2,
                    label=f"seed {run.seed}")  # fmt: skip
        _labels(ax, config, "experience gain G", "performance F")
    return fig


def convergence_panels(
    panels: Mapping[str, Mapping[str, Sequence[RunData]]], title: str
) -> Figure:
    """Best F against evaluations per framework: the mean over seeds, their range shaded."""
    fig, axes = _panels(len(panels), title)
    for ax, (config, by_framework) in zip(axes, panels.items(), strict=False):
        for framework, runs in by_framework.items():
            if not runs:
                continue
            length = min(len(r.history) for r in runs)
            evals = np.array([rec.evaluations for rec in runs[0].history[:length]])
            best = np.array([[rec.best_F for rec in r.history[:length]] for r in runs])
            colour = _FRAMEWORK_COLOURS[framework]
            ax.plot(evals, best.mean(axis=0), color=colour, lw=1.6,
                    label=f"{framework} stage ({len(runs)} seeds)")  # fmt: skip
            ax.fill_between(evals, best.min(axis=0), best.max(axis=0), color=colour, alpha=0.2)
        _labels(ax, config, "evaluations", "best performance F")
    return fig


def niche_panels(panels: Panels, robot: str, title: str) -> Figure:
    """The first seed's niche shares stacked, every seed's largest share, the paper's range."""
    fig, axes = _panels(len(panels), title)
    low, high = NICHE_RANGE[robot]
    for ax, (config, runs) in zip(axes, panels.items(), strict=False):
        if runs:
            first = runs[0]
            ids, shares = niche_share_matrix(first.history)
            gens = np.array([r.generation for r in first.history])
            cmap = mpl.colormaps["tab20"]
            ax.stackplot(gens, shares.T, colors=[cmap(j % 20) for j in range(len(ids))],
                         alpha=0.35, lw=0.0, step="mid")  # fmt: skip
            for run in runs:
                ax.plot([r.generation for r in run.history],
                        [r.largest_niche_share for r in run.history], lw=1.0, color="black",
                        alpha=0.9 if run is first else 0.35, drawstyle="steps-mid")  # fmt: skip
        for bound in (low, high) if low > 0.0 else (high,):
            ax.axhline(bound, color="tab:red", ls="--", lw=1.4)
        ax.plot([], [], color="tab:red", ls="--", label="the paper's range")
        ax.plot([], [], color="black", label="largest niche, each seed")
        ax.set_ylim(0.0, 1.0)
        seed = f", bands: seed {runs[0].seed}'s species" if runs else ""
        _labels(ax, f"{config}{seed}", "generation", "share of the population")
    return fig


def complexity_panels(panels: Panels, title: str) -> Figure:
    """Box plots of the final populations' F per complexity bin, the seeds pooled."""
    fig, axes = _panels(len(panels), title)
    for ax, (config, runs) in zip(axes, panels.items(), strict=False):
        if runs:
            f = np.concatenate([final_population(r)[0] for r in runs])
            c = np.concatenate([final_population(r)[1] for r in runs])
            bins = complexity_bins(c, f)
            ax.boxplot([b[2] for b in bins], widths=0.6)
            ax.set_xticks(range(1, len(bins) + 1),
                          [f"{lo:.2f}-{hi:.2f}\nn={len(v)}" for lo, hi, v in bins],
                          fontsize="small")  # fmt: skip
        _labels(ax, f"{config} ({len(runs)} seeds pooled)",
                "complexity (FLOPs ratio to the minimal network)", "performance F")
    return fig


def _labels(ax: Axes, title: str, x: str, y: str) -> None:
    ax.set_title(title, fontsize="medium")
    ax.set_xlabel(x)
    ax.set_ylabel(y)
    ax.grid(alpha=0.3)
    if ax.get_legend_handles_labels()[0]:
        ax.legend(loc="best", fontsize="small")


__all__ = ["complexity_panels", "convergence_panels", "niche_panels", "pareto_panels"]
