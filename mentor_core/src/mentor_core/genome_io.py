"""Versioned JSON files of genomes (the planner node loads the trainer's best genome).

Format ``mentor-genome`` version 1::

    {"format": "mentor-genome", "version": 1, "n_inputs": 11, "n_outputs": 2,
     "hidden_activation": "sigmoid",
     "nodes": [{"id": 0, "kind": "input", "activation": "identity"}, ...],
     "connections": [{"innovation": 0, "in": 0, "out": 12, "weight": 0.5, "enabled": true}, ...],
     "metadata": {...}}

Writes are atomic; every read fault is a :class:`~mentor_core.errors.FileFormatError` naming
the file and the fault (missing file, not JSON, wrong format or version, missing or ill-typed
field, NaN/inf weight, unknown activation, dangling reference, cycle).
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from mentor_core.atomic import write_json_atomic
from mentor_core.errors import FileFormatError, is_version
from mentor_core.genome import (
    NODE_KINDS,
    ConnectionGene,
    Genome,
    InvalidGenomeError,
    NodeGene,
    NodeKind,
    validate_genome,
)
from mentor_core.network import ACTIVATIONS

FORMAT = "mentor-genome"
VERSION = 1
_TOP_KEYS = frozenset(
    {
        "format",
        "version",
        "n_inputs",
        "n_outputs",
        "hidden_activation",
        "nodes",
        "connections",
        "metadata",
    }
)
_NODE_KEYS = frozenset({"id", "kind", "activation"})
_CONNECTION_KEYS = frozenset({"innovation", "in", "out", "weight", "enabled"})


class _Fault(Exception):
    """Internal: one parsing fault, turned into FileFormatError with the source."""


def genome_to_dict(genome: Genome, metadata: Mapping[str, Any] | None = None) -> dict[str, Any]:
    """The versioned JSON-ready dict of ``genome`` (``metadata`` copied under its own key)."""
    return {
        "format": FORMAT,
        "version": VERSION,
        "n_inputs": genome.n_inputs,
        "n_outputs": genome.n_outputs,
        "hidden_activation": genome.hidden_activation,
        "nodes": [{"id": n.id, "kind": n.kind, "activation": n.activation} for n in genome.nodes],
        "connections": [
            {
                "innovation": c.innovation,
                "in": c.in_node,
                "out": c.out_node,
                "weight": c.weight,
                "enabled": c.enabled,
            }
            for c in genome.connections
        ],
        "metadata": dict(metadata or {}),
    }


def genome_from_dict(d: Any, source: str = "<dict>") -> Genome:
    """Parse and validate :func:`genome_to_dict`'s dict; FileFormatError(source, fault)."""
    return _parse(d, source)[0]


def save_genome(
    genome: Genome, path: str | Path, metadata: Mapping[str, Any] | None = None
) -> None:
    """Write ``genome`` to ``path`` atomically (a reader never sees half a file)."""
    write_json_atomic(path, genome_to_dict(genome, metadata))


def load_genome(path: str | Path) -> Genome:
    """Read a genome file; FileFormatError naming ``path`` and the fault on anything wrong."""
    return load_genome_and_metadata(path)[0]


def load_genome_and_metadata(path: str | Path) -> tuple[Genome, dict[str, Any]]:
    """Like :func:`load_genome`, also returning the file's ``metadata`` dict."""
    try:
        text = Path(path).read_text(encoding="utf-8")
    except FileNotFoundError:
        raise FileFormatError(path, "file not found") from None
    except (OSError, UnicodeDecodeError) as err:
        raise FileFormatError(path, f"cannot read: {err}") from None
    try:
        d = json.loads(text, parse_constant=_reject_constant)
    except (json.JSONDecodeError, _Fault, RecursionError) as err:
        raise FileFormatError(path, f"not valid JSON: {err}") from None
    return _parse(d, str(path))


