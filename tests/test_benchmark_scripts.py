"""The scripts of ``benchmarks/`` (performance benchmarks, tools, probes) are kept runnable:
each answers ``--help`` (issue 54). One interpreter runs them all, each as ``__main__`` with
its own folder first on ``sys.path``, as ``python benchmarks/perf/x.py`` would."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

BENCHMARKS = Path(__file__).resolve().parents[1] / "benchmarks"
FOLDERS = ("perf", "tools", "probes")

RUN_ALL = """
import contextlib, io, runpy, sys
bad = []
for path in sys.argv[1:]:
    sys.argv = [path, "--help"]
    sys.path.insert(0, path.rsplit("/", 1)[0])
    out = io.StringIO()
    try:
        with contextlib.redirect_stdout(out):
            runpy.run_path(path, run_name="__main__")
        bad.append(path + ": did not exit on --help")
    except SystemExit as stop:
        if stop.code not in (0, None) or "usage" not in out.getvalue():
            bad.append(f"{path}: exit {stop.code}, no usage")
    except Exception as err:
        bad.append(f"{path}: {type(err).__name__}: {err}")
    sys.path.pop(0)
print("\\n".join(bad))
"""


def scripts() -> list[Path]:
    return sorted(p for folder in FOLDERS for p in (BENCHMARKS / folder).glob("*.py"))


def test_benchmarks_holds_only_sorted_scripts() -> None:
    assert not list(BENCHMARKS.glob("*.py")), "a script belongs in perf/, tools/ or probes/"
    assert len(scripts()) >= 25


def test_every_script_answers_help() -> None:
    done = subprocess.run([sys.executable, "-c", RUN_ALL, *map(str, scripts())],
                          capture_output=True, text=True, timeout=600)  # fmt: skip
    assert done.returncode == 0, done.stderr[-3000:]
    assert done.stdout.strip() == "", done.stdout
