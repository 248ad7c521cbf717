"""A deployment layer's flag on the command lines (``--turn-gain``, ``--view-margin``): taken by
``mentor-bench`` into each genome's settings, refused in one line when bad or beside
``--deployed``."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from mentor_core.cli import bench as bench_cli
from mentor_core.cli import evaluate as eval_cli

REPO = Path(__file__).resolve().parents[1]
SWARM_PLANNER = REPO / "planners" / "swarm-paper-dual-s1.json"


def check_deployment_flag(
    flag: str, value: float, bad: str, key: str, tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
) -> None:  # fmt: skip
    """``mentor-bench --flag value`` records ``value`` as the genome's setting ``key``; a
    ``bad`` value, or any beside ``--deployed``, is one line naming the flag and status 2 in
    both ``mentor-bench`` and ``mentor-eval``."""
    out = tmp_path / "bench"
    assert bench_cli.main([str(SWARM_PLANNER), "--robot", "swarm", "--families", "rooms",
                           "--pairs-per-family", "2", "--baselines", "none", "--no-oracle",
                           flag, str(value), "--out", str(out)]) == 0  # fmt: skip
    doc = json.loads((out / "bench.json").read_text())
    assert doc["contenders"][0]["settings"][key] == value
    for main in (bench_cli.main, eval_cli.main):
        robot = ["--robot", "swarm"] if main is bench_cli.main else ["--bag", "bags/unseen/swarm"]
        for extra in ([flag, bad], ["--deployed", flag, str(value)]):
            capsys.readouterr()
            assert main([str(SWARM_PLANNER), *robot, *extra]) == 2
            err = capsys.readouterr().err
            assert flag in err and len(err.strip().splitlines()) == 1
