"""Every command as careful as mentor-train (issue 58): the probes of the issue, as tests.

One output policy (``cli.outputs``, ``docs/files.md``): never an input, never an existing file
or folder without ``--force``, never a run directory, an unwritable target refused at once.
Bounded YAML (size, nesting, aliases; YAML 1.2 numbers; no key twice) and bounded counts, each
fault one line naming the file, key or argument, exit status 2, nothing written.
"""

from __future__ import annotations

import errno
import json
import shutil
import signal
import subprocess
import sys
import time
from collections.abc import Callable, Sequence
from pathlib import Path

import pytest
import yaml
from cli_support import one_line, run

from mentor_core.cli import bench, evaluate, report, train
from mentor_core.cli import outputs as outputs_module
from mentor_core.errors import FileFormatError, short_repr
from mentor_core.evolution.genome import genome_from_edges
from mentor_core.files.genome_file import save_genome
from mentor_core.navigation.map_file import load_map
from mentor_core.training.memory_bound import check_memory, run_bytes
from mentor_core.yaml_reading import YAML_MAX_DEPTH, read_yaml, yaml_value

ROOT = Path(__file__).resolve().parents[1]
PLANNER = ROOT / "planners" / "swarm-paper-dual-s1.json"
UNSEEN_SWARM = ROOT / "bags" / "unseen" / "swarm"
#: nine anchors of nine aliases each under a key of the config: 9**9 (387 million) values from
#: about 400 bytes (formatting the value for the key's error took 65 s and 1.7 GB before)
ALIAS_BOMB = 'n_scenarios:\n  - &a ["x", "x", "x", "x", "x", "x", "x", "x", "x"]\n' + "".join(
    f"  - &{b} [{', '.join([f'*{a}'] * 9)}]\n"
    for a, b in zip("abcdefgh", "bcdefghi", strict=True)
)
DEEP = "[" * 600 + "]" * 600  # about 600 levels: Python's recursion limit in PyYAML's composer


def refused(
    main: Callable[..., int], argv: Sequence[object], capsys: pytest.CaptureFixture[str]
) -> str:
    """The one line on stderr of a command that exits 2."""
    status = run(main, argv)
    line = one_line(capsys)
    assert status == 2, line
    return line


@pytest.fixture
def no_work(monkeypatch: pytest.MonkeyPatch) -> None:
    """A refused command must not start its work."""

    def refuse(*args: object, **kwargs: object) -> None:
        raise AssertionError("the command started its work")

    monkeypatch.setattr(train, "train", refuse)
    monkeypatch.setattr(bench, "build_suite", refuse)
    monkeypatch.setattr(evaluate, "assess", refuse)


def a_run_directory(path: Path) -> Path:
    path.mkdir(parents=True)
    (path / "config.yaml").write_text("robot: swarm\nframework: dual\nseed: 0\n")
    (path / "history.csv").write_text("generation\n")
    return path


def contents(folder: Path) -> dict[str, bytes]:
    return {str(p.relative_to(folder)): p.read_bytes() for p in folder.rglob("*") if p.is_file()}


# ----------------------------------------------------------------- 1. mentor-bench --out


BENCH_TINY = ["--robot", "swarm", "--families", "rooms", "--pairs-per-family", "1",
              "--baselines", "bug", "--no-oracle"]  # fmt: skip


@pytest.fixture(scope="module")
def validation_bench(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("bench") / "val"
    assert bench.main([*BENCH_TINY, "--out", str(out)]) == 0
    return out


def test_bench_never_replaces_an_input_it_reads(
    validation_bench: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str], no_work: None
) -> None:
    before = contents(validation_bench)
    chosen = validation_bench / "bench.json"
    line = refused(bench.main, [*BENCH_TINY, "--split", "test", "--baselines-chosen-on", chosen,
                                "--out", validation_bench, "--force"], capsys)  # fmt: skip
    assert f"--out {validation_bench}: holds the input {chosen}" in line
    genomes = tmp_path / "genomes"
    genomes.mkdir()
    genome = genomes / "bench.json"
    shutil.copy(PLANNER, genome)
    line = refused(bench.main, [genome, *BENCH_TINY, "--out", genomes, "--force"], capsys)
    assert "holds the input" in line and genome.read_bytes() == PLANNER.read_bytes()
    assert contents(validation_bench) == before


