"""The genome <-> dict codec: the versioned, JSON-ready form of a :class:`Genome`.

Format ``mentor-genome`` version 1::

    {"format": "mentor-genome", "version": 1, "n_inputs": 11, "n_outputs": 2,
     "hidden_activation": "sigmoid",
     "nodes": [{"id": 0, "kind": "input", "activation": "identity"}, ...],
     "connections": [{"innovation": 0, "in": 0, "out": 12, "weight": 0.5, "enabled": true}, ...],
     "metadata": {...}}

A recurrent connection gene also has ``"recurrent": true``; the key is left out of forward
genes, so feed-forward genomes are written as before.

Genome files (:mod:`mentor_core.files.genome_file`), checkpoints and run files hold genomes in
this form. Every parse fault is a :class:`~mentor_core.errors.FileFormatError` naming the source
and the fault (wrong format or version, missing or ill-typed field, NaN/inf weight, unknown
activation, dangling reference, cycle).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

from mentor_core.errors import FileFormatError, is_version
from mentor_core.evolution.genome import (
    NODE_KINDS,
    ConnectionGene,
    Genome,
    InvalidGenomeError,
    NodeGene,
    NodeKind,
    validate_genome,
)
from mentor_core.evolution.network import ACTIVATIONS

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
_CONNECTION_OPTIONAL = frozenset({"recurrent"})


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
        "connections": [_connection_dict(c) for c in genome.connections],
        "metadata": dict(metadata or {}),
    }


def _connection_dict(c: ConnectionGene) -> dict[str, Any]:
    entry: dict[str, Any] = {
        "innovation": c.innovation,
        "in": c.in_node,
        "out": c.out_node,
        "weight": c.weight,
        "enabled": c.enabled,
    }
    if c.recurrent:
        entry["recurrent"] = True
    return entry


def genome_from_dict(d: Any, source: str = "<dict>") -> Genome:
    """Parse and validate :func:`genome_to_dict`'s dict; FileFormatError(source, fault)."""
    return genome_and_metadata_from_dict(d, source)[0]


def genome_and_metadata_from_dict(
    d: Any, source: str = "<dict>"
) -> tuple[Genome, dict[str, Any]]:
    """Like :func:`genome_from_dict`, also returning the dict's ``metadata`` dict."""
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
    _check_keys(entry, _CONNECTION_KEYS, where, _CONNECTION_OPTIONAL)
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
    recurrent = entry.get("recurrent", False)
    if not isinstance(recurrent, bool):
        raise _Fault(f"{where}.recurrent must be true or false, got {recurrent!r}")
    return ConnectionGene(
        _int(entry["innovation"], f"{where}.innovation"),
        _int(entry["in"], f"{where}.in"),
        _int(entry["out"], f"{where}.out"),
        value,
        enabled,
        recurrent,
    )


def _check_keys(
    entry: Any, keys: frozenset[str], where: str, optional: frozenset[str] = frozenset()
) -> None:
    if not isinstance(entry, dict):
        raise _Fault(f"{where} must be an object")
    missing = sorted(keys - entry.keys())
    if missing:
        raise _Fault(f"{where} is missing {', '.join(missing)}")
    unknown = sorted(str(k) for k in entry.keys() - keys - optional)
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

