"""Foundation: mentor_core imports without ROS, errors name file and fault, writes are atomic."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from mentor_core.atomic import write_json_atomic, write_text_atomic
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
