"""The benchmark's report: tables and figures of a ``mentor-bench`` result document
(``mentor_core.benchmark.document``), written by ``mentor-bench --out`` and included by
``mentor-report --bench``.

* :func:`success_bars` -- success per family (and overall) as grouped bars, one bar per
  planner: evolved (blues), baselines (oranges, greens), oracle (grey), so that which one
  wins in each family shows at a glance;
* :func:`example_trajectories` -- one pair per family, every planner's trajectory on it,
  each ending in a dot (reached), a cross (collided) or a circle (timed out);
* :func:`bench_markdown` -- both figures and the tables (success and SPL per family under
  each time limit, per planner and, where a name has several seeds (``report.seed_groups``),
  its mean +- sd beside the baselines; each evolved planner head to head with the best
  baseline per family (``report.head_to_head``); its paths against that baseline's on the
  pairs both reached (``report.path_efficiency``); every score overall) as Markdown lines.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.figure import Figure
from matplotlib.patches import Circle, Rectangle

from mentor_core.atomic import write_bytes_atomic
from mentor_core.report.figures import _figure, _png
from mentor_core.report.head_to_head import head_to_head_markdown
from mentor_core.report.path_efficiency import DETOUR, efficiency_markdown
from mentor_core.report.seed_groups import seed_groups
from mentor_core.report.tables import _fmt, _md_table, _pct

_PALETTES = {"evolved": ("tab:blue", "tab:cyan", "tab:purple", "navy", "steelblue"),
             "baseline": ("tab:orange", "tab:green", "tab:brown", "gold"),
             "pursuit": ("tab:gray", "dimgray", "silver"),
             "oracle": ("0.45", "0.2")}  # fmt: skip
_ENDS = {"reached": "o", "collided": "x", "timed out": "$\\circ$"}
LIMIT_TITLES = {"paper": "the paper's 50 s", "scaled": "the limit scaled to the shortest path"}


def colours(doc: Mapping[str, Any]) -> list[str]:
    """A colour per contender, by kind (module docstring)."""
    used = {k: 0 for k in _PALETTES}
    out = []
    for c in doc["contenders"]:
        palette = _PALETTES.get(str(c["kind"]), _PALETTES["baseline"])
        n = used.get(str(c["kind"]), 0)
        out.append(palette[n % len(palette)])
        used[str(c["kind"])] = n + 1
    return out


def success_bars(doc: Mapping[str, Any], limit: str = "paper") -> Figure:
    """Success per family and overall, one bar per contender (module docstring)."""
    groups = [*doc["families"], "overall"]
    contenders = doc["contenders"]
    fig = _figure(max(6.0, 0.9 * len(groups) + 2.0), 4.0)
    ax = fig.add_subplot()
    width = 0.8 / max(1, len(contenders))
    x = np.arange(len(groups))
    for j, (c, colour) in enumerate(zip(contenders, colours(doc), strict=True)):
        values = [c["scores"][limit][g]["success"] for g in groups]
        ax.bar(x - 0.4 + (j + 0.5) * width, values, width, color=colour,
               label=f"{c['name']} ({c['kind']})")  # fmt: skip
    ax.set_xticks(x, groups, rotation=30, ha="right")
    ax.set_ylim(0.0, 1.05)
    ax.set_ylabel("success")
    ax.set_title(f"{doc['robot']}, {doc['split']} split: success within "
                 f"{LIMIT_TITLES.get(limit, limit)}", fontsize=10)  # fmt: skip
    ax.grid(axis="y", alpha=0.3)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.0, 1.0))
    return fig


def _outcome(result: Mapping[str, Any]) -> str:
    return "reached" if result["reached"] else "collided" if result["collided"] else "timed out"


def example_trajectories(doc: Mapping[str, Any], per_family: int = 1) -> Figure:
    """The first ``per_family`` pairs of each family with every contender's trajectory."""
    chosen: list[int] = []
    for family in doc["families"]:
        chosen += [i for i, p in enumerate(doc["pairs"]) if p["family"] == family][:per_family]
    cols = min(4, len(chosen))
    rows = math.ceil(len(chosen) / cols)
    fig = _figure(3.2 * cols + 1.5, 3.2 * rows)
    size = float(doc["arena"])
    palette = colours(doc)
    for k, i in enumerate(chosen):
        p = doc["pairs"][i]
        ax = fig.add_subplot(rows, cols, k + 1)
        ax.add_patch(Rectangle((0.0, 0.0), size, size, fill=False, edgecolor="black", lw=1.0))
        for x0, y0, x1, y1 in doc["worlds"][p["world"]]:
            ax.add_patch(Rectangle((x0, y0), x1 - x0, y1 - y0, color="0.35"))
        ax.add_patch(Circle(p["goal"], float(doc["goal_radius"]), fill=False,
                            color="tab:red", lw=0.8))  # fmt: skip
        ax.plot(*p["start"][:2], marker="^", color="black", ms=6, zorder=5)
        for c, colour in zip(doc["contenders"], palette, strict=True):
            result = c["results"][i]
            path = np.asarray(result["trajectory"], dtype=np.float64).reshape(-1, 2)
            ax.plot(path[:, 0], path[:, 1], color=colour, lw=1.0, label=c["name"])
            ax.plot(path[-1, 0], path[-1, 1], marker=_ENDS[_outcome(result)], color=colour,
                    ms=6, zorder=6)  # fmt: skip
        ax.set_xlim(0.0, size)
        ax.set_ylim(0.0, size)
        ax.set_aspect("equal")
        ax.set_xticks([])
        ax.set_yticks([])
        ax.set_title(f"{p['family']} (world {p['seed']}, l = {p['shortest']:.1f} m)",
                     fontsize=8)  # fmt: skip
    handles, labels = fig.axes[0].get_legend_handles_labels() if fig.axes else ([], [])
    fig.legend(handles, labels, fontsize=7, loc="outside right upper")
    return fig


