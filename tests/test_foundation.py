"""Foundation: mentor_core imports without ROS, errors name file and fault, writes are atomic."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from mentor_core.atomic import (
    remove_stale_temps,
    temp_target,
    write_json_atomic,
    write_text_atomic,
)
from mentor_core.errors import ConfigError, FileFormatError


def test_mentor_core_never_imports_rclpy() -> None:
    code = (
        "import importlib, pkgutil, sys, mentor_core\n"
        "for m in pkgutil.walk_packages(mentor_core.__path__, 'mentor_core.'):\n"
        "    importlib.import_module(m.name)\n"
        "roots = {n.split('.')[0] for n in sys.modules}\n"
        "bad = sorted(roots & {'rclpy', 'rosidl_runtime_py'})\n"
        "print(','.join(bad))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == ""


def test_error_messages_are_one_line_and_name_the_file() -> None:
    err = FileFormatError("/tmp/g.json", "version 7 is not supported")
    assert str(err) == "/tmp/g.json: version 7 is not supported"
    cfg = ConfigError("must be in [0, 1]", key="crossover_rate", path="cfg.yaml")
    assert str(cfg) == "cfg.yaml: crossover_rate: must be in [0, 1]"
    assert "\n" not in str(err) + str(cfg)


def test_atomic_write_replaces_whole_file(tmp_path: Path) -> None:
    target = tmp_path / "sub" / "out.json"
    write_json_atomic(target, {"a": 1})
    write_json_atomic(target, {"b": [1, 2]})
    assert json.loads(target.read_text()) == {"b": [1, 2]}
    assert [p.name for p in target.parent.iterdir()] == ["out.json"]


def test_atomic_write_failure_keeps_old_file(tmp_path: Path) -> None:
    target = tmp_path / "out.json"
    write_text_atomic(target, "old")
    with pytest.raises(ValueError):
        write_json_atomic(target, {"x": float("nan")})
    assert target.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["out.json"]


def test_atomic_writes_get_ordinary_modes(tmp_path: Path) -> None:
    """0666 less the umask, as open() gives (bags are 0644), not mkstemp's 0600."""
    previous = os.umask(0o022)
    try:
        write_text_atomic(tmp_path / "a.txt", "a")
        os.umask(0o077)
        write_text_atomic(tmp_path / "b.txt", "b")
    finally:
        os.umask(previous)
    assert (tmp_path / "a.txt").stat().st_mode & 0o777 == 0o644
    assert (tmp_path / "b.txt").stat().st_mode & 0o777 == 0o600


def test_stale_temps_of_named_files_only_are_removed(tmp_path: Path) -> None:
    target = tmp_path / "checkpoint.json"
    ours = [tmp_path / ".checkpoint.json.k2x_9qzt.tmp", tmp_path / ".checkpoint.json.0a1b2c3d.tmp"]
    others = [tmp_path / n for n in (".history.csv.0a1b2c3d.tmp", ".checkpoint.json.tmp",
                                     ".checkpoint.json.0a1b2c3.tmp", "checkpoint.json")]
    for p in ours + others:
        p.write_text("x")
    assert [temp_target(p) for p in ours] == [target, target]
    assert temp_target(others[1]) is None and temp_target(others[2]) is None
    assert remove_stale_temps([target, tmp_path / "missing" / "f.json"]) == sorted(ours)
    assert sorted(tmp_path.iterdir()) == sorted(others)
