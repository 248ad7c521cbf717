"""IR-SIM, imported only when an episode needs it (:mod:`mentor_core.irsim`)."""

from __future__ import annotations

import contextlib
import importlib
import io
from types import ModuleType

from mentor_core.errors import MentorError

#: the line a user sees when the extra is missing
MISSING = "IR-SIM is not installed: install mentor-core[irsim] (pip install 'mentor-core[irsim]')"


class IrsimMissing(MentorError):
    """IR-SIM cannot be imported (:data:`MISSING`)."""


def load_irsim() -> ModuleType:
    """The ``irsim`` module; IrsimMissing (one line) when it is not installed. What IR-SIM
    prints on stdout as it is first imported (the interactive matplotlib backends it tries
    and that a headless machine lacks) is dropped."""
    try:
        with contextlib.redirect_stdout(io.StringIO()):
            return importlib.import_module("irsim")
    except ImportError:
        raise IrsimMissing(MISSING) from None


__all__ = ["MISSING", "IrsimMissing", "load_irsim"]