def _cells(doc: Mapping[str, Any], limit: str, fmt: Callable[[Mapping[str, Any]], str]) -> list[
        list[str]]:
    rows = []
    for group in [*doc["families"], "overall"]:
        label = f"**{group}**" if group == "overall" else group
        rows.append([label] + [fmt(c["scores"][limit][group]) for c in doc["contenders"]])
    return rows


def _none_nan(x: Any) -> float:
    return math.nan if x is None else float(x)


def _spread(values: Sequence[float], percent: bool) -> str:
    """``mean +- sd`` (sample sd, ``ddof=1``) of the finite values."""
    v = np.asarray([x for x in values if math.isfinite(x)], dtype=np.float64)
    if v.size == 0:
        return "-"
    mean, sd = float(v.mean()), float(v.std(ddof=1)) if v.size > 1 else 0.0
    return f"{100 * mean:.0f} ± {100 * sd:.0f} %" if percent else f"{mean:.2f} ± {sd:.2f}"


def _seed_table(doc: Mapping[str, Any], limit: str) -> list[str]:
    """Success / SPL per family: each seed group's mean +- sd, then the other contenders
    that are not evolved (the baselines and the oracle)."""
    contenders = doc["contenders"]
    groups = seed_groups(contenders)
    others = [c for c in contenders if c["kind"] != "evolved"]
    header = ["family", *(f"{name} ({len(idx)} seeds)" for name, idx in groups.items()),
              *(f"{c['name']} ({c['kind']})" for c in others)]  # fmt: skip
    rows = []
    for group in [*doc["families"], "overall"]:
        cells = [f"**{group}**" if group == "overall" else group]
        for idx in groups.values():
            scores = [contenders[i]["scores"][limit][group] for i in idx]
            cells.append(_spread([_none_nan(t["success"]) for t in scores], True) + " / "
                         + _spread([_none_nan(t["spl"]) for t in scores], False))
        cells += [f"{_pct(_none_nan(c['scores'][limit][group]['success']))} / "
                  f"{_fmt(_none_nan(c['scores'][limit][group]['spl']), 2)}" for c in others]
        rows.append(cells)
    return _md_table(header, rows)


def _limits(settings: Mapping[str, Any], period: float) -> str:
    """A planner's action limits: its step range and largest turn per decision, and its
    control period (``period``, the reference's, where a document written before it was
    recorded per planner lacks it)."""
    turn = math.degrees(float(settings["heading_change_max"]))
    period = float(settings.get("control_period", period))
    return (f"{settings['step_min']:.3g}-{settings['step_max']:.3g} m, ±{turn:.3g}° "
            f"every {period:.3g} s")


