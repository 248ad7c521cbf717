"""How the command tests run a ``mentor-*`` command in process and read its one-line refusal."""

from __future__ import annotations

from collections.abc import Callable, Sequence

import pytest


def run(main: Callable[..., int], argv: Sequence[object]) -> int:
    """The exit status of a command (its arguments as text), whether it returns it or argparse
    exits."""
    try:
        return main([str(a) for a in argv])
    except SystemExit as stop:
        return int(stop.code or 0)


def one_line(capsys: pytest.CaptureFixture[str]) -> str:
    """The one line the command wrote on stderr (no traceback)."""
    err = capsys.readouterr().err
    assert "Traceback" not in err
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    return lines[0]
