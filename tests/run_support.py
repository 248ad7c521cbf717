"""A run directory's files as a comparable snapshot, for tests that compare two runs, the
tiny training config those runs use, and how the tests start a run they interrupt."""

from __future__ import annotations

import csv
import io
import json
import signal
from pathlib import Path
from typing import Any

import yaml

#: a dual-stage Swarm-Robot run of seconds: 6 genomes x 3 generations on 3 scenarios
TINY = {
    "robot": "swarm",
    "framework": "dual",
    "generations": 3,
    "stage1_generations": 2,
    "n_scenarios": 3,
    "evolution": {"population_size": 6},
}


#: the shipped quick Swarm-Robot config, which :func:`tiny_config` shrinks
QUICK = (
    Path(__file__).resolve().parents[1]
    / "mentor_core/src/mentor_core/configs/train_swarm_quick.yaml"
)


def tiny_config(folder: Path) -> Path:
    """The quick Swarm-Robot config shrunk to a run of about a second (8 genomes x 3
    generations on 3 scenarios), written to ``folder/tiny.yaml``: the runs the fault tests
    stop and resume."""
    data = yaml.safe_load(QUICK.read_text())
    data.update(generations=3, stage1_generations=1, n_scenarios=3)
    data["evolution"]["population_size"] = 8
    path = folder / "tiny.yaml"
    path.write_text(yaml.safe_dump(data))
    return path


def train_argv(config: Path, framework: str, out: Path, *extra: str) -> list[str]:
    """mentor-train's arguments for a Swarm-Robot run of ``config`` (seed 5, quiet) into
    ``out``."""
    return ["--robot", "swarm", "--framework", framework, "--config", str(config),
            "--seed", "5", "--quiet", "--out", str(out), *extra]  # fmt: skip


def sigint_as_in_a_terminal() -> None:
    """``preexec_fn`` of a run the test stops with SIGINT: Ctrl-C's default, as a terminal's
    foreground job has it (Python then raises KeyboardInterrupt). A shell started without job
    control passes its background jobs SIGINT ignored, and the child would run on."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def without_seconds(history: str) -> list[dict[str, str]]:
    """The rows of a history CSV text without the wall-clock ``seconds`` column."""
    return [{k: v for k, v in row.items() if k != "seconds"}
            for row in csv.DictReader(io.StringIO(history))]  # fmt: skip


def snapshot(run: Path) -> dict[str, Any]:
    """Every file of a run directory, by name; the wall-clock ``seconds`` column of
    history.csv and of the checkpoint's copy of it left out."""
    files: dict[str, Any] = {}
    for path in sorted(run.iterdir()):
        if path.name == "history.csv":
            files[path.name] = without_seconds(path.read_text())
        elif path.name == "checkpoint.json":
            state = json.loads(path.read_text())
            state["history"] = without_seconds(state["history"])
            files[path.name] = state
        else:
            files[path.name] = path.read_bytes()
    return files