def bench_markdown(doc: Mapping[str, Any], out_dir: str | Path, prefix: str = "bench",
                   heading: str = "##") -> list[str]:
    """Write the figures into ``out_dir`` (``<prefix>_success.png``, ``<prefix>_success_
    scaled.png``, ``<prefix>_trajectories.png``) and return the Markdown of the benchmark."""
    out = Path(out_dir)
    for name, fig in ((f"{prefix}_success.png", success_bars(doc, "paper")),
                      (f"{prefix}_success_scaled.png", success_bars(doc, "scaled")),
                      (f"{prefix}_trajectories.png", example_trajectories(doc))):  # fmt: skip
        write_bytes_atomic(out / name, _png(fig))
    n_pairs = len(doc["pairs"])
    header = ["family", *(f"{c['name']} ({c['kind']})" for c in doc["contenders"])]
    md = [
        f"{heading} Benchmark: {doc['robot']}, {doc['split']} split",
        "",
        f"{n_pairs} start/goal pairs in {len(doc['worlds'])} worlds, "
        f"{len(doc['families'])} families; arena {float(doc['arena']):g} m, goal radius "
        f"{float(doc['goal_radius']):.3g} m. Cells: success / SPL (Anderson et al. 2018: "
        "success weighted by shortest path length / path taken).",
        "",
    ]
    for limit in ("paper", "scaled"):
        md += [f"Within {LIMIT_TITLES[limit]}:", ""]
        md += _md_table(header, _cells(doc, limit, lambda s: (
            f"{_pct(_none_nan(s['success']))} / {_fmt(_none_nan(s['spl']), 2)}")))
    if seed_groups(doc["contenders"]):
        for limit in ("paper", "scaled"):
            md += [f"Planners over their seeds (`<name>-s<seed>`; mean ± sample sd of the "
                   f"seeds' rates), within {LIMIT_TITLES[limit]}:", ""]
            md += _seed_table(doc, limit)
    versus = head_to_head_markdown(doc, "paper")
    if versus:
        md += [f"Head to head, within {LIMIT_TITLES['paper']}: each evolved planner against "
               "the best baseline variant in each family, on success and on SPL separately "
               "(the oracle is not a baseline):", "", *versus]
    chosen = doc.get("baseline_choice")
    if versus and chosen is not None:
        md += [f"Head to head against the baseline variant that was best on the "
               f"{chosen.get('split', '?')} split (`{chosen.get('source', '?')}`) in each "
               "family and column, scored here (no winner's bias from picking the best on "
               "these pairs):", "", *head_to_head_markdown(doc, "paper", chosen["choice"])]
    efficiency = efficiency_markdown(doc, "paper")
    if efficiency:
        md += [f"Where SPL goes, within {LIMIT_TITLES['paper']}: SPL is success times the path "
               "efficiency, the mean of shortest / taken over the pairs reached. So that a "
               "planner that fails the hard pairs is not scored on the easy ones, each evolved "
               "planner and the baseline of the highest SPL in each family are compared on the "
               "pairs both reached (each seed's, the seeds pooled). Each cell: the efficiency · "
               "the median of taken / shortest · the share of paths longer than "
               f"{DETOUR:g} times the shortest:", "", *efficiency]
    md += [f"![success per family]({prefix}_success.png)", "",
           f"![success per family, scaled limit]({prefix}_success_scaled.png)", ""]
    rows = []
    period = float(doc["control_period"])
    for c in doc["contenders"]:
        for limit in ("paper", "scaled"):
            s = c["scores"][limit]["overall"]
            rows.append([f"`{c['name']}`", c["kind"], _limits(c["settings"], period), limit,
                         _pct(_none_nan(s["success"])), _pct(_none_nan(s["collision"])),
                         _pct(_none_nan(s["timeout"])), _fmt(_none_nan(s["time_to_goal"]), 1),
                         _fmt(_none_nan(s["spl"]), 3)])  # fmt: skip
    md += _md_table(["planner", "kind", "steps, turns, period", "limit", "success", "collisions",
                     "timeouts", "time to goal (s)", "SPL"], rows)  # fmt: skip
    md += [f"![example trajectories]({prefix}_trajectories.png)", ""]
    return md
