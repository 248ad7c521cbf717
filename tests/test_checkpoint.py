"""Checkpoints: versioned atomic JSON, exact round trip, one-line errors for bad files."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from mentor_core.errors import FileFormatError
from mentor_core.evolution.config import EvolutionConfig
from mentor_core.evolution.loop import Evolution
from mentor_core.files.checkpoint import (
    CHECKPOINT_FORMAT,
    CHECKPOINT_VERSION,
    Checkpointer,
    load_checkpoint,
    read_checkpoint,
    save_checkpoint,
)


def evolved(generations: int = 2, seed: int = 0) -> Evolution:
    cfg = EvolutionConfig.from_dict({"population_size": 16, "mutation": {"node_rate": 0.3}})
    evo = Evolution(cfg, 3, 2, seed=seed, objectives=2)
    rng = np.random.default_rng(100 + seed)
    for _ in range(generations):
        evo.ask()
        evo.tell(rng.uniform(0.0, 1.0, (16, 2)))
    return evo


def test_round_trip(tmp_path: Path) -> None:
    evo = evolved()
    path = tmp_path / "run" / "checkpoint.json"
    save_checkpoint(path, evo, extra={"stage": 1, "note": "x"})
    data = json.loads(path.read_text())
    assert data["format"] == CHECKPOINT_FORMAT == "mentor-checkpoint"
    assert data["version"] == CHECKPOINT_VERSION == 1
    assert data["evolution"]["rng"] == evo.rng.bit_generator.state
    loaded, extra = read_checkpoint(path)
    assert extra == {"stage": 1, "note": "x"}
    assert loaded.to_state() == evo.to_state()
    assert load_checkpoint(path).ask() == evo.ask()
    assert [p.name for p in path.parent.iterdir()] == ["checkpoint.json"]  # no temp files


def test_overwrite_keeps_latest(tmp_path: Path) -> None:
    evo = evolved(1)
    path = tmp_path / "ck.json"
    save_checkpoint(path, evo)
    evo.tell(np.ones((16, 2)))
    save_checkpoint(path, evo)
    assert load_checkpoint(path).generation == 2
    assert read_checkpoint(path)[1] is None


def test_checkpointer_reporter(tmp_path: Path) -> None:
    evo = evolved(0)
    path = tmp_path / "ck.json"
    evo.reporters.add(Checkpointer(evo, path, every=2))
    evo.tell(np.ones((16, 2)))
    assert not path.exists()
    evo.tell(np.ones((16, 2)))
    assert load_checkpoint(path).to_state() == evo.to_state()
    with pytest.raises(ValueError):
        Checkpointer(evo, path, every=0)


def test_missing_file(tmp_path: Path) -> None:
    with pytest.raises(FileFormatError, match="no such file") as info:
        load_checkpoint(tmp_path / "none.json")
    assert str(tmp_path / "none.json") in str(info.value)


@pytest.mark.parametrize(
    ("text", "fault"),
    [
        ("{not json", "not JSON"),
        ("[1, 2]", "not a mentor-checkpoint"),
        ('{"format": "mentor-genome", "version": 1}', "format"),
        ('{"format": "mentor-checkpoint", "version": 2, "evolution": {}}', "version 2"),
        ('{"format": "mentor-checkpoint", "version": 1}', "no evolution state"),
        ('{"format": "mentor-checkpoint", "version": 1, "evolution": {}}', "format/version"),
        ('{"format": "mentor-checkpoint", "version": 1, "evolution": {}, "extra": 3}', "extra"),
    ],
)
def test_corrupt_files(tmp_path: Path, text: str, fault: str) -> None:
    path = tmp_path / "bad.json"
    path.write_text(text)
    with pytest.raises(FileFormatError, match=fault) as info:
        load_checkpoint(path)
    assert str(info.value).startswith(str(path))
    assert "\n" not in str(info.value)


def test_truncated_and_tampered(tmp_path: Path) -> None:
    path = tmp_path / "ck.json"
    save_checkpoint(path, evolved())
    text = path.read_text()
    path.write_text(text[: len(text) // 2])
    with pytest.raises(FileFormatError, match="not JSON"):
        load_checkpoint(path)
    data = json.loads(text)
    data["evolution"]["population"][0]["connections"] = "oops"
    path.write_text(json.dumps(data))
    with pytest.raises(FileFormatError):
        load_checkpoint(path)
    data = json.loads(text)
    data["evolution"]["config"]["population_size"] = -3
    path.write_text(json.dumps(data))
    with pytest.raises(FileFormatError, match="population_size"):
        load_checkpoint(path)
