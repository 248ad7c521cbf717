"""Versioned JSON files of genomes (the planner node loads the trainer's best genome).

A file holds one genome in the ``mentor-genome`` form of
:mod:`mentor_core.evolution.genome_codec`. Writes are atomic; every read fault is a
:class:`~mentor_core.errors.FileFormatError` naming the file and the fault (missing file, not
JSON, wrong format or version, missing or ill-typed field, NaN/inf weight, unknown activation,
dangling reference, cycle).
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from mentor_core.atomic import write_json_atomic
from mentor_core.errors import FileFormatError
from mentor_core.evolution.genome import Genome
from mentor_core.evolution.genome_codec import genome_and_metadata_from_dict, genome_to_dict


class _Constant(Exception):
    """Internal: NaN or Infinity in the JSON text, turned into FileFormatError with the path."""


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
    except (json.JSONDecodeError, _Constant, RecursionError) as err:
        raise FileFormatError(path, f"not valid JSON: {err}") from None
    return genome_and_metadata_from_dict(d, str(path))


def _reject_constant(name: str) -> Any:
    raise _Constant(f"{name} is not allowed")