def _parse(d: Any, source: str) -> tuple[Genome, dict[str, Any]]:
    try:
        genome, metadata = _parse_or_fault(d)
        validate_genome(genome)
    except (_Fault, InvalidGenomeError) as err:
        raise FileFormatError(source, str(err)) from None
    return genome, metadata


def _parse_or_fault(d: Any) -> tuple[Genome, dict[str, Any]]:
    if not isinstance(d, dict):
        raise _Fault(f"top level must be a JSON object, got {type(d).__name__}")
    if d.get("format") != FORMAT:
        raise _Fault(f"format is {d.get('format')!r}, expected {FORMAT!r}")
    if not is_version(d.get("version"), VERSION):
        raise _Fault(f"version {d.get('version')!r} is not supported (expected {VERSION})")
    _check_keys(d, _TOP_KEYS, "genome")
    metadata = d["metadata"]
    if not isinstance(metadata, dict):
        raise _Fault("metadata must be an object")
    hidden_activation = _activation(d["hidden_activation"], "hidden_activation")
    nodes = tuple(_node(entry, k) for k, entry in enumerate(_list(d, "nodes")))
    connections = tuple(_connection(entry, k) for k, entry in enumerate(_list(d, "connections")))
    genome = Genome(
        _int(d["n_inputs"], "n_inputs"),
        _int(d["n_outputs"], "n_outputs"),
        nodes,
        connections,
        hidden_activation,
    )
    return genome, metadata


def _node(entry: Any, k: int) -> NodeGene:
    where = f"nodes[{k}]"
    _check_keys(entry, _NODE_KEYS, where)
    kind = entry["kind"]
    if not isinstance(kind, str) or kind not in NODE_KINDS:
        raise _Fault(f"{where}.kind {kind!r} is not one of {sorted(NODE_KINDS)}")
    node_kind: NodeKind = entry["kind"]  # validated just above
    return NodeGene(
        _int(entry["id"], f"{where}.id"),
        node_kind,
        _activation(entry["activation"], f"{where}.activation"),
    )


def _connection(entry: Any, k: int) -> ConnectionGene:
    where = f"connections[{k}]"
    _check_keys(entry, _CONNECTION_KEYS, where)
    weight = entry["weight"]
    if isinstance(weight, bool) or not isinstance(weight, int | float):
        raise _Fault(f"{where}.weight must be a number, got {weight!r}")
    try:
        value = float(weight)
    except OverflowError:
        raise _Fault(f"{where}.weight is out of range") from None
    if not math.isfinite(value):
        raise _Fault(f"{where}.weight is {weight}")
    enabled = entry["enabled"]
    if not isinstance(enabled, bool):
        raise _Fault(f"{where}.enabled must be true or false, got {enabled!r}")
    return ConnectionGene(
        _int(entry["innovation"], f"{where}.innovation"),
        _int(entry["in"], f"{where}.in"),
        _int(entry["out"], f"{where}.out"),
        value,
        enabled,
    )


def _check_keys(entry: Any, keys: frozenset[str], where: str) -> None:
    if not isinstance(entry, dict):
        raise _Fault(f"{where} must be an object")
    missing = sorted(keys - entry.keys())
    if missing:
        raise _Fault(f"{where} is missing {', '.join(missing)}")
    unknown = sorted(str(k) for k in entry.keys() - keys)
    if unknown:
        raise _Fault(f"{where} has unknown keys {', '.join(unknown)}")


def _list(d: dict[str, Any], key: str) -> list[Any]:
    value = d[key]
    if not isinstance(value, list):
        raise _Fault(f"{key} must be a list")
    return value


def _int(value: Any, where: str) -> int:
    if isinstance(value, bool) or not isinstance(value, int):
        raise _Fault(f"{where} must be an integer, got {value!r}")
    return value


def _activation(value: Any, where: str) -> str:
    if not isinstance(value, str) or value not in ACTIVATIONS:
        raise _Fault(f"{where} {value!r} is not one of {sorted(ACTIVATIONS)}")
    return str(value)


def _reject_constant(name: str) -> Any:
    raise _Fault(f"{name} is not allowed")
