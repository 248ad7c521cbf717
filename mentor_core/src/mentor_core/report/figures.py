"""The figures of MENTOR runs and evaluations (paper section IV).

One function per figure; each takes plain data (history records, arrays, a genome, episode
results) and returns a :class:`matplotlib.figure.Figure` drawn on the Agg canvas, so nothing
here touches pyplot or the global backend:

* :func:`pareto_front` -- performance F vs experience gain G, the first front highlighted;
* :func:`convergence` -- best F (solid) and mean F (dashed) against evaluations, several runs
  in one axes, the dual-stage switch marked;
* :func:`niche_sizes` -- relative niche (species) sizes per generation as a stacked area, the
  largest share and the paper's 1/3 bound;
* :func:`complexity_boxplots` -- performance F per complexity (FLOPs ratio) bin;
* :func:`topology` -- the evolved network, inputs left, outputs right, hidden nodes by
  longest-path layer, with its genes in a table beneath;
* :func:`trajectories` -- the arena, its obstacles, start/goal pairs and each trajectory
  coloured by its outcome.
"""

from __future__ import annotations

import io
import itertools
import math
from collections.abc import Mapping, Sequence

import matplotlib as mpl
import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Circle, Rectangle
from numpy.typing import ArrayLike

from mentor_core.evolution.genome import Genome
from mentor_core.report.runs import EpisodeResult
from mentor_core.training.run_files import GenerationRecord

NICHE_BOUND = 1.0 / 3.0  # the paper: the largest niche stays around a third of the population
OUTCOME_COLOURS = {"reached": "tab:green", "collided": "tab:red", "timed out": "tab:orange"}
_DPI = 120
TABLE_MAX_GENES = 60  # larger genomes get their gene table in report.md only


def _figure(width: float, height: float) -> Figure:
    fig = Figure(figsize=(width, height), dpi=_DPI, layout="constrained")
    FigureCanvasAgg(fig)
    return fig


def pareto_front(points: ArrayLike, front: Sequence[int], title: str = "") -> Figure:
    """Performance F vs experience gain G of a population, its first front highlighted.

    ``points`` is (n, 2) [F, G] (paper eqs. 3-4 and the MST length of eq. 8);
    ``front`` the indices of the non-dominated points (both objectives maximised).
    """
    pts = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    on_front = np.zeros(len(pts), dtype=bool)
    on_front[list(front)] = True
    fig = _figure(6.0, 4.5)
    ax = fig.add_subplot()
    ax.scatter(pts[~on_front, 1], pts[~on_front, 0], s=18, c="0.6", label="dominated")
    fp = pts[on_front]
    order = np.argsort(fp[:, 1])
    ax.plot(fp[order, 1], fp[order, 0], "-o", color="tab:red", ms=6, lw=1.2,
            label=f"Pareto front ({len(fp)})")  # fmt: skip
    ax.set_xlabel("experience gain G (MST length of visited states)")
    ax.set_ylabel("performance F")
    ax.set_title(title or "Pareto front")
    ax.grid(alpha=0.3)
    ax.legend(loc="best")
    return fig


def _stage_switch(history: Sequence[GenerationRecord]) -> float | None:
    """Evaluations at the end of the first stage (None for a single-stage history)."""
    for prev, rec in itertools.pairwise(history):
        if rec.stage != prev.stage:
            return float(prev.evaluations)
    return None


