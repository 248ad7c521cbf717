"""``mentor-report``: figures and a Markdown report of training runs and evaluations.

    mentor-report runs/ugv-single runs/ugv-dual --eval eval/ugv.json --out report/
    mentor-report runs/*-s* --out report/       # unfinished runs are skipped with a warning
    mentor-report runs/ugv-dual --bench bench/ugv/bench.json --out report/
    mentor-report --paper out/study --out docs/reproduction.md   # the paper, side by side

Writes PNG figures (Pareto front, convergence, niche sizes, performance vs complexity,
topology, trajectories; with ``--bench`` the benchmark's success per family and example
trajectories) and ``report.md`` with the numbers into ``--out``: a new or empty folder, or
with ``--force`` one holding files (an earlier report is replaced: its figures this report
does not draw are removed); never a run directory, an input's folder or a folder holding an
input (``cli.outputs``). Checked before any run is read. A path that is no run directory, and
a report with nothing in it (every run unfinished), are refused.

With ``--paper STUDY`` (a ``scripts/study.sh`` folder) it writes the reproduction page
instead: ``--out`` names the page (``.md``), its figures go into the folder of the page's
stem beside it (``docs/reproduction/``); an existing page or a non-empty figure folder needs
``--force`` (``report.reproduction``).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import matplotlib

from mentor_core.cli.arguments import Parser, fail
from mentor_core.cli.outputs import check_file, check_folder
from mentor_core.errors import MentorError
from mentor_core.report.markdown import write_report
from mentor_core.report.reproduction import write_reproduction
from mentor_core.report.study import study_inputs


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of mentor-report."""
    p = Parser(prog="mentor-report", description=__doc__.split("\n")[0])
    p.add_argument("runs", nargs="*", type=Path, help="run directories (mentor-train --out)")
    p.add_argument(
        "--eval",
        action="append",
        default=[],
        type=Path,
        metavar="EVAL_JSON",
        help="mentor-eval JSON file (repeatable)",
    )
    p.add_argument(
        "--bench",
        action="append",
        default=[],
        type=Path,
        metavar="BENCH_JSON",
        help="mentor-bench JSON file (repeatable)",
    )
    p.add_argument(
        "--paper",
        type=Path,
        metavar="STUDY_DIR",
        help="write the reproduction page of a scripts/study.sh folder: --out names the page "
        "(.md), its figures go into the folder of the page's stem",
    )
    p.add_argument("--out", required=True, type=Path,
                   help="output directory (with --paper: the page, .md)")  # fmt: skip
    p.add_argument(
        "--force",
        action="store_true",
        help="write into an --out folder that holds files (an earlier report's, replaced); "
        "never a run directory or an input's folder",
    )
    return p


def main(argv: list[str] | None = None) -> int:
    """Entry point; returns the exit status (2 on bad input)."""
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.paper is not None:
        if args.runs or args.eval or args.bench:
            parser.error("--paper takes a study folder alone: no run directory, --eval or --bench")
        if args.out.suffix != ".md":
            parser.error(f"--out {args.out}: with --paper it names the page, a .md file")
    elif not (args.runs or args.eval or args.bench):
        parser.error("give a run directory, --eval or --bench")
    matplotlib.use("Agg")  # no display needed; the report draws on the Agg canvas only
    try:
        if args.paper is not None:
            inputs = study_inputs(args.paper)
            check_file("--out", args.out, inputs, args.force)
            check_folder("--out", args.out.with_suffix(""), inputs, args.force)
            written = write_reproduction(args.paper, args.out)
        else:
            check_folder("--out", args.out, [*args.runs, *args.eval, *args.bench], args.force)
            written = write_report(args.runs, args.eval, args.out, bench_jsons=args.bench)
    except (MentorError, OSError) as err:
        return fail("mentor-report", err)
    print(f"mentor-report: wrote {written}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
