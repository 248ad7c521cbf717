"""Genome files: exact round trip, every read fault a FileFormatError naming file and fault,
atomic saves over an existing file."""

from __future__ import annotations

import json
import os
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from mentor_core.errors import FileFormatError
from mentor_core.evolution.genome import Genome, minimal_genome
from mentor_core.evolution.genome_codec import genome_from_dict, genome_to_dict
from mentor_core.evolution.innovation import InnovationTracker
from mentor_core.evolution.mutation import MutationConfig, mutate
from mentor_core.evolution.network import FeedForwardNetwork
from mentor_core.files.genome_file import load_genome, load_genome_and_metadata, save_genome


def evolved(seed: int = 0) -> Genome:
    """A genome with hidden nodes, disabled genes and awkward float weights."""
    rng = np.random.default_rng(seed)
    tracker = InnovationTracker(4 + 1 + 2)
    g = minimal_genome(4, 2, tracker, rng, hidden_activation="tanh", output_activation="relu")
    for _ in range(3):
        g = mutate(g, MutationConfig(node_rate=0.3, edge_rate=0.1), tracker, rng)
        tracker.new_generation()
    assert g.hidden_nodes and any(not c.enabled for c in g.connections)
    return g


def test_save_load_round_trip_is_exact(tmp_path: Path) -> None:
    g = evolved()
    path = tmp_path / "best.json"
    meta = {"generation": 12, "objectives": [0.5, 1.25], "note": "ünïcode"}
    save_genome(g, path, metadata=meta)
    loaded, loaded_meta = load_genome_and_metadata(path)
    assert loaded == g  # weights bit-exact, enabled flags, activations, order
    assert loaded_meta == meta
    assert load_genome(str(path)) == g
    x = np.random.default_rng(1).normal(size=(5, g.n_inputs))
    np.testing.assert_array_equal(
        FeedForwardNetwork.from_genome(loaded).activate(x),
        FeedForwardNetwork.from_genome(g).activate(x),
    )


def test_dict_round_trip_and_documented_layout() -> None:
    g = evolved(1)
    d = genome_to_dict(g)
    assert d["format"] == "mentor-genome" and d["version"] == 1
    assert d["metadata"] == {}
    assert set(d["connections"][0]) == {"innovation", "in", "out", "weight", "enabled"}
    assert genome_from_dict(json.loads(json.dumps(d))) == g


def test_missing_file(tmp_path: Path) -> None:
    path = tmp_path / "nope.json"
    with pytest.raises(FileFormatError) as err:
        load_genome(path)
    assert err.value.path == str(path) and "not found" in str(err.value)