def convergence(histories: Mapping[str, Sequence[GenerationRecord]], title: str = "") -> Figure:
    """Best F (solid) and mean F (dashed) against evaluations, one line pair per history.

    A history with more than one stage is dual-stage (orange shades, a dotted vertical line
    where stage 2 begins), one with a single stage single-stage (blue shades).
    """
    fig = _figure(7.0, 4.5)
    ax = fig.add_subplot()
    dual = {label: _stage_switch(h) is not None for label, h in histories.items() if h}
    counts = {True: sum(dual.values()), False: len(dual) - sum(dual.values())}
    seen = {True: 0, False: 0}
    switches: set[float] = set()
    for label, is_dual in dual.items():
        hist = histories[label]
        cmap = mpl.colormaps["Oranges" if is_dual else "Blues"]
        n = counts[is_dual]
        colour = cmap(0.85 - 0.45 * seen[is_dual] / max(1, n - 1)) if n > 1 else cmap(0.75)
        seen[is_dual] += 1
        evals = [r.evaluations for r in hist]
        ax.plot(evals, [r.best_F for r in hist], "-", color=colour, lw=1.6, label=label)
        ax.plot(evals, [r.mean_F for r in hist], "--", color=colour, lw=1.0)
        switch = _stage_switch(hist)
        if switch is not None and switch not in switches:
            switches.add(switch)
            ax.axvline(switch, color="tab:orange", ls=":", lw=1.2)
    handles, _ = ax.get_legend_handles_labels()
    handles.append(Line2D([], [], color="0.3", lw=1.6, label="best F"))
    handles.append(Line2D([], [], color="0.3", ls="--", lw=1.0, label="mean F"))
    if switches:
        handles.append(
            Line2D([], [], color="tab:orange", ls=":", lw=1.2, label="dual: stage 1 -> 2")
        )
    ax.set_xlabel("evaluations (genomes evaluated)")
    ax.set_ylabel("performance F")
    ax.set_title(title or "Convergence")
    ax.grid(alpha=0.3)
    ax.legend(handles=handles, loc="lower right", fontsize="small")
    return fig


def niche_share_matrix(history: Sequence[GenerationRecord]) -> tuple[list[int], np.ndarray]:
    """Species ids (sorted) and the (generations, species) matrix of population shares."""
    ids = sorted({s for r in history for s in r.niche_sizes})
    shares = np.zeros((len(history), len(ids)))
    col = {s: j for j, s in enumerate(ids)}
    for i, r in enumerate(history):
        total = sum(r.niche_sizes.values())
        for s, n in r.niche_sizes.items():
            shares[i, col[s]] = n / total if total else 0.0
    return ids, shares


def niche_sizes(history: Sequence[GenerationRecord], title: str = "") -> Figure:
    """Relative niche sizes per generation (stacked area), the largest share and 1/3.

    Each colour band is one species (niche), its height the share of the population in it.
    """
    ids, shares = niche_share_matrix(history)
    gens = np.array([r.generation for r in history])
    fig = _figure(7.0, 4.5)
    ax = fig.add_subplot()
    if ids:
        cmap = mpl.colormaps["tab20"]
        colours = [cmap(j % 20) for j in range(len(ids))]
        ax.stackplot(
            gens, shares.T, colors=colours, alpha=0.55, lw=0.3, edgecolor="white", step="mid"
        )
    largest = [r.largest_niche_share for r in history]
    ax.plot(gens, largest, "-", color="black", lw=1.8, drawstyle="steps-mid",
            label="largest niche share")  # fmt: skip
    ax.axhline(NICHE_BOUND, color="tab:red", ls="--", lw=1.2, label="1/3 of the population")
    for prev, rec in itertools.pairwise(history):
        if rec.stage != prev.stage:
            ax.axvline(rec.generation - 0.5, color="0.3", ls=":", lw=1.2, label="stage 1 -> 2")
    ax.set_xlim(gens.min(), max(gens.max(), gens.min() + 1))
    ax.set_ylim(0.0, 1.0)
    ax.set_xlabel("generation")
    ax.set_ylabel("share of the population")
    ax.set_title(title or f"Niche sizes ({len(ids)} species over the run; bands = species)")
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=3, fontsize="small",
              frameon=False)  # fmt: skip
    return fig


def complexity_bins(
    complexity: ArrayLike, performance: ArrayLike, n_bins: int = 5
) -> list[tuple[float, float, np.ndarray]]:
    """Equal-width complexity bins ``(low, high, performances)``, empty bins left out."""
    c = np.asarray(complexity, dtype=np.float64).ravel()
    f = np.asarray(performance, dtype=np.float64).ravel()
    if c.shape != f.shape:
        raise ValueError("complexity and performance differ in length")
    if not c.size:
        return []
    lo, hi = float(c.min()), float(c.max())
    if hi <= lo:
        return [(lo, hi, f)]
    edges = np.linspace(lo, hi, n_bins + 1)
    index = np.clip(np.searchsorted(edges, c, side="right") - 1, 0, n_bins - 1)
    return [
        (float(edges[b]), float(edges[b + 1]), f[index == b])
        for b in range(n_bins)
        if np.any(index == b)
    ]


