"""Fault injection for tests/test_run_faults.py and tests/test_output_faults.py: stop a
process inside its own file writes.

Every atomic write (``mentor_core.atomic``) into one folder, or a folder inside it (a bag's
staging folder), passes two points, counted in order over the whole process: ``written`` (the
temporary file holds the data, before its fsync and rename) and ``renamed`` (the rename done,
before anything else). A bag passes a ``written`` point per file and a ``renamed`` point per
rename. :func:`install` wraps ``os.fsync`` and ``os.replace`` to count those points and, at
the n-th, to send the process a signal (SIGKILL dies there, SIGINT raises KeyboardInterrupt
there, as Ctrl-C would) or, for ``ENOSPC``, to fail the fsync as a full disk does.

    python tests/fault_hook.py EVENT SIGNAL OUT -- [mentor-eval | mentor-bench] arguments

runs mentor-train (or the command named) in this process with the hook installed (EVENT 0:
never fire) and writes the number of points passed to stderr as its last line
(``fault_hook: N points``).
"""

from __future__ import annotations

import errno
import os
import signal
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any


class Hook:
    """The installed wrappers: ``seen`` points so far; :meth:`remove` restores ``os``."""

    def __init__(self, folder: Path, event: int, sig: int) -> None:
        self.folder = os.path.abspath(folder)
        self.event = event
        self.sig = sig
        self.seen = 0
        self._fsync: Callable[[int], None] = os.fsync
        self._replace: Callable[..., None] = os.replace

    def _point(self) -> None:
        self.seen += 1
        if self.seen == self.event:
            if self.sig == ENOSPC:
                raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
            os.kill(os.getpid(), self.sig)

    def _ours(self, path: str | os.PathLike[str]) -> bool:
        return os.path.abspath(path).startswith(self.folder + os.sep)

    def fsync(self, fd: int) -> None:
        if self._ours(os.readlink(f"/proc/self/fd/{fd}")):
            self._point()
        self._fsync(fd)

    def replace(self, src: Any, dst: Any, **kwargs: Any) -> None:
        self._replace(src, dst, **kwargs)
        if self._ours(dst):
            self._point()

    def remove(self) -> None:
        os.fsync, os.replace = self._fsync, self._replace  # type: ignore[assignment]


#: the "signal" that fails the write as a full disk does
ENOSPC = -errno.ENOSPC


def install(folder: Path, event: int = 0, sig: int = signal.SIGKILL) -> Hook:
    """Count the write points into ``folder``; signal ``sig`` at point ``event`` (1-based)."""
    hook = Hook(folder, event, sig)
    os.fsync = hook.fsync
    os.replace = hook.replace  # type: ignore[assignment]
    return hook


def main() -> int:
    event, out = int(sys.argv[1]), Path(sys.argv[3])
    sig = ENOSPC if sys.argv[2] == "ENOSPC" else signal.Signals[sys.argv[2]]
    argv = sys.argv[sys.argv.index("--") + 1 :]
    hook = install(out, event, sig)
    from mentor_core.cli import bench, evaluate, train

    commands = {
        "mentor-train": train.main, "mentor-eval": evaluate.main, "mentor-bench": bench.main
    }  # fmt: skip
    if argv and argv[0] in commands:
        command, argv = commands[argv[0]], argv[1:]
    else:
        command = train.main
    try:
        return command(argv)
    finally:
        signal.signal(signal.SIGINT, signal.SIG_IGN)  # a timed Ctrl-C come after the end
        print(f"fault_hook: {hook.seen} points", file=sys.stderr)


if __name__ == "__main__":
    sys.exit(main())
