"""The figures and the Markdown report of MENTOR runs and evaluations (paper section IV).

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

:func:`load_run` and :func:`load_eval` read and validate a run directory (see
:class:`mentor_core.trainer.RunPaths`) and a ``mentor-eval`` JSON file; :func:`write_report`
writes the PNGs and ``report.md`` with the numbers, every file atomically.
"""

from __future__ import annotations

import csv
import io
import itertools
import json
import math
import re
import sys
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, TextIO

import matplotlib as mpl
import numpy as np
import yaml
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Circle, Rectangle
from numpy.typing import ArrayLike

from mentor_core.atomic import write_bytes_atomic, write_text_atomic
from mentor_core.errors import FileFormatError, is_version
from mentor_core.genome import Genome
from mentor_core.genome_io import load_genome_and_metadata
from mentor_core.trainer import HISTORY_FIELDS, GenerationRecord, RunPaths

NICHE_BOUND = 1.0 / 3.0  # the paper: the largest niche stays around a third of the population
FRAMEWORKS = ("single", "dual")
OUTCOME_COLOURS = {"reached": "tab:green", "collided": "tab:red", "timed out": "tab:orange"}
_DPI = 120
TABLE_MAX_GENES = 60  # larger genomes get their gene table in report.md only

# ---------------------------------------------------------------------------------------------
# Data read from disk


@dataclass(frozen=True)
class RunData:
    """A finished training run: its config, history, final population and best genome."""

    path: Path
    robot: str
    framework: str
    seed: int
    generations: int
    history: list[GenerationRecord]
    members: list[dict[str, Any]]  # population.json members (genome dicts, objectives, ...)
    pareto_points: np.ndarray  # (n, 2) [F, G] of the Pareto file's population
    pareto_front: list[int]  # indices into pareto_points
    pareto_stage: int
    best_genome: Genome
    input_encoding: str = "paper"  # of the best genome (its metadata)

    @property
    def label(self) -> str:
        """A short label: robot, framework and seed."""
        return f"{self.robot} {self.framework} s{self.seed}"


@dataclass(frozen=True)
class EpisodeResult:
    """One episode of an evaluation (a start/goal pair driven by one genome)."""

    scenario: int
    reached: bool
    collided: bool
    timed_out: bool
    time: float  # s
    final_distance: float  # m
    trajectory: np.ndarray  # (m, 3) poses [x, y, theta], m, rad

    @property
    def outcome(self) -> str:
        """ "reached", "collided" or "timed out"."""
        return "reached" if self.reached else "collided" if self.collided else "timed out"


@dataclass(frozen=True)
class EvalRun:
    """One genome's results in an evaluation file."""

    label: str
    path: str
    results: list[EpisodeResult]
    summary: dict[str, float]  # success_rate, collision_rate, survivability, mean_time_reached


@dataclass(frozen=True)
class EvalData:
    """A ``mentor-eval`` file: the unseen world, its start/goal pairs and the runs on it."""

    path: Path
    robot: str
    source: str
    world_size: float  # m
    obstacles: np.ndarray  # (k, 4) [xmin, ymin, xmax, ymax], m
    starts: np.ndarray  # (n, 3) [x, y, theta]
    goals: np.ndarray  # (n, 2)
    goal_radius: float  # m
    time_limit: float  # s
    runs: list[EvalRun]


def _one_line(err: BaseException) -> str:
    return " ".join(str(err).split())


def _read_json(path: Path) -> Any:
    try:
        return json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise FileFormatError(path, "no such file") from None
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as err:
        raise FileFormatError(path, f"not valid JSON ({_one_line(err)})") from None


def _check_format(path: Path, data: Any, fmt: str) -> dict[str, Any]:
    if not isinstance(data, dict) or data.get("format") != fmt:
        raise FileFormatError(path, f"not a {fmt} file")
    if not is_version(data.get("version"), 1):
        raise FileFormatError(path, f"unsupported version {data.get('version')!r}")
    return data