def complexity_boxplots(
    complexity: ArrayLike, performance: ArrayLike, n_bins: int = 5, title: str = ""
) -> Figure:
    """Performance F of a population grouped into complexity (FLOPs ratio) bins, box plots."""
    bins = complexity_bins(complexity, performance, n_bins)
    fig = _figure(7.0, 4.5)
    ax = fig.add_subplot()
    if bins:
        ax.boxplot([b[2] for b in bins], widths=0.6)
        ax.set_xticks(
            range(1, len(bins) + 1),
            [f"{lo:.2f}-{hi:.2f}\nn={len(v)}" for lo, hi, v in bins],
        )
    ax.set_xlabel("complexity (FLOPs ratio to the minimal network)")
    ax.set_ylabel("performance F")
    ax.set_title(title or "Performance vs complexity")
    ax.grid(axis="y", alpha=0.3)
    return fig


def node_labels(
    genome: Genome, encoding: str = "paper", feedback_action: bool = False
) -> dict[int, str]:
    """Readable node names: range sensors r0.., the goal inputs of the encoding (dX, dY,
    heading; or cos β, sin β, S), the context a planner with a memory reads (its previous
    action outputs Δθ⁻, Δs⁻ with ``feedback_action``, its memory m1⁻.., one per output beyond
    the two actions), bias, dtheta, ds, the memory outputs m1.., h<id>."""
    labels: dict[int, str] = {}
    n_in = genome.n_inputs
    memory = [f"m{j + 1}" for j in range(max(genome.n_outputs - 2, 0))]
    goal = ["cos β", "sin β", "S"] if encoding == "egocentric" else ["dX", "dY", "θ"]
    context = (["Δθ⁻", "Δs⁻"] if feedback_action else []) + [f"{m}⁻" for m in memory]
    tail = goal + context if n_in >= 3 + len(context) else []
    for i in range(n_in):
        j = i - (n_in - len(tail))
        labels[i] = tail[j] if j >= 0 else f"r{i}"
    labels[genome.bias_id] = "bias"
    outs = ["Δθ", "Δs", *memory] if genome.n_outputs >= 2 else []
    for k, o in enumerate(genome.output_ids):
        labels[o] = outs[k] if outs else f"out{k}"
    for n in genome.hidden_nodes:
        labels[n.id] = f"h{n.id}"
    return labels


def node_layers(genome: Genome) -> dict[int, int]:
    """Column of each node: inputs and bias 0, hidden nodes 1 + the longest path to them
    from an input (over all forward genes), outputs one column right of the deepest hidden
    node."""
    preds: dict[int, list[int]] = {}
    for c in genome.connections:
        if not c.recurrent:  # a delayed edge may point backwards; it sets no column
            preds.setdefault(c.out_node, []).append(c.in_node)
    kinds = {n.id: n.kind for n in genome.nodes}
    layer: dict[int, int] = {}

    def depth(node: int, stack: frozenset[int]) -> int:
        if node in layer:
            return layer[node]
        if kinds.get(node) in ("input", "bias"):
            layer[node] = 0
            return 0
        ins = [p for p in preds.get(node, []) if p not in stack and kinds.get(p) != "output"]
        d = 1 + max((depth(p, stack | {node}) for p in ins), default=0)
        layer[node] = d
        return d

    hidden = [n.id for n in genome.hidden_nodes]
    deepest = max((depth(h, frozenset()) for h in hidden), default=0)
    out: dict[int, int] = {}
    for n in genome.nodes:
        if n.kind in ("input", "bias"):
            out[n.id] = 0
        elif n.kind == "output":
            out[n.id] = deepest + 1
        else:
            out[n.id] = layer[n.id]
    return out


def _node_positions(genome: Genome) -> dict[int, tuple[float, float]]:
    layers = node_layers(genome)
    kinds = {n.id: n.kind for n in genome.nodes}
    by_layer: dict[int, list[int]] = {}
    for node in sorted(layers):
        by_layer.setdefault(layers[node], []).append(node)
    tallest = max(len(v) for v in by_layer.values())
    pos: dict[int, tuple[float, float]] = {}
    for lay, nodes in by_layer.items():
        m = len(nodes)
        for k, node in enumerate(nodes):
            # the tallest column on integer rows; shorter ones evenly inside its height
            y = tallest - 1 - k if m == tallest else (tallest - 1) * (m - k) / (m + 1)
            if kinds[node] == "hidden" and m < tallest:
                y += 0.35 if lay % 2 else -0.35  # stagger so straight edges miss nodes
            pos[node] = (float(lay), float(y))
    return pos


