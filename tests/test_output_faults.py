"""mentor-eval --record, mentor-bench --out and a full disk, stopped inside their writes
(issue 58), as ``test_run_faults.py`` stops mentor-train.

``fault_hook.py`` kills the command (SIGKILL) at a point of its writes into the output folder,
or fails one write as a full disk does. Afterwards no output is half-written: each is absent,
the earlier one, or whole; the next run of the same command removes what the killed one left
(a bag's staging folder) and ends with the outputs of an unbroken run.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest
from run_support import snapshot, tiny_config, train_argv

from mentor_core.cli import bench, evaluate
from mentor_core.cli import train as train_cli
from mentor_core.files.bags import read_episode_bag

ROOT = Path(__file__).resolve().parents[1]
HOOK = Path(__file__).with_name("fault_hook.py")
PLANNER = ROOT / "planners" / "swarm-paper-dual-s1.json"
UNSEEN_SWARM = ROOT / "bags" / "unseen" / "swarm"


def eval_argv(out: Path, *extra: str) -> list[str]:
    return [str(PLANNER), "--bag", str(UNSEEN_SWARM), "--record", str(out / "rec"),
            "--out", str(out / "eval.json"), *extra]  # fmt: skip


def bench_argv(out: Path, *extra: str) -> list[str]:
    return ["--robot", "swarm", "--families", "rooms", "--pairs-per-family", "1",
            "--baselines", "bug", "--no-oracle", "--out", str(out / "bench"), *extra]  # fmt: skip


def hooked(command: str, args: list[str], folder: Path, event: int, sig: str = "SIGKILL") -> Any:
    cmd = [sys.executable, str(HOOK), str(event), sig, str(folder), "--", command, *args]
    return subprocess.run(cmd, capture_output=True, text=True, timeout=300)


def points(command: str, args: list[str], folder: Path) -> int:
    done = hooked(command, args, folder, 0)
    assert done.returncode == 0, done.stderr
    return int(done.stderr.strip().splitlines()[-1].split()[1])


def everything(folder: Path) -> dict[str, bytes]:
    """Every file under ``folder``, hidden ones included, by relative path."""
    return {str(p.relative_to(folder)): p.read_bytes() for p in folder.rglob("*") if p.is_file()}


def without_seconds(doc: dict[str, Any]) -> dict[str, Any]:
    for entry in doc["contenders"]:
        entry.pop("seconds", None)
    return doc


@pytest.fixture(scope="module")
def eval_reference(tmp_path_factory: pytest.TempPathFactory) -> tuple[dict[str, bytes], int]:
    out = tmp_path_factory.mktemp("eval_ref")
    n = points("mentor-eval", eval_argv(out), out)
    return everything(out), n


def test_a_killed_record_leaves_no_half_bag_and_the_next_run_cleans_up(
    eval_reference: tuple[dict[str, bytes], int], tmp_path: Path
) -> None:
    reference, n = eval_reference
    assert n >= 4  # the bag's files and rename, eval.json's two points
    for event in range(1, n + 1):
        out = tmp_path / f"at{event}"
        out.mkdir()
        killed = hooked("mentor-eval", eval_argv(out), out, event)
        assert killed.returncode == -9
        rec = out / "rec"
        if rec.exists():  # whole, or not there at all
            assert len(read_episode_bag(rec).robots) > 0
        assert evaluate.main(eval_argv(out, "--force")) == 0
        assert everything(out) == reference, f"killed at point {event} of {n}"


def test_a_killed_replacement_gives_the_earlier_bag_back(
    eval_reference: tuple[dict[str, bytes], int], tmp_path: Path
) -> None:
    """Killed between moving the earlier bag aside and renaming the new one into place."""
    _, n = eval_reference
    out = tmp_path / "out"
    out.mkdir()
    assert evaluate.main(eval_argv(out)) == 0
    earlier = everything(out / "rec")
    # a replacing run passes n + 1 points: the bag's files (n - 3), the earlier bag moved
    # aside (into its staging folder inside out/), the new one renamed, eval.json's two
    moved_aside = n - 2
    killed = hooked("mentor-eval", eval_argv(out, "--force"), out, moved_aside)
    assert killed.returncode == -9
    assert not (out / "rec").exists() and any(out.glob(".rec.*.tmp"))
    # the next run of the bag (refused: no --force) restores the earlier bag before its check
    again = [str(PLANNER), "--bag", str(UNSEEN_SWARM), "--record", str(out / "rec")]
    assert evaluate.main(again) == 2
    assert everything(out / "rec") == earlier and not any(out.glob(".rec.*.tmp"))


def test_a_killed_benchmark_leaves_whole_files_and_force_completes_it(tmp_path: Path) -> None:
    ref = tmp_path / "ref"
    ref.mkdir()
    n = points("mentor-bench", bench_argv(ref), ref)
    reference = json.loads((ref / "bench" / "bench.json").read_text())
    for event in sorted({1, n // 2, n - 1}):
        out = tmp_path / f"at{event}"
        out.mkdir()
        assert hooked("mentor-bench", bench_argv(out), out, event).returncode == -9
        leftovers = [p.name for p in (out / "bench").iterdir() if p.name.startswith(".")]
        assert len(leftovers) <= 1  # at most the temporary file of the write it died in
        assert not (out / "bench" / "bench.json").exists()  # written last
        assert bench.main(bench_argv(out)) == 2  # the folder holds files: not without --force
        assert bench.main(bench_argv(out, "--force")) == 0
        doc = json.loads((out / "bench" / "bench.json").read_text())
        assert without_seconds(doc) == without_seconds(json.loads(json.dumps(reference)))
        assert not [p for p in (out / "bench").iterdir() if p.name.startswith(".")]


def test_a_full_disk_names_the_file_and_the_run_resumes(tmp_path: Path) -> None:
    config = tiny_config(tmp_path)
    ref = tmp_path / "ref"
    assert train_cli.main(train_argv(config, "dual", ref)) == 0
    out = tmp_path / "run"
    event = 5  # a written point: the temporary file of the third write holds its data
    failed = hooked("mentor-train", train_argv(config, "dual", out), out, event, "ENOSPC")
    assert failed.returncode == 2, failed.stderr
    line = failed.stderr.strip().splitlines()[-2]  # the hook's own count comes last
    assert line.startswith(f"mentor-train: {out}/") and "No space left on device" in line
    assert line.endswith(f"continue the run with --resume --out {out}")
    assert train_cli.main(train_argv(config, "dual", out, "--resume")) == 0
    assert snapshot(out) == snapshot(ref)