def test_neither_command_replaces_the_deployment_file_it_reads(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], no_work: None
) -> None:
    """A deployment file (``--deployment FILE``) is an input like a genome."""
    deployment = tmp_path / "deployment.yaml"
    deployment.write_text("stages:\n  collision_guard: {memory: 3}\n")
    before = deployment.read_bytes()
    line = refused(bench.main, [*BENCH_TINY, "--deployment", deployment, "--out", tmp_path,
                                "--force"], capsys)  # fmt: skip
    assert f"--out {tmp_path}: holds the input {deployment}" in line
    for flag in ("--out", "--record"):
        argv = [PLANNER, "--bag", UNSEEN_SWARM, "--deployment", deployment, flag, deployment]
        line = refused(evaluate.main, [*argv, "--force"], capsys)
        assert f"{flag} {deployment}: is an input" in line
    assert deployment.read_bytes() == before


def test_bench_replaces_an_earlier_benchmark_only_with_force(
    validation_bench: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "again"
    shutil.copytree(validation_bench, out)
    before = contents(out)
    line = refused(bench.main, [*BENCH_TINY, "--out", out], capsys)
    assert "already exists and is not empty; pass --force" in line
    assert contents(out) == before
    assert run(bench.main, [*BENCH_TINY, "--out", out, "--force"]) == 0
    doc = json.loads((out / "bench.json").read_text())
    assert doc["split"] == "validation" and doc["robot"] == "swarm"


def test_bench_never_writes_into_a_run_directory_or_an_unwritable_place(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch,
    no_work: None,
) -> None:  # fmt: skip
    run_dir = a_run_directory(tmp_path / "run")
    before = contents(run_dir)
    line = refused(bench.main, [*BENCH_TINY, "--out", run_dir, "--force"], capsys)
    assert "is a training run directory" in line and contents(run_dir) == before
    a_file = tmp_path / "notes.txt"
    a_file.write_text("mine")
    line = refused(bench.main, [*BENCH_TINY, "--out", a_file / "bench"], capsys)
    assert f"{a_file} is not a directory" in line

    def read_only(*args: object, **kwargs: object) -> None:
        raise OSError(errno.EROFS, "Read-only file system")

    monkeypatch.setattr(outputs_module.tempfile, "TemporaryFile", read_only)
    line = refused(bench.main, [*BENCH_TINY, "--out", tmp_path / "new"], capsys)
    assert "cannot write in" in line and "Read-only file system" in line
    assert not (tmp_path / "new").exists()


def test_bench_with_nothing_to_run_is_one_line(
    capsys: pytest.CaptureFixture[str], no_work: None
) -> None:
    line = refused(bench.main, ["--robot", "swarm", "--baselines", "none", "--no-oracle"], capsys)
    assert "nothing to run" in line


def test_bench_counts_are_bounded(capsys: pytest.CaptureFixture[str], no_work: None) -> None:
    line = refused(bench.main, ["--robot", "swarm", "--pairs-per-family", 10**8], capsys)
    assert "--pairs-per-family must be in 1..100000" in line


def test_every_rooms_world_of_the_validation_split_is_drawn() -> None:
    """Seeds 169, 174 and 198 of the rooms family drew a door wider than its wall (a
    traceback from mentor-bench --pairs-per-family 1000)."""
    from mentor_core.benchmark.suite import world_pairs
    from mentor_core.sim.robots import get_profile

    for seed in (169, 174, 198):
        _, pairs = world_pairs("rooms", seed, get_profile("swarm"))
        assert len(pairs) == 5


# ----------------------------------------------------------------- 2, 3, 8, 9: YAML


def test_an_alias_bomb_is_refused_before_it_is_expanded(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], no_work: None
) -> None:
    config = tmp_path / "bomb.yaml"
    config.write_text(ALIAS_BOMB)
    assert len(ALIAS_BOMB) < 800
    line = refused(train.main, ["--robot", "swarm", "--framework", "dual", "--config", config,
                                "--out", tmp_path / "run"], capsys)  # fmt: skip
    assert f"{config}: not valid YAML" in line and "aliases expanded" in line
    assert not (tmp_path / "run").exists()
    with pytest.raises(ValueError, match="aliases expanded"):
        yaml_value(ALIAS_BOMB)
    with pytest.raises(ValueError, match="refers to a value that holds it"):
        yaml_value("a: &a [1, *a]")