def topology(
    genome: Genome, title: str = "", table: bool = True, encoding: str = "paper",
    feedback_action: bool = False,
) -> Figure:
    """The network of a genome with (if ``table``) its connection genes in a table beneath.

    Inputs (and bias) on the left, outputs on the right, hidden nodes in columns by their
    longest path from the inputs. Edge width grows with |weight|; blue positive, red
    negative; disabled genes dotted grey; recurrent genes (the previous decision's value)
    dashed, a node's loop onto itself as a dashed ring beside it.
    """
    pos = _node_positions(genome)
    labels = node_labels(genome, encoding, feedback_action)
    kinds = {n.id: n.kind for n in genome.nodes}
    n_rows = len(genome.connections)
    table = table and 0 < n_rows <= TABLE_MAX_GENES
    blocks = 1 if n_rows <= 16 else 2 if n_rows <= 40 else 3
    per_block = math.ceil(n_rows / blocks)
    table_h = 0.22 * (per_block + 1) if table else 0.0
    height = max(3.0, 0.42 * max(len(genome.input_ids) + 1, 3)) + 0.6
    fig = _figure(7.5 if blocks < 3 else 9.0, height + table_h)
    if table:
        gs = fig.add_gridspec(2, 1, height_ratios=[height, table_h])
        ax = fig.add_subplot(gs[0])
    else:
        ax = fig.add_subplot()
    wmax = max((abs(c.weight) for c in genome.connections), default=1.0) or 1.0
    for c in genome.connections:
        (x0, y0), (x1, y1) = pos[c.in_node], pos[c.out_node]
        colour = "tab:blue" if c.weight >= 0 else "tab:red"
        style = "--" if c.recurrent else "-"
        if not c.enabled:
            colour, style = "0.55", ":"
        width = 0.4 + 3.0 * abs(c.weight) / wmax if c.enabled else 1.0
        if c.in_node == c.out_node:
            ax.add_patch(Circle((x1 + 0.22, y1 + 0.22), 0.14, fill=False, ls=style, lw=width,
                                edgecolor=colour, zorder=1))  # fmt: skip
        else:
            ax.plot([x0, x1], [y0, y1], style, color=colour, lw=width,
                    alpha=0.75 if c.enabled else 1.0, zorder=1)  # fmt: skip
    face = {"input": "#cfe2f3", "bias": "#eeeeee", "hidden": "#fff2cc", "output": "#d9ead3"}
    for node, (x, y) in pos.items():
        ax.scatter([x], [y], s=520, c=face[kinds[node]], edgecolors="0.2", zorder=2)
        ax.text(x, y, labels[node], ha="center", va="center", fontsize=8, zorder=3)
    ax.set_xlim(-0.5, max(x for x, _ in pos.values()) + 0.5)
    ys = [y for _, y in pos.values()]
    ax.set_ylim(min(ys) - 0.7, max(ys) + 0.7)
    ax.set_axis_off()
    handles = [
        Line2D([], [], color="tab:blue", lw=2, label="weight > 0"),
        Line2D([], [], color="tab:red", lw=2, label="weight < 0"),
        Line2D([], [], color="0.55", ls=":", lw=1, label="disabled"),
    ]
    if genome.is_recurrent:
        handles.append(Line2D([], [], color="0.2", ls="--", lw=1.5, label="recurrent"))
    ax.legend(handles=handles, loc="upper center", bbox_to_anchor=(0.5, 0.0), ncol=len(handles),
              fontsize="small", frameon=False)  # fmt: skip
    hidden = len(genome.hidden_nodes)
    enabled = len(genome.enabled_connections)
    counts = f"{hidden} hidden nodes, {enabled}/{n_rows} genes enabled"
    ax.set_title(f"{title}\n{counts}" if title else f"Evolved topology: {counts}")
    if table:
        tax = fig.add_subplot(gs[1])
        tax.set_axis_off()
        genes = [
            [str(c.innovation), labels[c.in_node] + ("(t-1)" if c.recurrent else ""),
             labels[c.out_node], f"{c.weight:+.3f}", "yes" if c.enabled else "no"]
            for c in genome.connections
        ]  # fmt: skip
        genes += [[""] * 5] * (blocks * per_block - n_rows)
        # the genes in `blocks` side-by-side column groups, read top to bottom
        rows = [
            [cell for b in range(blocks) for cell in genes[b * per_block + r]]
            for r in range(per_block)
        ]
        tab = tax.table(
            cellText=rows,
            colLabels=["#", "from", "to", "weight", "on"] * blocks,
            loc="upper center",
            cellLoc="center",
        )
        tab.auto_set_font_size(False)
        tab.set_fontsize(7)
    return fig


