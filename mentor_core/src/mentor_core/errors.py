"""Exceptions of the MENTOR library.

Every error about a file names the file and the fault in one line, so the command-line tools
can print ``str(err)`` and exit non-zero.
"""

from __future__ import annotations

import reprlib
from pathlib import Path
from typing import TypeGuard


class MentorError(Exception):
    """Base class of all errors raised on purpose by mentor_core."""


class ConfigError(MentorError, ValueError):
    """A configuration value or key is invalid."""

    def __init__(self, message: str, key: str | None = None, path: str | Path | None = None):
        self.message = message
        self.key = key
        self.path = None if path is None else str(path)
        where = f"{self.path}: " if self.path else ""
        what = f"{key}: " if key else ""
        super().__init__(f"{where}{what}{message}")


class FileFormatError(MentorError, ValueError):
    """A file (genome, checkpoint, world, bag) is missing, corrupt or of the wrong version."""

    def __init__(self, path: str | Path, fault: str):
        self.path = str(path)
        self.fault = fault
        super().__init__(f"{self.path}: {fault}")


class WriteFault(MentorError, OSError):
    """A file could not be written (the disk is full, the folder read-only, ...): one line
    naming the file, still an OSError with the ``errno`` of the fault."""

    def __init__(self, path: str | Path, err: OSError) -> None:
        OSError.__init__(self, err.errno, err.strerror or one_line(err), str(path))
        self.path = str(path)

    def __str__(self) -> str:
        return f"{self.path}: cannot write ({self.strerror})"


def is_version(value: object, expected: int) -> bool:
    """Whether a file's ``version`` field is exactly the integer ``expected`` (JSON ``true``
    equals 1 in Python, but is not a version)."""
    return type(value) is int and value == expected


def is_number(value: object) -> TypeGuard[int | float]:
    """Whether a config or metadata value is an int or a float, not a bool (YAML and JSON
    ``true`` is an int in Python, but is not a number of metres or degrees)."""
    return isinstance(value, int | float) and not isinstance(value, bool)


def one_line(err: BaseException) -> str:
    """``str(err)`` on one line (every run of whitespace, newlines included, one space), for a
    fault quoted inside a one-line error message."""
    return " ".join(str(err).split())


_REPR_MAX = 60
_REPR = reprlib.Repr()
_REPR.maxstring = _REPR.maxother = _REPR.maxlong = _REPR_MAX


def short_repr(value: object) -> str:
    """``repr(value)`` cut to :data:`_REPR_MAX` characters, built within that bound (a value
    may be huge: reprlib shows only the first items of each level)."""
    try:
        text = _REPR.repr(value)
    except (ValueError, RecursionError):  # an int past Python's 4300 digits
        text = f"<{type(value).__name__}>"
    return text if len(text) <= _REPR_MAX else text[: _REPR_MAX - 3] + "..."
