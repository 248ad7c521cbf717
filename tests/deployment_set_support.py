"""A stage's setting on the command lines (``--deployment``, ``--set stages.<stage>.<field>=V``):
taken by ``mentor-bench`` into each genome's settings, turned off on top of the shipped
deployment by another ``--set``, refused in one line naming the key when bad."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from mentor_core.cli import bench as bench_cli
from mentor_core.cli import evaluate as eval_cli

REPO = Path(__file__).resolve().parents[1]
SWARM_PLANNER = REPO / "planners" / "swarm-paper-dual-s1.json"


def check_stage_setting(
    setting: str, value: float, bad: str, key: str, off: str, tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
) -> None:  # fmt: skip
    """``mentor-bench --set <setting>=<value>`` records ``value`` as the genome's setting
    ``key``; ``--deployment shipped --set <off>`` replaces the shipped deployment's stage and
    leaves the layer out (no ``key`` among the settings); ``--set <setting>=<bad>`` is one line
    naming the key and status 2 in both ``mentor-bench`` and ``mentor-eval``."""
    common = [str(SWARM_PLANNER), "--robot", "swarm", "--families", "rooms",
              "--pairs-per-family", "2", "--baselines", "none", "--no-oracle"]  # fmt: skip
    for extra, expected in (
        (["--deployment", "none", "--set", f"{setting}={value}"], value),
        (["--deployment", "shipped", "--set", off], None),
    ):
        out = tmp_path / f"bench-{extra[1]}"
        assert bench_cli.main([*common, *extra, "--out", str(out)]) == 0
        doc = json.loads((out / "bench.json").read_text())
        assert doc["contenders"][0]["settings"].get(key) == expected
    for main in (bench_cli.main, eval_cli.main):
        robot = ["--robot", "swarm"] if main is bench_cli.main else ["--bag", "bags/unseen/swarm"]
        capsys.readouterr()
        assert main([str(SWARM_PLANNER), *robot, "--set", f"{setting}={bad}"]) == 2
        err = capsys.readouterr().err
        assert setting in err and len(err.strip().splitlines()) == 1
