"""A deployment layer's flag on the command lines (``--turn-gain``, ``--view-margin``): taken by
``mentor-bench`` into each genome's settings, replacing the robot's beside ``--deployed``,
refused in one line when bad."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from mentor_core.cli import bench as bench_cli
from mentor_core.cli import evaluate as eval_cli

REPO = Path(__file__).resolve().parents[1]
SWARM_PLANNER = REPO / "planners" / "swarm-paper-dual-s1.json"


def check_deployment_flag(
    flag: str, value: float, bad: str, key: str, off: str, tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
) -> None:  # fmt: skip
    """``mentor-bench --flag value`` records ``value`` as the genome's setting ``key``; beside
    ``--deployed``, ``--flag off`` replaces the robot's deployed value and leaves the layer
    out (no ``key`` among the settings); a ``bad`` value is one line naming the flag and
    status 2 in both ``mentor-bench`` and ``mentor-eval``."""
    common = [str(SWARM_PLANNER), "--robot", "swarm", "--families", "rooms",
              "--pairs-per-family", "2", "--baselines", "none", "--no-oracle"]  # fmt: skip
    for extra, expected in (([flag, str(value)], value), (["--deployed", flag, off], None)):
        out = tmp_path / f"bench{len(extra)}"
        assert bench_cli.main([*common, *extra, "--out", str(out)]) == 0
        doc = json.loads((out / "bench.json").read_text())
        assert doc["contenders"][0]["settings"].get(key) == expected
    for main in (bench_cli.main, eval_cli.main):
        robot = ["--robot", "swarm"] if main is bench_cli.main else ["--bag", "bags/unseen/swarm"]
        capsys.readouterr()
        assert main([str(SWARM_PLANNER), *robot, flag, bad]) == 2
        err = capsys.readouterr().err
        assert flag in err and len(err.strip().splitlines()) == 1