def _read_config(path: Path) -> dict[str, Any]:
    try:
        data = yaml.safe_load(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise FileFormatError(path, "no such file") from None
    except (OSError, UnicodeDecodeError, yaml.YAMLError) as err:
        raise FileFormatError(path, f"not valid YAML ({_one_line(err)})") from None
    if not isinstance(data, dict):
        raise FileFormatError(path, "not a mapping")
    for key, kind in (("robot", str), ("framework", str), ("seed", int), ("generations", int)):
        if not isinstance(data.get(key), kind):
            raise FileFormatError(path, f"missing or bad key {key!r}")
    return data


def read_history(path: str | Path) -> list[GenerationRecord]:
    """Parse ``history.csv`` (columns :data:`mentor_core.trainer.HISTORY_FIELDS`)."""
    p = Path(path)
    try:
        text = p.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise FileFormatError(p, "no such file") from None
    except (OSError, UnicodeDecodeError) as err:
        raise FileFormatError(p, f"unreadable ({_one_line(err)})") from None
    reader = csv.DictReader(io.StringIO(text))
    missing = [f for f in HISTORY_FIELDS if f not in (reader.fieldnames or ())]
    if missing:
        raise FileFormatError(p, f"missing columns {', '.join(missing)}")
    records: list[GenerationRecord] = []
    floats = (
        "best_F", "mean_F", "best_G", "mean_G", "largest_niche_share",
        "best_success_rate", "mean_complexity", "best_complexity", "seconds",
    )  # fmt: skip
    for line, row in enumerate(reader, start=2):
        try:
            sizes = json.loads(row["niche_sizes"])
            if not isinstance(sizes, dict):
                raise ValueError("niche_sizes is not a JSON object")
            records.append(
                GenerationRecord(
                    generation=int(row["generation"]),
                    stage=int(row["stage"]),
                    mode=str(row["mode"]),
                    evaluations=int(row["evaluations"]),
                    species=int(row["species"]),
                    niche_sizes={int(k): int(v) for k, v in sizes.items()},
                    **{k: float(row[k]) for k in floats},
                )
            )
        except (TypeError, ValueError) as err:
            raise FileFormatError(p, f"line {line}: {_one_line(err)}") from None
    if not records:
        raise FileFormatError(p, "no generations recorded")
    return records


def is_finished(run_dir: str | Path) -> bool:
    """Whether a run directory holds a final population (the trainer writes it last)."""
    return RunPaths(Path(run_dir)).population.is_file()


def load_run(run_dir: str | Path) -> RunData:
    """Read and validate a finished run directory (FileFormatError naming file and fault)."""
    paths = RunPaths(Path(run_dir))
    if not paths.root.is_dir():
        raise FileFormatError(paths.root, "no such run directory")
    config = _read_config(paths.config)
    history = read_history(paths.history)

    population = _check_format(paths.population, _read_json(paths.population), "mentor-population")
    members = population.get("members")
    if not isinstance(members, list) or not members:
        raise FileFormatError(paths.population, "no members")
    for i, m in enumerate(members):
        try:
            float(m["objectives"]["performance"])
            float(m["objectives"]["experience_gain"])
            float(m["complexity"])
        except (KeyError, TypeError, ValueError) as err:
            raise FileFormatError(paths.population, f"member {i}: bad {_one_line(err)}") from None

    pareto = _check_format(paths.pareto, _read_json(paths.pareto), "mentor-pareto")
    try:
        points = np.asarray(pareto["points"], dtype=np.float64)
        front = [int(i) for i in pareto["front"]]
        stage = int(pareto.get("stage", 0))
    except (KeyError, TypeError, ValueError) as err:
        raise FileFormatError(paths.pareto, f"corrupt ({_one_line(err)})") from None
    if points.ndim != 2 or points.shape[1] != 2 or not points.size:
        raise FileFormatError(paths.pareto, "points must be a non-empty list of [F, G]")
    if any(not 0 <= i < len(points) for i in front):
        raise FileFormatError(paths.pareto, "front index out of range")

    genome, genome_meta = load_genome_and_metadata(paths.best_genome)
    return RunData(
        path=paths.root,
        robot=str(config["robot"]),
        framework=str(config["framework"]),
        seed=int(config["seed"]),
        generations=int(config["generations"]),
        history=history,
        members=members,
        pareto_points=points,
        pareto_front=front,
        pareto_stage=stage,
        best_genome=genome,
        input_encoding=str(genome_meta.get("input_encoding", "paper")),
    )


def _episode(path: Path, where: str, r: Any) -> EpisodeResult:
    try:
        traj = np.asarray(r["trajectory"], dtype=np.float64).reshape(-1, 3)
        return EpisodeResult(
            scenario=int(r["scenario"]),
            reached=bool(r["reached"]),
            collided=bool(r["collided"]),
            timed_out=bool(r["timed_out"]),
            time=float(r["time"]),
            final_distance=float(r["final_distance"]),
            trajectory=traj,
        )
    except (KeyError, TypeError, ValueError) as err:
        raise FileFormatError(path, f"{where}: bad result ({_one_line(err)})") from None


def _summary_value(v: Any) -> float:
    return math.nan if v is None else float(v)


def load_eval(path: str | Path) -> EvalData:
    """Read and validate a ``mentor-eval`` JSON file (FileFormatError naming file and fault)."""
    p = Path(path)
    data = _check_format(p, _read_json(p), "mentor-eval")
    try:
        world = data["world"]
        obstacles = np.asarray(world["obstacles"], dtype=np.float64).reshape(-1, 4)
        starts = np.asarray([s["start"] for s in data["scenarios"]], np.float64).reshape(-1, 3)
        goals = np.asarray([s["goal"] for s in data["scenarios"]], np.float64).reshape(-1, 2)
        runs = []
        for k, run in enumerate(data["runs"]):
            results = [_episode(p, f"run {k}", r) for r in run["results"]]
            summary = {
                key: _summary_value(run["summary"][key])
                for key in ("success_rate", "collision_rate", "survivability", "mean_time_reached")
            }
            runs.append(EvalRun(str(run["genome"]), str(run.get("path", "")), results, summary))
        out = EvalData(
            path=p,
            robot=str(data["robot"]),
            source=str(data.get("source", "")),
            world_size=float(world["size"]),
            obstacles=obstacles,
            starts=starts,
            goals=goals,
            goal_radius=float(data.get("goal_radius", 0.0)),
            time_limit=float(data.get("time_limit", math.nan)),
            runs=runs,
        )
    except FileFormatError:
        raise
    except (KeyError, TypeError, ValueError) as err:
        raise FileFormatError(p, f"corrupt ({_one_line(err)})") from None
    for run in out.runs:
        for r in run.results:
            if not 0 <= r.scenario < len(out.starts):
                raise FileFormatError(p, f"{run.label}: scenario {r.scenario} out of range")
    return out


# ---------------------------------------------------------------------------------------------
# Figures


def _figure(width: float, height: float) -> Figure:
    fig = Figure(figsize=(width, height), dpi=_DPI, layout="constrained")
    FigureCanvasAgg(fig)
    return fig


def pareto_front(points: ArrayLike, front: Sequence[int], title: str = "") -> Figure:
    """Performance F vs experience gain G of a population, its first front highlighted.

    ``points`` is (n, 2) [F, G] (paper eq. 3 and the MST length of the visited states);
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


def _framework_of(label: str) -> str:
    for name in FRAMEWORKS:
        if re.search(rf"\b{name}\b", label):
            return name
    return ""


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


def node_labels(genome: Genome, encoding: str = "paper") -> dict[int, str]:
    """Readable node names: range sensors r0.., the goal inputs of the encoding (dX, dY,
    heading; or cos β, sin β, S), bias, dtheta, ds, h<id>."""
    labels: dict[int, str] = {}
    n_in = genome.n_inputs
    goal = ["cos β", "sin β", "S"] if encoding == "egocentric" else ["dX", "dY", "θ"]
    tail = goal if n_in >= 3 else []
    for i in range(n_in):
        j = i - (n_in - len(tail))
        labels[i] = tail[j] if j >= 0 else f"r{i}"
    labels[genome.bias_id] = "bias"
    outs = ["Δθ", "Δs"] if genome.n_outputs == 2 else []
    for k, o in enumerate(genome.output_ids):
        labels[o] = outs[k] if outs else f"out{k}"
    for n in genome.hidden_nodes:
        labels[n.id] = f"h{n.id}"
    return labels


def node_layers(genome: Genome) -> dict[int, int]:
    """Column of each node: inputs and bias 0, hidden nodes 1 + the longest path to them
    from an input (over all genes), outputs one column right of the deepest hidden node."""
    preds: dict[int, list[int]] = {}
    for c in genome.connections:
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
    genome: Genome, title: str = "", table: bool = True, encoding: str = "paper"
) -> Figure:
    """The network of a genome with (if ``table``) its connection genes in a table beneath.

    Inputs (and bias) on the left, outputs on the right, hidden nodes in columns by their
    longest path from the inputs. Edge width grows with |weight|; blue positive, red
    negative; disabled genes dotted grey.
    """
    pos = _node_positions(genome)
    labels = node_labels(genome, encoding)
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
        if c.enabled:
            colour = "tab:blue" if c.weight >= 0 else "tab:red"
            ax.plot([x0, x1], [y0, y1], "-", color=colour, lw=0.4 + 3.0 * abs(c.weight) / wmax,
                    alpha=0.75, zorder=1)  # fmt: skip
        else:
            ax.plot([x0, x1], [y0, y1], ":", color="0.55", lw=1.0, zorder=1)
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
    ax.legend(handles=handles, loc="upper center", bbox_to_anchor=(0.5, 0.0), ncol=3,
              fontsize="small", frameon=False)  # fmt: skip
    hidden = len(genome.hidden_nodes)
    enabled = len(genome.enabled_connections)
    counts = f"{hidden} hidden nodes, {enabled}/{n_rows} genes enabled"
    ax.set_title(f"{title}\n{counts}" if title else f"Evolved topology: {counts}")
    if table:
        tax = fig.add_subplot(gs[1])
        tax.set_axis_off()
        genes = [
            [str(c.innovation), labels[c.in_node], labels[c.out_node], f"{c.weight:+.3f}",
             "yes" if c.enabled else "no"]
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


# ---------------------------------------------------------------------------------------------
# The report


def _png(fig: Figure) -> bytes:
    buf = io.BytesIO()
    # "tight" keeps legends placed outside the axes inside the picture
    fig.savefig(buf, format="png", dpi=_DPI, bbox_inches="tight", pad_inches=0.1)
    return buf.getvalue()


def _slug(text: str) -> str:
    return re.sub(r"[^A-Za-z0-9_.-]+", "-", text).strip("-") or "run"


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


def genome_tables(genome: Genome, encoding: str = "paper") -> list[str]:
    """Markdown tables of a genome's nodes and connection genes."""
    labels = node_labels(genome, encoding)
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


def _eval_group(run: EvalRun, runs: Sequence[RunData], base: Path) -> tuple[str, str]:
    """(framework, seed) of an evaluated genome whose file lies in a reported run directory
    (its path taken as given or relative to the evaluation file's folder ``base``);
    otherwise the framework named in its label (or the label itself) and no seed."""
    if run.path:
        parents = {Path(run.path).resolve().parent, (base / run.path).resolve().parent}
        for r in runs:
            if r.path.resolve() in parents:
                return r.framework, str(r.seed)
    return _framework_of(run.label) or run.label, "-"


def write_report(
    run_dirs: Sequence[str | Path],
    eval_jsons: Sequence[str | Path] = (),
    out_dir: str | Path = "report",
    *,
    log: TextIO | None = None,
) -> Path:
    """Write the figures (PNG) and ``report.md`` of some runs and evaluations into ``out_dir``.

    Unfinished runs (no ``population.json``) are skipped with a warning line on ``log``
    (stderr by default); a missing or corrupt file raises FileFormatError naming it. Returns
    the path of ``report.md``.
    """
    stream = log if log is not None else sys.stderr
    out = Path(out_dir)
    runs: list[RunData] = []
    skipped: list[Path] = []
    for d in run_dirs:
        p = Path(d)
        if p.is_dir() and not is_finished(p):
            print(f"mentor-report: warning: {p}: unfinished run (no population.json), skipped",
                  file=stream)  # fmt: skip
            skipped.append(p)
            continue
        runs.append(load_run(p))
    evals = [load_eval(e) for e in eval_jsons]

    names: dict[int, str] = {}
    taken: set[str] = set()
    for i, r in enumerate(runs):
        base = _slug(r.path.name)
        name, k = base, 2
        while name in taken:
            name, k = f"{base}-{k}", k + 1
        taken.add(name)
        names[i] = name

    def save(fig: Figure, name: str) -> str:
        write_bytes_atomic(out / name, _png(fig))
        return name

    md: list[str] = ["# MENTOR report", ""]
    if runs:
        md += ["## Runs", ""]
        rows = []
        for i, r in enumerate(runs):
            n = run_numbers(r)
            flag = " ⚠ > 1/3" if n.max_niche_share > NICHE_BOUND else ""
            rows.append([
                f"`{names[i]}`", r.robot, r.framework, str(r.seed), str(r.generations),
                str(n.evaluations), _fmt(n.best_F), _fmt(n.best_G), _pct(n.best_success_rate),
                str(n.species), f"{_pct(n.max_niche_share)}{flag}",
            ])  # fmt: skip
        md += _md_table(
            ["run", "robot", "framework", "seed", "generations", "evaluations", "best F",
             "best G", "best success", "species", "largest niche (max)"],
            rows,
        )  # fmt: skip
        md += [
            "Best F, best G, best success rate and species are those of the last generation;",
            "the largest niche is the maximum share over all generations (the paper reports",
            "about a third of the population or less; ⚠ marks runs above 1/3).",
            "",
        ]
        groups: dict[tuple[str, str], list[RunData]] = {}
        for r in runs:
            groups.setdefault((r.robot, r.framework), []).append(r)
        md += ["### Per robot and framework (mean ± std over seeds)", ""]
        grows = []
        for (robot, fw), members in sorted(groups.items()):
            nums = [run_numbers(r) for r in members]
            grows.append([
                robot, fw, str(len(members)),
                _spread([n.best_F for n in nums], _fmt),
                _spread([n.best_G for n in nums], _fmt),
                _spread([n.best_success_rate for n in nums], _pct),
                _spread([float(n.species) for n in nums], lambda x: f"{x:.1f}"),
                _spread([n.max_niche_share for n in nums], _pct),
            ])  # fmt: skip
        md += _md_table(
            ["robot", "framework", "runs", "best F", "best G", "best success", "species",
             "largest niche (max)"],
            grows,
        )  # fmt: skip

        md += ["## Convergence", ""]
        for robot in sorted({r.robot for r in runs}):
            chosen = [i for i, r in enumerate(runs) if r.robot == robot]
            short = [f"{runs[i].framework} s{runs[i].seed}" for i in chosen]
            hist = {
                (lab if short.count(lab) == 1 else f"{lab} ({names[i]})"): runs[i].history
                for i, lab in zip(chosen, short, strict=True)
            }
            fig = convergence(hist, title=f"{robot}: best F (solid), mean F (dashed)")
            name = save(fig, f"convergence_{_slug(robot)}.png")
            md += [f"![convergence {robot}]({name})", ""]

        for i, r in enumerate(runs):
            n = run_numbers(r)
            tag = names[i]
            md += [f"## Run `{tag}` ({r.label})", "", f"Directory: `{r.path}`", ""]
            stage = f"stage {r.pareto_stage + 1} end" if r.framework == "dual" else "final"
            fig = pareto_front(r.pareto_points, r.pareto_front,
                               title=f"{r.label}: population at {stage}")  # fmt: skip
            md += [f"![Pareto front]({save(fig, f'{tag}_pareto.png')})", ""]
            md += [
                f"Pareto front: {len(r.pareto_front)} of {len(r.pareto_points)} genomes "
                f"({stage}).",
                "",
            ]
            fig = niche_sizes(r.history, title=f"{r.label}: niche sizes")
            md += [f"![niche sizes]({save(fig, f'{tag}_niches.png')})", ""]
            verdict = "above" if n.max_niche_share > NICHE_BOUND else "within"
            md += [
                f"Largest niche: at most {_pct(n.max_niche_share)} of the population over "
                f"{len(r.history)} generations ({verdict} the paper's 1/3).",
                "",
            ]
            cx = [float(m["complexity"]) for m in r.members]
            fx = [float(m["objectives"]["performance"]) for m in r.members]
            fig = complexity_boxplots(cx, fx, title=f"{r.label}: final population")
            md += [f"![performance vs complexity]({save(fig, f'{tag}_complexity.png')})", ""]
            g = r.best_genome
            fig = topology(g, title=f"{r.label}: best genome", encoding=r.input_encoding)
            md += [f"![topology]({save(fig, f'{tag}_topology.png')})", ""]
            md += [
                f"Best genome: {g.n_inputs} inputs + bias, {g.n_outputs} outputs, "
                f"{len(g.hidden_nodes)} hidden nodes, {len(g.enabled_connections)} of "
                f"{len(g.connections)} connection genes enabled.",
                "",
            ]
            md += ["<details><summary>genome tables</summary>", ""]
            md += genome_tables(g, r.input_encoding)
            md += ["</details>", ""]

    if evals:
        md += ["## Evaluations on unseen environments", ""]
        for k, ev in enumerate(evals):
            etag = f"eval{k}-{_slug(ev.path.stem)}"
            md += [
                f"### `{ev.path.name}` ({ev.robot}, {ev.source or 'unknown source'})",
                "",
                f"{len(ev.starts)} start/goal pairs, arena {ev.world_size:g} m, "
                f"{len(ev.obstacles)} obstacles, goal radius {ev.goal_radius:g} m, "
                f"time limit {ev.time_limit:g} s.",
                "",
            ]
            rows = []
            grouped: dict[str, list[EvalRun]] = {}
            for run in ev.runs:
                fw, seed = _eval_group(run, runs, ev.path.parent)
                grouped.setdefault(fw, []).append(run)
                s = run.summary
                rows.append([
                    f"`{run.label}`", fw, seed, _pct(s["success_rate"]),
                    _pct(s["collision_rate"]), _pct(s["survivability"]),
                    _fmt(s["mean_time_reached"], 1),
                ])  # fmt: skip
            md += _md_table(
                ["genome", "framework", "seed", "success", "collisions", "survivability",
                 "mean time to goal (s)"],
                rows,
            )  # fmt: skip
            if any(len(v) > 1 for v in grouped.values()):
                md += [f"Per framework, {ev.robot} (mean ± std over genomes):", ""]
                md += _md_table(
                    ["framework", "genomes", "success", "collisions", "survivability",
                     "mean time to goal (s)"],
                    [
                        [fw, str(len(v))]
                        + [_spread([r.summary[key] for r in v], _pct) for key in
                           ("success_rate", "collision_rate", "survivability")]
                        + [_spread([r.summary["mean_time_reached"] for r in v],
                                   lambda x: f"{x:.1f}")]
                        for fw, v in sorted(grouped.items())
                    ],
                )  # fmt: skip
            for j, run in enumerate(ev.runs):
                fig = trajectories(
                    run.results, ev.world_size, ev.obstacles, ev.starts, ev.goals,
                    ev.goal_radius, title=f"{ev.robot}: {run.label}",
                )  # fmt: skip
                name = save(fig, f"{etag}_{j}-{_slug(run.label)}_trajectories.png")
                md += [f"![trajectories {run.label}]({name})", ""]

    if skipped:
        md += ["## Skipped", ""]
        md += [f"- `{p}`: unfinished run (no population.json)" for p in skipped]
        md += [""]
    if not runs and not evals:
        md += ["Nothing to report: no finished run and no evaluation.", ""]
    report = out / "report.md"
    write_text_atomic(report, "\n".join(md))
    return report


__all__ = [
    "EpisodeResult",
    "EvalData",
    "EvalRun",
    "RunData",
    "complexity_boxplots",
    "convergence",
    "genome_tables",
    "load_eval",
    "load_run",
    "niche_sizes",
    "pareto_front",
    "read_history",
    "run_numbers",
    "topology",
    "trajectories",
    "write_report",
]
