"""A study folder of ``scripts/study.sh``, read back: its runs by config, robot and framework,
and its evaluations on the unseen bags and the benchmark's test split.

Layout (``scripts/study.sh OUT``): ``OUT/<config>/<robot>-<framework>-s<seed>/`` (a run
directory each), ``OUT/eval_unseen_<robot>.json`` (every best genome on ``bags/unseen/<robot>``,
labelled ``<config>-<framework>-s<seed>``), optionally ``OUT/eval_unseen_<robot>_deployed.json``
(the same, deployed, labels prefixed ``deployed-``), ``OUT/bench_<robot>/bench.json`` (the
test split, deployed) and ``OUT/bench_<robot>_plain/bench.json`` (the networks alone).
:func:`load_study` reads what is there; a run folder that is not finished is left out with a
warning, a corrupt file is a FileFormatError naming it.
"""

from __future__ import annotations

import math
import re
import sys
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, TextIO, TypeVar

from mentor_core.benchmark.document import load_bench
from mentor_core.errors import FileFormatError
from mentor_core.report.runs import EvalData, EvalRun, RunData, is_finished, load_eval, load_run

T = TypeVar("T")
ROBOTS = ("ugv", "swarm")
FRAMEWORKS = ("single", "dual")
_RUN_NAME = re.compile(r"^(ugv|swarm)-(single|dual)-s(\d+)$")


@dataclass(frozen=True)
class Study:
    """The finished runs and evaluations of one study folder."""

    root: Path
    runs: Mapping[tuple[str, str, str], Sequence[RunData]]
    """(config, robot, framework) -> its runs, by ascending seed."""
    unseen: Mapping[str, EvalData]
    """robot -> the plain evaluation on the unseen bags."""
    unseen_deployed: Mapping[str, EvalData]
    """robot -> the deployed evaluation on the unseen bags (where the study made one)."""
    bench: Mapping[str, dict[str, Any]]
    """robot -> the benchmark document of the test split (where the study made one)."""
    bench_plain: Mapping[str, dict[str, Any]] = field(default_factory=dict)
    """robot -> the same of the networks alone (where the study made one)."""

    @property
    def configs(self) -> list[str]:
        """The configs studied, in name order."""
        return sorted({c for c, _, _ in self.runs})

    def group(self, config: str, robot: str, framework: str) -> Sequence[RunData]:
        """The runs of one cell (empty when the study has none)."""
        return self.runs.get((config, robot, framework), ())

    def unseen_runs(self, config: str, robot: str, framework: str,
                    deployed: bool = False) -> list[EvalRun]:  # fmt: skip
        """The evaluations of one cell's genomes on the unseen bags, by ascending seed."""
        data = (self.unseen_deployed if deployed else self.unseen).get(robot)
        if data is None:
            return []
        prefix = f"{'deployed-' if deployed else ''}{config}-{framework}-s"
        return _by_seed([(r.label, r) for r in data.runs], prefix)


def _by_seed(named: Sequence[tuple[str, T]], prefix: str) -> list[T]:
    """The items named ``<prefix><seed>`` (the study's labels), by ascending seed."""
    found = [(int(name[len(prefix):]), item) for name, item in named
             if name.startswith(prefix) and name[len(prefix):].isdigit()]  # fmt: skip
    return [item for _, item in sorted(found, key=lambda x: x[0])]


def bench_success(doc: Mapping[str, Any] | None, config: str, framework: str) -> list[float]:
    """The success within the paper's limit, over all pairs, of each of one cell's genomes in
    a benchmark document (labelled ``<config>-<framework>-s<seed>``), by ascending seed; NaN
    where not computed, empty without a document."""
    if doc is None:
        return []
    named = [(str(c["name"]), c["scores"]["paper"]["overall"]["success"])
             for c in doc["contenders"]]  # fmt: skip
    values = _by_seed(named, f"{config}-{framework}-s")
    return [math.nan if v is None else float(v) for v in values]


def load_study(root: str | Path, log: TextIO | None = None) -> Study:
    """Read the study folder ``root`` (module docstring). FileFormatError when it holds no
    finished run."""
    stream = log if log is not None else sys.stderr
    base = Path(root)
    if not base.is_dir():
        raise FileFormatError(base, "no such study folder")
    runs: dict[tuple[str, str, str], list[RunData]] = {}
    for config_dir in sorted(p for p in base.iterdir() if p.is_dir()):
        for run_dir in sorted(config_dir.iterdir()):
            match = _RUN_NAME.match(run_dir.name)
            if not (run_dir.is_dir() and match):
                continue
            if not is_finished(run_dir):
                print(f"mentor-report: warning: {run_dir}: unfinished run, left out",
                      file=stream)  # fmt: skip
                continue
            run = load_run(run_dir)
            runs.setdefault((config_dir.name, match[1], match[2]), []).append(run)
    if not runs:
        raise FileFormatError(base, "holds no finished run (<config>/<robot>-<framework>-s<seed>)")
    for group in runs.values():
        group.sort(key=lambda r: r.seed)
    unseen = _evals(base, "eval_unseen_{}.json")
    deployed = _evals(base, "eval_unseen_{}_deployed.json")
    bench = _benches(base, "bench_{}")
    return Study(base, runs, unseen, deployed, bench, _benches(base, "bench_{}_plain"))


def study_inputs(root: str | Path) -> list[Path]:
    """What :func:`load_study` reads in ``root``: its run directories and its evaluation and
    benchmark files (so that an output may lie elsewhere in the folder, as the study's
    report does)."""
    base = Path(root)
    if not base.is_dir():
        return [base]
    runs = [d for c in base.iterdir() if c.is_dir() for d in c.iterdir()
            if d.is_dir() and _RUN_NAME.match(d.name)]  # fmt: skip
    files = [base / p.format(r) for r in ROBOTS
             for p in ("eval_unseen_{}.json", "eval_unseen_{}_deployed.json", "bench_{}",
                       "bench_{}_plain")]  # fmt: skip
    return sorted(runs) + [f for f in files if f.exists()]


def _benches(base: Path, pattern: str) -> dict[str, dict[str, Any]]:
    return {r: load_bench(p) for r in ROBOTS
            if (p := base / pattern.format(r) / "bench.json").is_file()}  # fmt: skip


def _evals(base: Path, pattern: str) -> dict[str, EvalData]:
    return {r: load_eval(p) for r in ROBOTS if (p := base / pattern.format(r)).is_file()}


__all__ = ["FRAMEWORKS", "ROBOTS", "Study", "bench_success", "load_study", "study_inputs"]
