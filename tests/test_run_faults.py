"""A run directory is one transaction: killed or interrupted anywhere, a run resumes to the
files of an unbroken run; one writer at a time; nothing of another run is overwritten.

Fault injection: ``fault_hook.py`` stops a ``mentor-train`` process with SIGKILL or SIGINT at a
seeded point of its file writes (inside an atomic write, with the temporary file written but
not renamed, or just after a rename) or after a seeded time; ``--resume`` then must give every
file of the unbroken run (history's wall-clock ``seconds`` aside). A tiny quick Swarm-Robot
config keeps each run about a second.
"""

from __future__ import annotations

import csv
import io
import json
import os
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import fault_hook
import numpy as np
import pytest
from run_support import sigint_as_in_a_terminal, snapshot, tiny_config
from run_support import train_argv as argv

from mentor_core.cli import train as train_cli

HOOK = Path(__file__).with_name("fault_hook.py")
# the final phase: the last writes of a run (population.json onwards), 2 points each
FINAL_POINTS = 8


class Reference:
    """An unbroken run: its files, the number of write points it passed, its generations'
    time."""

    def __init__(self, config: Path, framework: str, out: Path) -> None:
        hook = fault_hook.install(out)
        try:
            assert train_cli.main(argv(config, framework, out)) == 0
        finally:
            hook.remove()
        self.points = hook.seen
        self.files = snapshot(out)
        history = csv.DictReader(io.StringIO((out / "history.csv").read_text()))
        self.seconds = sum(float(row["seconds"]) for row in history)  # training, no start-up


