"""The reproduction page: every numbered result of the paper beside a study's, with figures.

:func:`write_reproduction` reads a study folder (:func:`~mentor_core.report.study.load_study`),
checks every claim of :data:`~mentor_core.report.paper_claims.CLAIMS` on each config studied,
and writes one Markdown page (a table: where the paper says it, what it says, each config's
numbers and verdict; then why, and the study's cells and their training time) and, in the
folder named after the page's stem, the paper's Figs. 7-18 redrawn with one panel per config.
Every file is written atomically; the page last, so a page never links a figure not written.
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import TextIO

from matplotlib.figure import Figure

from mentor_core.atomic import write_bytes_atomic, write_text_atomic
from mentor_core.errors import FileFormatError
from mentor_core.report.figures import _png
from mentor_core.report.paper_claims import CLAIMS, ROBOT_NAMES, SETTLING
from mentor_core.report.paper_figures import (
    complexity_panels,
    convergence_panels,
    niche_panels,
    pareto_panels,
)
from mentor_core.report.study import FRAMEWORKS, ROBOTS, Study, load_study
from mentor_core.report.tables import _md_table

PAGE_TITLE = "# The paper, reproduced"
#: the paper's figure numbers per robot: Pareto, convergence, niches dual and single,
#: complexity dual and single
_FIGURES = {"ugv": (7, 8, 9, 10, 11, 12), "swarm": (13, 14, 15, 16, 17, 18)}


def write_reproduction(study_dir: str | Path, page: str | Path, log: TextIO | None = None) -> Path:
    """Write the reproduction page of ``study_dir`` to ``page`` and its figures into the
    folder ``page``'s stem names beside it. Returns the page's path."""
    study = load_study(study_dir, log)
    configs = compared_configs(study)
    if not configs:
        raise FileFormatError(study.root, "holds no config trained in both frameworks")
    page_path = Path(page)
    figures = page_path.with_suffix("")
    figures.mkdir(parents=True, exist_ok=True)
    links = _draw(study, configs, figures)
    lines = [PAGE_TITLE, "", *_preamble(study, configs), *_claims_table(study, configs),
             *_cells(study)]  # fmt: skip
    lines += ["## The figures in the paper's layout", ""]
    for caption, name in links:
        lines += [f"### {caption}", "", f"![{caption}]({figures.name}/{name})", ""]
    write_text_atomic(page_path, "\n".join(lines).rstrip("\n") + "\n")
    print(f"mentor-report: {len(CLAIMS)} claims, {len(links)} figures", file=log or sys.stderr)
    return page_path


def compared_configs(study: Study) -> list[str]:
    """The configs of ``study`` trained in both frameworks for some robot: the paper compares
    the two stages, so a config trained in one (an ablation arm) has no column."""
    return [c for c in study.configs
            if any(study.group(c, r, "single") and study.group(c, r, "dual") for r in ROBOTS)]


def _preamble(study: Study, configs: list[str]) -> list[str]:
    seeds = sorted({r.seed for group in study.runs.values() for r in group})
    return [
        "Written by `mentor-report --paper STUDY --out docs/reproduction.md` from a "
        f"`scripts/study.sh` folder (configs {', '.join(f'`{c}`' for c in configs)}; seeds "
        f"{', '.join(map(str, seeds))}; its command and time: `benchmarks/RESULTS.md`, \"The "
        "paper side by side\"); do not edit it by hand. Each row is one result the paper "
        "states in Sections IV-V, its figure or table, and this implementation's "
        "numbers under each config: mean ± sample sd over the seeds. Where the paper compares "
        "two groups, the seeds are compared with the two-sided Mann-Whitney U test (p < 0.05 "
        "to hold or fail; otherwise *not shown*). `original` is the paper's own settings "
        "(Table I, its inputs and actions, the choices the paper leaves open made in "
        "`docs/algorithm.md`); `paper` is the shipped configs, which depart from it to learn "
        f"(`docs/departures.md`). Niche shares are judged from generation "
        f"{SETTLING} on: every run starts as one species.",
        "",
    ]


def _claims_table(study: Study, configs: list[str]) -> list[str]:
    header = ["where", "robot", "the paper"]
    for config in configs:
        header += [f"`{config}`", "verdict"]
    rows, notes = [], []
    for k, claim in enumerate(CLAIMS, start=1):
        row = [claim.where, ROBOT_NAMES.get(claim.robot, claim.robot), claim.paper]
        whys: dict[str, list[str]] = {}
        for config in configs:
            finding = claim.check(study, config)
            row += [finding.text, f"**{finding.verdict}**"]
            if finding.why:
                whys.setdefault(finding.why, []).append(f"`{config}`")
        rows.append(row)
        for why, names in whys.items():
            scope = "" if len(names) == len(configs) else " (" + ", ".join(names) + ")"
            notes.append(f"{k}{scope}: {why}")
    numbered = [[str(k), *r] for k, r in enumerate(rows, start=1)]
    lines = ["## Every claim", "", *_md_table(["#", *header], numbered)]
    if notes:
        lines += ["Why each verdict reads as it does:", "", *[f"- {n}" for n in notes], ""]
    return lines


def _cells(study: Study) -> list[str]:
    rows = []
    for config in study.configs:
        for robot in ROBOTS:
            for framework in FRAMEWORKS:
                runs = study.group(config, robot, framework)
                if not runs:
                    continue
                minutes = [sum(r.seconds for r in run.history) / 60.0 for run in runs]
                rows.append([f"`{config}`", ROBOT_NAMES[robot], framework,
                             ", ".join(str(r.seed) for r in runs),
                             f"{sum(minutes) / len(minutes):.1f}"])  # fmt: skip
    header = ["config", "robot", "framework", "seeds", "minutes a run (evolution)"]
    return ["## The study", "", *_md_table(header, rows)]


def _draw(study: Study, configs: list[str], folder: Path) -> list[tuple[str, str]]:
    """Draw every figure into ``folder``; (caption, file name) of each."""
    links: list[tuple[str, str]] = []

    def save(fig: Figure, number: int, caption: str, slug: str) -> None:
        name = f"fig{number:02d}-{slug}.png"
        write_bytes_atomic(folder / name, _png(fig))
        links.append((f"Fig. {number}: {caption}", name))

    for robot in ROBOTS:
        pareto, conv, niche_dual, niche_single, box_dual, box_single = _FIGURES[robot]
        who = ROBOT_NAMES[robot]
        by = {fw: {c: study.group(c, robot, fw) for c in configs} for fw in FRAMEWORKS}
        if not any(runs for cell in by.values() for runs in cell.values()):
            continue
        save(pareto_panels(by["dual"], f"{who}: Pareto front of the dual stage's stage 1"),
             pareto, f"{who}, Pareto front (dual stage)", f"{robot}-pareto")  # fmt: skip
        save(convergence_panels({c: {fw: by[fw][c] for fw in FRAMEWORKS} for c in configs},
                                f"{who}: convergence"),
             conv, f"{who}, convergence histories", f"{robot}-convergence")  # fmt: skip
        for number, fw in ((niche_dual, "dual"), (niche_single, "single")):
            save(niche_panels(by[fw], robot, f"{who}: niche sizes, {fw} stage"),
                 number, f"{who}, niche sizes ({fw} stage)", f"{robot}-niches-{fw}")  # fmt: skip
        for number, fw in ((box_dual, "dual"), (box_single, "single")):
            save(complexity_panels(by[fw], f"{who}: performance by complexity, {fw} stage"),
                 number, f"{who}, performance by complexity ({fw} stage)",
                 f"{robot}-complexity-{fw}")  # fmt: skip
    links.sort(key=lambda link: int(link[1][3:5]))
    return links


__all__ = ["PAGE_TITLE", "write_reproduction"]
