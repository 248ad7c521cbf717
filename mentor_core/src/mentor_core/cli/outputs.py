"""Output paths of the ``mentor-*`` commands, checked before the work starts.

An output never replaces one of the command's inputs (not even with ``--force``: the result
would be computed from a file it destroys), and never replaces an existing file or bag unless
``--force`` is given. Each refusal is one :class:`OutputError` line naming the option and the
path; the commands check every output before they read or compute anything else, so a refusal
costs nothing and nothing is half-written.
"""

from __future__ import annotations

import os
from collections.abc import Iterable
from pathlib import Path

from mentor_core.errors import MentorError
from mentor_core.files.bags import looks_like_bag


class OutputError(MentorError):
    """An output path the command may not write."""

    def __init__(self, option: str, path: Path, fault: str) -> None:
        super().__init__(f"{option} {path}: {fault}")


def check_file(option: str, path: Path, inputs: Iterable[Path], force: bool) -> None:
    """``path`` may be written as a file: it is no input, and no existing file unless
    ``force`` (a directory never)."""
    _not_an_input(option, path, inputs)
    if path.is_dir():
        raise OutputError(option, path, "is a directory")
    if exists(path) and not force:
        raise OutputError(option, path, "already exists; pass --force to replace it")


def check_bag(option: str, path: Path, inputs: Iterable[Path], force: bool) -> None:
    """``path`` may be written as a bag directory: it is no input and holds none, and it is
    no existing bag unless ``force`` (anything else that exists never)."""
    _not_an_input(option, path, inputs)
    if not exists(path):
        return
    if not looks_like_bag(path):
        raise OutputError(option, path, "already exists and is not a bag; not replacing it")
    if not force:
        raise OutputError(option, path, "already exists; pass --force to replace it")


def check_distinct(outputs: dict[str, Path | None]) -> None:
    """No two options name the same output."""
    seen: dict[Path, str] = {}
    for option, path in outputs.items():
        if path is None:
            continue
        key = path.resolve()
        if key in seen:
            raise OutputError(option, path, f"is also the {seen[key]} output")
        seen[key] = option


def _not_an_input(option: str, path: Path, inputs: Iterable[Path]) -> None:
    """Refuse ``path`` when it is an input, lies inside an input folder or holds an input."""
    target = path.resolve()
    for given in inputs:
        source = given.resolve()
        if target == source or _same_file(path, given):
            raise OutputError(option, path, f"is an input ({given}); not replacing it")
        if source in target.parents:
            raise OutputError(option, path, f"lies inside the input {given}; not writing there")
        if target in source.parents:
            raise OutputError(option, path, f"holds the input {given}; not replacing it")


def _same_file(a: Path, b: Path) -> bool:
    try:
        return os.path.samefile(a, b)  # a hard link or another spelling of the same file
    except OSError:
        return False


def exists(path: Path) -> bool:
    """Whether something (a broken link included) is at ``path``."""
    return path.exists() or path.is_symlink()


__all__ = ["OutputError", "check_bag", "check_distinct", "check_file", "exists"]