def _write_bad(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "bad-genome.json"
    path.write_text(text, encoding="utf-8")
    return path


def _doc() -> dict[str, Any]:
    # inputs 0..3, bias 4, outputs 5, 6; hidden ids from 7
    d = genome_to_dict(evolved(2))
    assert any(n["kind"] == "hidden" for n in d["nodes"])
    return d


def _set(key: str, value: Any) -> Callable[[dict[str, Any]], None]:
    return lambda d: d.__setitem__(key, value)


def _conn(key: str, value: Any) -> Callable[[dict[str, Any]], None]:
    return lambda d: d["connections"][0].__setitem__(key, value)


def _node(key: str, value: Any) -> Callable[[dict[str, Any]], None]:
    return lambda d: d["nodes"][-1].__setitem__(key, value)


def _add_cycle(d: dict[str, Any]) -> None:
    """A disabled gene output -> hidden that closes a loop through an existing path."""
    hidden_to_out = next(
        c for c in d["connections"] if c["in"] >= 7 and c["out"] in (5, 6)
    )
    d["connections"].append(
        {
            "innovation": max(c["innovation"] for c in d["connections"]) + 1,
            "in": hidden_to_out["out"],
            "out": hidden_to_out["in"],
            "weight": 0.5,
            "enabled": False,
        }
    )


BAD_DOCS: dict[str, tuple[Callable[[dict[str, Any]], None], str]] = {
    "wrong format name": (_set("format", "neat-genome"), "format is 'neat-genome'"),
    "wrong version": (_set("version", 2), "version 2 is not supported"),
    "boolean version": (_set("version", True), "version True is not supported"),
    "float version": (_set("version", 1.0), "version 1.0 is not supported"),
    "missing field": (lambda d: d.pop("connections"), "missing connections"),
    "missing gene field": (lambda d: d["connections"][0].pop("weight"), "connections[0]"),
    "unknown field": (_set("colour", "red"), "unknown keys colour"),
    "cycle": (_add_cycle, "cycle"),
    "infinite weight": (_conn("weight", "__1e999__"), "weight is inf"),  # 1e999 parses to inf
    "string weight": (_conn("weight", "0.5"), "weight must be a number"),
    "float id": (_conn("in", 1.0), "connections[0].in must be an integer"),
    "enabled not bool": (_conn("enabled", 1), "enabled must be true or false"),
    "dangling reference": (_conn("out", 99), "missing node 99"),
    "unknown activation": (_node("activation", "swish"), "'swish'"),
    "unknown kind": (_node("kind", "memory"), "'memory'"),
    "unhashable activation": (_node("activation", ["tanh"]), "activation"),
    "unhashable kind": (_node("kind", {"k": 1}), "kind"),
    "unhashable hidden_activation": (_set("hidden_activation", []), "hidden_activation"),
    "huge integer weight": (_conn("weight", 10**400), "weight"),
    "nodes not a list": (_set("nodes", {}), "nodes must be a list"),
    "metadata not an object": (_set("metadata", []), "metadata"),
    "bad layout": (_set("n_outputs", 3), "node 7 must be of kind 'output'"),
}


@pytest.mark.parametrize("case", sorted(BAD_DOCS))
def test_bad_file_is_refused_naming_file_and_fault(tmp_path: Path, case: str) -> None:
    corrupt, fault = BAD_DOCS[case]
    d = _doc()
    corrupt(d)
    path = _write_bad(tmp_path, json.dumps(d).replace('"__1e999__"', "1e999"))
    with pytest.raises(FileFormatError) as err:
        load_genome(path)
    assert err.value.path == str(path)
    assert str(err.value).startswith(f"{path}: ")
    assert fault in err.value.fault


@pytest.mark.parametrize(
    ("text", "fault"),
    [
        ('{"format": "mentor-genome", "version": 1, ', "not valid JSON"),
        ("", "not valid JSON"),
        ("[" * 100_000, "not valid JSON"),
        ("[1, 2]", "top level must be a JSON object"),
    ],
)
def test_corrupt_json_is_refused(tmp_path: Path, text: str, fault: str) -> None:
    path = _write_bad(tmp_path, text)
    with pytest.raises(FileFormatError) as err:
        load_genome(path)
    assert err.value.path == str(path) and fault in err.value.fault


@pytest.mark.parametrize(("weight", "constant"), [(float("nan"), "NaN"), (-np.inf, "-Infinity")])
def test_nan_weight_is_refused(tmp_path: Path, weight: float, constant: str) -> None:
    d = _doc()
    d["connections"][0]["weight"] = weight
    path = _write_bad(tmp_path, json.dumps(d))  # Python writes the non-standard constant
    assert f'"weight": {constant}' in path.read_text()
    with pytest.raises(FileFormatError) as err:
        load_genome(path)
    assert err.value.path == str(path) and constant in err.value.fault


def test_from_dict_names_its_source() -> None:
    d = _doc()
    d["version"] = 0
    with pytest.raises(FileFormatError) as err:
        genome_from_dict(d, source="ckpt.json#best")
    assert str(err.value).startswith("ckpt.json#best: version 0")


def _folder_listing(path: Path) -> list[str]:
    return sorted(os.listdir(path))


def test_saving_over_existing_file_replaces_it_whole(tmp_path: Path) -> None:
    path = tmp_path / "best.json"
    old, new = evolved(3), evolved(4)
    save_genome(old, path)
    save_genome(new, path, metadata={"gen": 2})
    assert load_genome(path) == new
    assert _folder_listing(tmp_path) == ["best.json"]  # no temporary file left behind


def test_failed_save_leaves_old_file_intact(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A crash after the new bytes are written but before the rename changes nothing."""
    path = tmp_path / "best.json"
    old = evolved(5)
    save_genome(old, path)
    before = path.read_bytes()
    seen: list[bytes] = []

    def crash(src: str | os.PathLike[str], dst: str | os.PathLike[str]) -> None:
        seen.append(Path(src).read_bytes())  # the complete new file sits beside the old
        raise OSError("disk pulled out")

    monkeypatch.setattr("mentor_core.atomic.os.replace", crash)
    with pytest.raises(OSError, match="disk pulled out"):
        save_genome(evolved(6), path)
    monkeypatch.undo()
    assert seen and json.loads(seen[0]) == genome_to_dict(evolved(6))
    assert path.read_bytes() == before
    assert load_genome(path) == old
    assert _folder_listing(tmp_path) == ["best.json"]


def test_unsavable_genome_leaves_old_file_intact(tmp_path: Path) -> None:
    path = tmp_path / "best.json"
    old = evolved(7)
    save_genome(old, path)
    c = old.connections[0]
    broken = old.with_connections(
        (type(c)(c.innovation, c.in_node, c.out_node, float("nan"), c.enabled),
         *old.connections[1:])
    )
    with pytest.raises(ValueError):
        save_genome(broken, path)
    assert load_genome(path) == old
    assert _folder_listing(tmp_path) == ["best.json"]


def test_save_creates_missing_folders(tmp_path: Path) -> None:
    path = tmp_path / "run" / "gen-007" / "best.json"
    g = evolved(8)
    save_genome(g, path)
    assert load_genome(path) == g
