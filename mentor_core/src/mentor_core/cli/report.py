"""``mentor-report``: figures and a Markdown report of training runs and evaluations.

    mentor-report runs/ugv-single runs/ugv-dual --eval eval/ugv.json --out report/
    mentor-report runs/*-s* --out report/       # unfinished runs are skipped with a warning
    mentor-report runs/ugv-dual --bench bench/ugv/bench.json --out report/

Writes PNG figures (Pareto front, convergence, niche sizes, performance vs complexity,
topology, trajectories; with ``--bench`` the benchmark's success per family and example
trajectories) and ``report.md`` with the numbers into ``--out``: a new or empty folder, or one
holding an earlier report (replaced: its figures this report does not draw are removed); a
folder holding other files only with ``--force``, and never a run directory or a folder where a
report file would replace an input. Checked before any run is read.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Iterable
from pathlib import Path

import matplotlib

from mentor_core.cli.arguments import Parser, fail
from mentor_core.cli.outputs import OutputError, exists
from mentor_core.errors import MentorError
from mentor_core.report.markdown import REPORT_FILE, is_report_dir, write_report


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
    p.add_argument("--out", required=True, type=Path, help="output directory")
    p.add_argument(
        "--force", action="store_true", help="write into an --out folder that holds other files"
    )
    return p


def check_report_dir(option: str, path: Path, inputs: Iterable[Path], force: bool) -> None:
    """``path`` may receive a report (``report.md`` and PNG figures): it is no input run
    directory nor inside one, it holds no input a report file would replace, and unless
    ``force`` it is new, empty or an earlier report (which the report replaces)."""
    target = path.resolve()
    if exists(path) and not path.is_dir():
        raise OutputError(option, path, "is not a directory")
    for given in inputs:
        source = given.resolve()
        if target == source or source in target.parents:
            raise OutputError(option, path, f"is inside the input {given}; not writing there")
        if source.parent == target and (source.name == REPORT_FILE or source.suffix == ".png"):
            raise OutputError(option, path, f"a report would replace the input {given}")
    if force or not path.is_dir() or not any(path.iterdir()) or is_report_dir(path):
        return
    raise OutputError(
        option, path, "holds files but no earlier report; pass --force to write into it"
    )


def main(argv: list[str] | None = None) -> int:
    """Entry point; returns the exit status (2 on bad input)."""
    parser = build_parser()
    args = parser.parse_args(argv)
    if not (args.runs or args.eval or args.bench):
        parser.error("give a run directory, --eval or --bench")
    matplotlib.use("Agg")  # no display needed; the report draws on the Agg canvas only
    try:
        check_report_dir("--out", args.out, [*args.runs, *args.eval, *args.bench], args.force)
        report = write_report(args.runs, args.eval, args.out, bench_jsons=args.bench)
    except (MentorError, OSError) as err:
        return fail("mentor-report", err)
    print(f"mentor-report: wrote {report}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