def test_error_text_never_formats_an_unbounded_value() -> None:
    huge = [list(range(1000))] * 1000
    assert len(short_repr(huge)) <= 60
    assert short_repr(10**5000) == "<int>"  # past Python's 4300 digits


@pytest.mark.parametrize(
    "where", ["config", "set", "world", "map", "bag", "deployment", "deployment-set"]
)
def test_deep_nesting_is_one_line_naming_the_file(
    where: str, tmp_path: Path, capsys: pytest.CaptureFixture[str], no_work: None
) -> None:
    deep = tmp_path / "deep.yaml"
    deep.write_text(f"value: {DEEP}\n")
    if where == "deployment":
        line = refused(evaluate.main, [PLANNER, "--bag", UNSEEN_SWARM, "--deployment", deep],
                       capsys)  # fmt: skip
        assert line == refused(bench.main, [PLANNER, *BENCH_TINY, "--deployment", deep],
                               capsys).replace("mentor-bench", "mentor-eval")  # fmt: skip
    elif where == "deployment-set":
        line = refused(bench.main, [*BENCH_TINY, "--set", f"scan_map={DEEP}"], capsys)
    elif where in ("config", "set"):
        config = ["--config", deep] if where == "config" else ["--set", f"n_scenarios={DEEP}"]
        argv = ["--robot", "swarm", "--framework", "dual", *config, "--out", tmp_path / "r"]
        line = refused(train.main, argv, capsys)
    elif where == "bag":
        bag = tmp_path / "bag"
        shutil.copytree(UNSEEN_SWARM, bag)
        (bag / "metadata.yaml").write_text(f"rosbag2_bagfile_information: {DEEP}\n")
        line = refused(evaluate.main, [PLANNER, "--bag", bag], capsys)
        deep = bag
    else:
        line = refused(evaluate.main, [PLANNER, "--robot", "swarm", f"--{where}", deep], capsys)
    assert f"nested deeper than {YAML_MAX_DEPTH} levels" in line
    if where not in ("set", "deployment-set"):
        assert str(deep) in line


def test_yaml_reads_as_yaml_1_2_and_refuses_a_key_twice(tmp_path: Path) -> None:
    assert yaml_value("5e-2") == 0.05 and yaml_value("1e3") == 1000.0
    assert yaml_value("1_2") == "1_2" and yaml_value("yes") == "yes"  # YAML 1.1: 12, true
    assert yaml_value("012") == 12 and yaml_value("0x1F") == 31 and yaml_value("0o17") == 15
    assert yaml_value("1:30") == "1:30" and yaml_value("2026-12-05") == "2026-12-05"
    doubled = tmp_path / "doubled.yaml"
    doubled.write_text("generations: 3\nn_scenarios: 4\ngenerations: 5\n")
    with pytest.raises(FileFormatError, match=r"doubled\.yaml: .*line 3 .duplicate key 'gen"):
        read_yaml(doubled)
    big = tmp_path / "big.yaml"
    with big.open("wb") as handle:
        handle.truncate(9 * 2**20)
    with pytest.raises(FileFormatError, match="larger than 8 MiB"):
        read_yaml(big)


def test_a_map_yaml_reads_numbers_as_map_server_does(tmp_path: Path) -> None:
    (tmp_path / "m.pgm").write_bytes(b"P5 2 2 255\n" + bytes([254, 0, 254, 254]))
    (tmp_path / "m.yaml").write_text(
        "image: m.pgm\nresolution: 5e-2\norigin: [0.0, 0.0, 0.0]\nnegate: 0\n"
        "occupied_thresh: 0.65\nfree_thresh: 0.196\n"
    )
    assert load_map(tmp_path / "m.yaml").resolution == 0.05


@pytest.mark.parametrize(
    ("config", "fault"),
    [
        ("extends: swarm/quick\nn_scenarios: 1_2\n", "n_scenarios: expected a whole number"),
        ("extends: swarm/quick\ngenerations: 3\ngenerations: 4\n", "duplicate key 'gen"),
        ("extends: swarm/quick\nrobot: ugv\n", "robot: the config is for 'ugv', not --robot"),
    ],
)
def test_config_faults_of_the_probes(
    config: str, fault: str, tmp_path: Path, capsys: pytest.CaptureFixture[str], no_work: None
) -> None:
    path = tmp_path / "c.yaml"
    path.write_text(config)
    line = refused(train.main, ["--robot", "swarm", "--framework", "dual", "--config", path,
                                "--out", tmp_path / "run"], capsys)  # fmt: skip
    assert str(path) in line and fault in line


