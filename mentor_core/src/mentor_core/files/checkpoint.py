"""Checkpoints: the whole evolution state as one versioned JSON file, written atomically.

A checkpoint holds ``Evolution.to_state()`` -- population, generator ``bit_generator.state``,
innovation tracker, species representatives, threshold, counters, best genome, history -- under
``{"format": "mentor-checkpoint", "version": 1}``, plus an optional JSON ``extra`` for the
caller (e.g. a trainer's stage). A run resumed from the checkpoint written after generation k
continues exactly as the unbroken run with the same seed would have.

:class:`Checkpointer` is the reporter form (neat-python's ``checkpoint.py``): it saves after
every ``every``-th generation, when the next population has been bred.
"""

from __future__ import annotations

import json
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

from mentor_core.atomic import write_json_atomic
from mentor_core.errors import FileFormatError, is_version
from mentor_core.evolution.loop import Evolution
from mentor_core.evolution.reporting import GenerationStats, Reporter

CHECKPOINT_FORMAT = "mentor-checkpoint"
CHECKPOINT_VERSION = 1


def save_checkpoint(
    path: str | Path, evolution: Evolution, extra: Mapping[str, Any] | None = None
) -> None:
    """Write ``evolution``'s state (and ``extra``, JSON-serialisable) to ``path`` atomically."""
    write_json_atomic(
        path,
        {
            "format": CHECKPOINT_FORMAT,
            "version": CHECKPOINT_VERSION,
            "evolution": evolution.to_state(),
            "extra": None if extra is None else dict(extra),
        },
    )


def read_checkpoint(
    path: str | Path, reporters: Iterable[Reporter] = ()
) -> tuple[Evolution, dict[str, Any] | None]:
    """The evolution and the ``extra`` dict stored in ``path``.

    Raises :class:`FileFormatError` naming the file for a missing, unreadable, non-JSON,
    wrong-format, wrong-version or inconsistent checkpoint.
    """
    source = str(path)
    try:
        text = Path(path).read_text(encoding="utf-8")
    except FileNotFoundError:
        raise FileFormatError(source, "no such file") from None
    except (OSError, UnicodeDecodeError) as err:
        raise FileFormatError(source, f"cannot read: {err}") from None
    try:
        data = json.loads(text)
    except json.JSONDecodeError as err:
        raise FileFormatError(source, f"not JSON ({err.msg} at line {err.lineno})") from None
    if not isinstance(data, dict):
        raise FileFormatError(source, "not a mentor-checkpoint file")
    if data.get("format") != CHECKPOINT_FORMAT:
        fault = f"format {data.get('format')!r} is not {CHECKPOINT_FORMAT!r}"
        raise FileFormatError(source, fault)
    if not is_version(data.get("version"), CHECKPOINT_VERSION):
        raise FileFormatError(
            source, f"checkpoint version {data.get('version')!r} is not supported "
            f"(expected {CHECKPOINT_VERSION})"
        )
    if "evolution" not in data:
        raise FileFormatError(source, "checkpoint has no evolution state")
    extra = data.get("extra")
    if extra is not None and not isinstance(extra, dict):
        raise FileFormatError(source, "checkpoint 'extra' is not a mapping")
    evolution = Evolution.from_state(data["evolution"], source, reporters)
    return evolution, extra


def load_checkpoint(path: str | Path, reporters: Iterable[Reporter] = ()) -> Evolution:
    """The evolution stored in ``path`` (see :func:`read_checkpoint`)."""
    return read_checkpoint(path, reporters)[0]


class Checkpointer(Reporter):
    """Reporter that saves ``evolution`` to ``path`` after every ``every``-th generation.

    It saves from inside ``Evolution.tell`` (the ``end_generation`` event). A caller that
    changes the evolution after ``tell`` returns (``reseed`` at a stage change) must call
    :func:`save_checkpoint` itself afterwards, or a resume would miss that change.
    """

    def __init__(self, evolution: Evolution, path: str | Path, every: int = 1) -> None:
        if every < 1:
            raise ValueError(f"every must be >= 1, got {every}")
        self.evolution = evolution
        self.path = Path(path)
        self.every = every

    def end_generation(self, stats: GenerationStats) -> None:
        if (stats.generation + 1) % self.every == 0:
            save_checkpoint(self.path, self.evolution)
