"""The Markdown report: :func:`write_report` writes the figures (PNG) and ``report.md`` with
the numbers of some runs and evaluations, every file atomically."""

from __future__ import annotations

import re
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import TextIO

from matplotlib.figure import Figure

from mentor_core.atomic import write_bytes_atomic, write_text_atomic
from mentor_core.benchmark.document import load_bench
from mentor_core.errors import FileFormatError, MentorError
from mentor_core.report.bench import bench_markdown
from mentor_core.report.figures import (
    NICHE_BOUND,
    _png,
    complexity_boxplots,
    convergence,
    niche_sizes,
    pareto_front,
    topology,
    trajectories,
)
from mentor_core.report.runs import EvalRun, RunData, is_finished, load_eval, load_run
from mentor_core.report.tables import _fmt, _md_table, _pct, _spread, genome_tables, run_numbers
from mentor_core.training.run_directory import is_run_directory

FRAMEWORKS = ("single", "dual")
#: the first line of every report.md: how a folder is known to hold an earlier report
REPORT_TITLE = "# MENTOR report"
REPORT_FILE = "report.md"
_FIGURE_LINK = re.compile(r"\]\(([^)/\\]+\.png)\)")


def _slug(text: str) -> str:
    return re.sub(r"[^A-Za-z0-9_.-]+", "-", text).strip("-") or "run"


def _framework_of(label: str) -> str:
    for name in FRAMEWORKS:
        if re.search(rf"\b{name}\b", label):
            return name
    return ""


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


def is_report_dir(path: str | Path) -> bool:
    """Whether ``path`` is a folder holding a report of :func:`write_report` (its report.md
    starts with :data:`REPORT_TITLE`)."""
    report = Path(path) / REPORT_FILE
    try:
        with report.open(encoding="utf-8") as handle:
            return handle.readline().rstrip("\n") == REPORT_TITLE
    except (OSError, UnicodeDecodeError):
        return False


def _linked_figures(out: Path) -> set[str]:
    """The figures (PNG file names) an earlier report in ``out`` links to."""
    if not is_report_dir(out):
        return set()
    return set(_FIGURE_LINK.findall((out / REPORT_FILE).read_text(encoding="utf-8")))


def write_report(
    run_dirs: Sequence[str | Path],
    eval_jsons: Sequence[str | Path] = (),
    out_dir: str | Path = "report",
    *,
    log: TextIO | None = None,
    bench_jsons: Sequence[str | Path] = (),
) -> Path:
    """Write the figures (PNG) and ``report.md`` of some runs, evaluations and benchmark
    results (``mentor-bench`` JSON, ``bench_jsons``) into ``out_dir``.

    Unfinished runs (no ``population.json``) are skipped with a warning line on ``log``
    (stderr by default); a missing or corrupt file raises FileFormatError naming it. An
    earlier report in ``out_dir`` is replaced: its figures that this report does not draw are
    removed, other files are left alone. Returns the path of ``report.md``.
    """
    stream = log if log is not None else sys.stderr
    out = Path(out_dir)
    runs: list[RunData] = []
    skipped: list[Path] = []
    for d in run_dirs:
        p = Path(d)
        if p.is_dir() and not is_run_directory(p):
            raise FileFormatError(p, "not a training run directory (mentor-train --out writes "
                                     "one)")  # fmt: skip
        if p.is_dir() and not is_finished(p):
            print(f"mentor-report: warning: {p}: unfinished run (no best_genome.json yet), "
                  "skipped", file=stream)  # fmt: skip
            skipped.append(p)
            continue
        runs.append(load_run(p))
    evals = [load_eval(e) for e in eval_jsons]
    benches = [(Path(b), load_bench(b)) for b in bench_jsons]
    if not (runs or evals or benches):  # refused before anything is written
        raise MentorError("nothing to report: every run given is unfinished")

    names: dict[int, str] = {}
    taken: set[str] = set()
    for i, r in enumerate(runs):
        base = _slug(r.path.name)
        name, k = base, 2
        while name in taken:
            name, k = f"{base}-{k}", k + 1
        taken.add(name)
        names[i] = name

    earlier = _linked_figures(out)
    drawn: set[str] = set()

    def save(fig: Figure, name: str) -> str:
        write_bytes_atomic(out / name, _png(fig))
        drawn.add(name)
        return name

    md: list[str] = [REPORT_TITLE, ""]
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
            fig = topology(g, title=f"{r.label}: best genome", encoding=r.input_encoding,
                           feedback_action=r.feedback_action)  # fmt: skip
            md += [f"![topology]({save(fig, f'{tag}_topology.png')})", ""]
            md += [
                f"Best genome: {g.n_inputs} inputs + bias, {g.n_outputs} outputs, "
                f"{len(g.hidden_nodes)} hidden nodes, {len(g.enabled_connections)} of "
                f"{len(g.connections)} connection genes enabled.",
                "",
            ]
            md += ["<details><summary>genome tables</summary>", ""]
            md += genome_tables(g, r.input_encoding, r.feedback_action)
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

    for k, (path, doc) in enumerate(benches):
        lines = bench_markdown(doc, out, prefix=f"bench{k}-{_slug(path.stem)}")
        drawn.update(_FIGURE_LINK.findall("\n".join(lines)))  # its figures are this report's
        md += lines
    if skipped:
        md += ["## Skipped", ""]
        md += [f"- `{p}`: unfinished run (no best_genome.json yet)" for p in skipped]
        md += [""]
    report = out / REPORT_FILE
    write_text_atomic(report, "\n".join(md))
    for name in sorted(earlier - drawn):
        (out / name).unlink(missing_ok=True)
    return report


__all__ = [
    "REPORT_FILE",
    "REPORT_TITLE",
    "is_report_dir",
    "write_report",
]