@pytest.fixture(scope="module")
def config(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return tiny_config(tmp_path_factory.mktemp("config"))


@pytest.fixture(scope="module")
def references(config: Path, tmp_path_factory: pytest.TempPathFactory) -> dict[str, Reference]:
    root = tmp_path_factory.mktemp("references")
    return {fw: Reference(config, fw, root / fw) for fw in ("dual", "single")}


def run_hooked(
    config: Path, framework: str, out: Path, event: int, sig: str
) -> subprocess.Popen[str]:
    cmd = [sys.executable, str(HOOK), str(event), sig, str(out), "--",
           *argv(config, framework, out)]  # fmt: skip
    return subprocess.Popen(cmd, stderr=subprocess.PIPE, text=True,
                            preexec_fn=sigint_as_in_a_terminal)  # fmt: skip


# (framework, signal, where): at "any" write point, at one of the "final" phase, inside the
# final "checkpoint" write (its temporary file written), at the "end" (after that write), or
# after a "timed" wait in the generations
CASES = [
    *[("dual", "SIGKILL", "any")] * 4,
    *[("dual", "SIGINT", "any")] * 2,
    ("dual", "SIGKILL", "final"),
    ("dual", "SIGINT", "final"),
    ("dual", "SIGKILL", "checkpoint"),
    ("single", "SIGKILL", "final"),
    ("single", "SIGINT", "any"),
    ("single", "SIGINT", "end"),
    ("dual", "SIGKILL", "timed"),
    ("dual", "SIGINT", "timed"),
]


def kill_point(where: str, points: int, rng: np.random.Generator) -> int:
    """The write point (1-based, 0: none) a case stops its run at."""
    first = {"any": 1, "final": points - FINAL_POINTS + 1}
    fixed = {"checkpoint": points - 1, "end": points, "timed": 0}
    return fixed[where] if where in fixed else int(rng.integers(first[where], points + 1))


@pytest.mark.parametrize("case", range(len(CASES)))
def test_a_run_stopped_anywhere_resumes_to_the_unbroken_runs_files(
    case: int, config: Path, references: dict[str, Reference], tmp_path: Path
) -> None:
    framework, sig, where = CASES[case]
    ref = references[framework]
    rng = np.random.default_rng([17, case])
    out = tmp_path / "run"
    assert ref.points % 2 == 0 and ref.points > FINAL_POINTS  # 2 points a write
    event = kill_point(where, ref.points, rng)
    proc = run_hooked(config, framework, out, event, sig)
    if where == "timed":
        while not (out / "config.yaml").exists() and proc.poll() is None:
            time.sleep(0.01)
        time.sleep(rng.uniform(0.0, 0.6 * ref.seconds))
        proc.send_signal(signal.Signals[sig])
    _, err = proc.communicate(timeout=120)
    stopped = -9 if sig == "SIGKILL" else 130
    expected = {0, stopped} if where == "timed" else {stopped}
    assert proc.returncode in expected, err
    if proc.returncode == 130:
        assert "continue with --resume" in err
    assert train_cli.main(argv(config, framework, out, "--resume")) == 0
    assert snapshot(out) == ref.files, f"{framework} {sig} at point {event} of {ref.points}"


def test_two_writers_into_one_directory(
    config: Path, references: dict[str, Reference], tmp_path: Path
) -> None:
    """Started together, one writes the run and the other is refused with one line."""
    out = tmp_path / "run"
    procs = [run_hooked(config, "dual", out, 0, "SIGKILL") for _ in range(2)]
    results = [(p.wait(timeout=120), p.stderr.read()) for p in procs]  # type: ignore[union-attr]
    assert sorted(rc for rc, _ in results) == [0, 2], results
    refusal = next(err for rc, err in results if rc == 2).splitlines()
    assert refusal[-1] == "fault_hook: 0 points"
    assert refusal[-2].startswith(f"mentor-train: {out}: ")
    # usually at the same time (the holder named); one that came after the end finds the run
    assert "in use by " in refusal[-2] or "finished run" in refusal[-2]
    assert snapshot(out) == references["dual"].files


def test_the_lock_names_its_holder_and_goes_with_it(config: Path, tmp_path: Path,
                                                      capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "run"
    out.mkdir()
    code = ("import sys; from mentor_core.training.run_lock import RunLock\n"
            f"lock = RunLock.acquire({str(out)!r}); print('held', flush=True); sys.stdin.read()")
    holder = subprocess.Popen([sys.executable, "-c", code], stdin=subprocess.PIPE,
                              stdout=subprocess.PIPE, text=True)  # fmt: skip
    try:
        assert holder.stdout is not None and holder.stdout.readline() == "held\n"
        assert train_cli.main(argv(config, "dual", out)) == 2
        err = capsys.readouterr().err.splitlines()
        assert len(err) == 1, err  # refused before anything else is said
        assert err[0].startswith(f"mentor-train: {out}: in use by pid {holder.pid} on host "
                                 f"{socket.gethostname()} since ")  # fmt: skip
        assert [p.name for p in out.iterdir()] == ["train.lock"]
    finally:
        holder.kill()  # kill -9: the kernel lets go of the lock, whatever the file says
        holder.wait()
    assert train_cli.main(argv(config, "dual", out)) == 0
    assert not (out / "train.lock").exists()


def test_resume_completes_a_run_stopped_in_its_final_writes(
    config: Path, references: dict[str, Reference], tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
) -> None:
    """A final checkpoint without population.json, pareto.json, best_genome.json and the last
    history row (what a kill in the final writes left before): --resume writes them again."""
    out = tmp_path / "run"
    assert train_cli.main(argv(config, "single", out)) == 0
    for name in ("population.json", "pareto.json", "best_genome.json"):
        (out / name).unlink()
    history = (out / "history.csv").read_text().splitlines(keepends=True)
    (out / "history.csv").write_text("".join(history[:-1]))
    capsys.readouterr()
    assert train_cli.main(argv(config, "single", out, "--resume")) == 0
    assert "wrote the finished run's history.csv, population.json" in capsys.readouterr().err
    assert snapshot(out) == references["single"].files


def test_a_finished_run_is_left_as_it_is(
    config: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "run"
    assert train_cli.main(argv(config, "single", out)) == 0
    before = {p.name: p.stat().st_mtime_ns for p in out.iterdir()}
    capsys.readouterr()
    assert train_cli.main(argv(config, "single", out, "--resume")) == 0
    assert "holds a finished run; nothing to do" in capsys.readouterr().err
    assert train_cli.main(argv(config, "single", out)) == 2
    err = capsys.readouterr().err.splitlines()
    assert err == [f"mentor-train: {out}: already holds a finished run (3 generations); "
                   "choose another --out"]  # fmt: skip
    assert {p.name: p.stat().st_mtime_ns for p in out.iterdir()} == before


def refused(args: list[str], capsys: pytest.CaptureFixture[str], lines: int = 1) -> str:
    """The line mentor-train is refused with (``lines``: 2 when the checks of the trainer
    refuse, after the line that says what the run would be)."""
    capsys.readouterr()
    assert train_cli.main(args) == 2
    err = capsys.readouterr().err.splitlines()
    assert len(err) == lines, err
    return err[-1]


def test_a_directory_of_something_else_is_refused(
    config: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    notes = tmp_path / "notes"
    notes.mkdir()
    (notes / "todo.txt").write_text("keep me")
    line = refused(argv(config, "dual", notes), capsys)
    assert line == f"mentor-train: {notes}: holds todo.txt and no run; choose a new or empty --out"
    assert refused(argv(config, "dual", notes, "--resume"), capsys).startswith(
        f"mentor-train: {notes}: nothing to resume: holds todo.txt but no checkpoint.json"
    )
    assert [p.name for p in notes.iterdir()] == ["todo.txt"]
    # a run stopped before its first checkpoint: not overwritten, resumed only as itself
    out = tmp_path / "early"
    assert train_cli.main(argv(config, "dual", out, "--seed", "6")) == 0
    (out / "checkpoint.json").unlink()
    kept = snapshot(out)
    assert "continue it with --resume" in refused(argv(config, "dual", out), capsys)
    assert refused(argv(config, "dual", out, "--resume"), capsys, lines=2) == (
        f"mentor-train: {out / 'config.yaml'}: was written by a run of a different config or seed"
    )
    assert snapshot(out) == kept
    assert train_cli.main(argv(config, "dual", out, "--seed", "6", "--resume")) == 0
    # a run in progress: continued only with --resume, never by the library's words
    assert train_cli.main(argv(config, "dual", tmp_path / "full")) == 0
    stopped = tmp_path / "full" / "checkpoint.json"
    state = json.loads(stopped.read_text())
    state["generation"] = 1
    stopped.write_text(json.dumps(state))
    assert refused(argv(config, "dual", tmp_path / "full"), capsys).endswith(
        "already holds a run stopped after generation 1 of 3; continue it with --resume, or "
        "choose another --out"
    )
    stopped.write_text("[1, 2]")  # a checkpoint that is no checkpoint: one line too
    assert refused(argv(config, "dual", tmp_path / "full", "--resume"), capsys, lines=2) == (
        f"mentor-train: {stopped}: expected a JSON object, got an array"
    )


def test_resume_of_a_missing_or_empty_directory_is_refused(
    config: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    missing = tmp_path / "missing"
    assert refused(argv(config, "dual", missing, "--resume"), capsys) == (
        f"mentor-train: {missing}: nothing to resume: no such directory (start the run "
        "without --resume)"
    )
    assert not missing.exists()
    empty = tmp_path / "empty"
    empty.mkdir()
    assert refused(argv(config, "dual", empty, "--resume"), capsys) == (
        f"mentor-train: {empty}: nothing to resume: the directory is empty (start the run "
        "without --resume)"
    )
    assert list(empty.iterdir()) == []


def test_stale_temporary_files_go_and_outputs_get_ordinary_modes(
    config: Path, references: dict[str, Reference], tmp_path: Path
) -> None:
    out = tmp_path / "run"
    out.mkdir()
    ours = [".checkpoint.json.k2x_9qzt.tmp", ".history.csv.0123abcd.tmp"]  # mkstemp's, ours
    theirs = [".notes.txt.0123abcd.tmp", "checkpoint.json.tmp", ".checkpoint.json.tmp"]
    for name in ours:
        (out / name).write_text("{half a chec")
    for name in theirs:
        (out / name).write_text("not ours")
    previous = os.umask(0o027)
    try:
        assert train_cli.main(argv(config, "dual", out)) == 2  # others' files: refused
        assert sorted(p.name for p in out.iterdir()) == sorted(ours + theirs)  # untouched
        for name in theirs:
            (out / name).unlink()
        # the temporary files of a run's start, but not its config.yaml: resumed from the start
        assert train_cli.main(argv(config, "dual", out, "--resume")) == 0
        modes = {p.name: p.stat().st_mode & 0o777 for p in out.iterdir()}
    finally:
        os.umask(previous)
    assert modes == dict.fromkeys(references["dual"].files, 0o640)
    assert snapshot(out) == references["dual"].files