def test_counts_past_what_the_worlds_or_the_machine_hold_are_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], no_work: None
) -> None:
    base = ["--robot", "swarm", "--framework", "dual", "--out", tmp_path / "run"]
    line = refused(train.main, [*base, "--set", "n_scenarios=20000"], capsys)
    assert "n_scenarios: found only" in line
    line = refused(train.main, [*base, "--set", "evolution.population_size=100000000"], capsys)
    assert "evolution.population_size: 100000000 genomes" in line and "GiB" in line
    line = refused(evaluate.main, [PLANNER, "--robot", "swarm", "--seed", 1, "--n", 10**8],
                   capsys)  # fmt: skip
    assert line.startswith("mentor-eval: --n 100000000: at most")
    assert not (tmp_path / "run").exists()


def test_the_memory_bound() -> None:
    assert run_bytes(100, 60) == 100 * (22_000 + 13_000 * 60)
    check_memory(100, 60, "c.yaml", available=2**30)
    with pytest.raises(ValueError, match=r"c\.yaml: evolution\.population_size: .*at most 1337"):
        check_memory(2000, 60, "c.yaml", available=run_bytes(1337, 60) + 1)


def test_a_genome_for_an_unknown_or_other_robot_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], no_work: None
) -> None:
    genome = genome_from_edges(6, 2, [(4, 7, 2.0), (6, 8, 1.0)])
    tank = tmp_path / "tank.json"
    save_genome(genome, tank, {"robot": "tank"})
    line = refused(evaluate.main, [tank, "--bag", UNSEEN_SWARM], capsys)
    assert f"{tank}: robot: 'tank' is no known robot" in line
    line = refused(evaluate.main, [PLANNER, "--robot", "ugv", "--seed", 1], capsys)
    assert "trained for robot 'swarm', not 'ugv'" in line


# ----------------------------------------------------------------- 4, 5: mentor-report


def test_report_never_writes_into_a_run_directory(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    other = a_run_directory(tmp_path / "other")
    before = contents(other)
    mine = a_run_directory(tmp_path / "mine")
    line = refused(report.main, [mine, "--out", other, "--force"], capsys)
    assert "is a training run directory" in line
    assert contents(other) == before


def test_report_of_nothing_is_refused(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    empty = tmp_path / "empty"
    empty.mkdir()
    notes = tmp_path / "notes"
    notes.mkdir()
    (notes / "todo.txt").write_text("mine")
    for given in (empty, notes):
        line = refused(report.main, [given, "--out", tmp_path / "report"], capsys)
        assert f"{given}: not a training run directory" in line
    unfinished = a_run_directory(tmp_path / "unfinished")
    status = run(report.main, [unfinished, "--out", tmp_path / "report"])
    assert status == 2 and "nothing to report" in capsys.readouterr().err
    assert not (tmp_path / "report").exists()


# ----------------------------------------------------------------- 9: a kill -9 of --workers


def test_a_killed_pool_run_ends_on_no_warning_of_multiprocessing(tmp_path: Path) -> None:
    out = tmp_path / "run"
    cmd = [sys.executable, "-m", "mentor_core.cli.train", "--robot", "swarm", "--framework",
           "single", "--config", "quick", "--set", "generations=500", "--workers", "2",
           "--quiet", "--out", str(out)]  # fmt: skip
    proc = subprocess.Popen(cmd, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 120
    while not (out / "checkpoint.json").exists() and time.monotonic() < deadline:
        time.sleep(0.05)
    proc.send_signal(signal.SIGKILL)
    _, err = proc.communicate(timeout=60)  # every holder of the pipe gone: workers, tracker
    assert proc.returncode == -9
    assert "resource_tracker" not in err and "Warning" not in err, err


def test_yaml_documents_of_a_run_read_as_written(tmp_path: Path) -> None:
    """The run's config.yaml is written by PyYAML (YAML 1.1 quoting) and read back as YAML
    1.2: the same mapping."""
    data = {"a": "1_2", "b": "yes", "c": 1e-5, "d": [1, 2.5, None, True], "e": "2026-12-05"}
    (tmp_path / "c.yaml").write_text(yaml.safe_dump(data))
    assert read_yaml(tmp_path / "c.yaml") == data
