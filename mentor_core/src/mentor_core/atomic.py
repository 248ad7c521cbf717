"""Atomic file writes: a reader sees the old file or the new one, never half of either.

A write goes to a temporary file ``.<name>.<8 characters>.tmp`` beside the target (the pattern
of :data:`TEMP_NAME`, also that of the ``tempfile.mkstemp`` names written before), which is then
renamed over the target. A process killed inside a write leaves that temporary file behind; the
owner of a folder removes its files' leftovers with :func:`remove_stale_temps`. Written files
get the permissions ``open()`` gives (0666 less the umask: 0644 usually), not mkstemp's 0600.
A write that fails (a full disk, a read-only folder) raises :class:`~mentor_core.errors.WriteFault`
naming the target and leaves the target as it was.
"""

from __future__ import annotations

import json
import os
import re
import secrets
from collections.abc import Iterable
from pathlib import Path
from typing import Any

from mentor_core.errors import WriteFault

# ".<target name>.<8 of [a-z0-9_]>.tmp": ours (token_hex) and mkstemp's (its random names)
TEMP_NAME = re.compile(r"\.(?P<target>.+)\.[a-z0-9_]{8}\.tmp")


def _open_temp(target: Path) -> tuple[int, Path]:
    """A new temporary file beside ``target``, opened for writing (mode 0666 less the umask)."""
    while True:
        tmp = target.with_name(f".{target.name}.{secrets.token_hex(4)}.tmp")
        try:
            flags = os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_CLOEXEC
            return os.open(tmp, flags, 0o666), tmp
        except FileExistsError:  # 2**32 names: another writer's, try the next
            continue


def write_bytes_atomic(path: str | Path, data: bytes) -> None:
    """Write ``data`` to ``path`` through a temporary file in the same folder and a rename."""
    target = Path(path)
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = _open_temp(target)
    except OSError as err:
        raise WriteFault(target, err) from None
    try:
        with os.fdopen(fd, "wb") as handle:
            handle.write(data)
            handle.flush()
            os.fsync(handle.fileno())
        os.replace(tmp, target)
    except BaseException as err:
        tmp.unlink(missing_ok=True)
        if isinstance(err, OSError) and not isinstance(err, WriteFault):
            # a full disk says "[Errno 28] No space left on device" and names no file
            raise WriteFault(target, err) from None
        raise


def write_text_atomic(path: str | Path, text: str) -> None:
    """Write UTF-8 ``text`` to ``path`` atomically."""
    write_bytes_atomic(path, text.encode("utf-8"))


def write_json_atomic(path: str | Path, obj: Any, indent: int | None = 2) -> None:
    """Write ``obj`` as JSON to ``path`` atomically (NaN/inf are refused), indented by
    ``indent`` spaces, or compact with None: Python's C encoder, which ``indent`` turns off
    (about 6x faster on a trainer's checkpoint)."""
    write_text_atomic(path, json.dumps(obj, indent=indent, allow_nan=False) + "\n")


def temp_target(path: str | Path) -> Path | None:
    """The file whose atomic write left the temporary file ``path``; None when ``path`` is not
    such a temporary file."""
    p = Path(path)
    match = TEMP_NAME.fullmatch(p.name)
    return None if match is None else p.with_name(match["target"])


def remove_stale_temps(targets: Iterable[str | Path]) -> list[Path]:
    """Remove the temporary files that interrupted atomic writes of ``targets`` left; returns
    them. Only for a folder's owner: another process writing a target now would lose its
    write."""
    wanted = {Path(t) for t in targets}
    removed = []
    for folder in sorted({t.parent for t in wanted}):
        if not folder.is_dir():
            continue
        for entry in sorted(folder.iterdir()):
            if temp_target(entry) in wanted and entry.is_file():
                entry.unlink(missing_ok=True)
                removed.append(entry)
    return removed