def trajectories(
    results: Sequence[EpisodeResult],
    world_size: float,
    obstacles: ArrayLike,
    starts: ArrayLike,
    goals: ArrayLike,
    goal_radius: float = 0.0,
    title: str = "",
) -> Figure:
    """The arena (m), its obstacles, start (triangle) and goal (star + goal radius) of each
    scenario, and each trajectory coloured by its outcome: reached, collided, timed out."""
    boxes = np.asarray(obstacles, dtype=np.float64).reshape(-1, 4)
    st = np.asarray(starts, dtype=np.float64).reshape(-1, 3)
    gl = np.asarray(goals, dtype=np.float64).reshape(-1, 2)
    fig = _figure(7.4, 5.8)
    ax = fig.add_subplot()
    ax.add_patch(Rectangle((0, 0), world_size, world_size, fill=False, ec="black", lw=1.5))
    for x0, y0, x1, y1 in boxes:
        ax.add_patch(Rectangle((x0, y0), x1 - x0, y1 - y0, fc="0.45", ec="0.2", lw=0.5))
    used = sorted({r.scenario for r in results}) or list(range(len(st)))
    for s in used:
        ax.plot(st[s, 0], st[s, 1], marker="^", color="black", ms=7, ls="none", zorder=4)
        ax.plot(gl[s, 0], gl[s, 1], marker="*", color="gold", mec="black", ms=12, ls="none",
                zorder=4)  # fmt: skip
        if goal_radius > 0:
            ax.add_patch(Circle((gl[s, 0], gl[s, 1]), goal_radius, fill=False, ec="goldenrod",
                                ls="--", lw=0.8))  # fmt: skip
        for x, y in (st[s, :2], gl[s]):
            ax.annotate(str(s), (float(x), float(y)), textcoords="offset points", xytext=(5, 5))
    counts = dict.fromkeys(OUTCOME_COLOURS, 0)
    for r in results:
        counts[r.outcome] += 1
        t = r.trajectory
        if len(t):
            ax.plot(t[:, 0], t[:, 1], "-", color=OUTCOME_COLOURS[r.outcome], lw=1.4, alpha=0.85,
                    zorder=3)  # fmt: skip
            if r.collided:
                ax.plot(t[-1, 0], t[-1, 1], "x", color="tab:red", ms=8, mew=2, zorder=5)
    handles = [
        Line2D([], [], color=c, lw=2, label=f"{name} ({counts[name]})")
        for name, c in OUTCOME_COLOURS.items()
    ]
    handles += [
        Line2D([], [], marker="^", color="black", ls="none", label="start"),
        Line2D(
            [],
            [],
            marker="*",
            color="gold",
            mec="black",
            ms=10,
            ls="none",
            label=f"goal (radius {goal_radius:.2g} m)" if goal_radius > 0 else "goal",
        ),
    ]
    ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize="small")
    ax.set_xlim(-0.02 * world_size, 1.02 * world_size)
    ax.set_ylim(-0.02 * world_size, 1.02 * world_size)
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title(title or "Trajectories")
    return fig


def _png(fig: Figure) -> bytes:
    buf = io.BytesIO()
    # "tight" keeps legends placed outside the axes inside the picture
    fig.savefig(buf, format="png", dpi=_DPI, bbox_inches="tight", pad_inches=0.1)
    return buf.getvalue()


__all__ = [
    "complexity_boxplots",
    "convergence",
    "niche_sizes",
    "pareto_front",
    "topology",
    "trajectories",
]
