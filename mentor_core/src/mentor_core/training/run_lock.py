"""The lock a writer holds on a run directory for the whole of its run: one writer per run.

``fcntl.flock`` on ``<run>/train.lock`` (:data:`LOCK_NAME`). The kernel releases the lock when
its process ends, however it ends (kill -9 included), so a lock is never stale: a file left by a
killed run is taken over by the next writer. The file holds its holder's pid, host and start
time, for the one line a second writer is refused with (:class:`RunInUseError`). Locks hold
between the processes of one machine (on NFS too, where Linux maps them to POSIX locks).
"""

from __future__ import annotations

import fcntl
import json
import os
import socket
import time
from pathlib import Path
from types import TracebackType

from mentor_core.errors import MentorError

LOCK_NAME = "train.lock"


class RunInUseError(MentorError):
    """Another process holds the run directory's lock."""

    def __init__(self, root: str | Path, holder: str) -> None:
        self.path = str(root)
        self.holder = holder
        super().__init__(
            f"{root}: in use by {holder}; wait for that run to end or choose another --out"
        )


def _holder_text(data: bytes) -> str:
    """The holder a lock file names ("pid 12 on host h since 2025-01-01 10:00:00 UTC")."""
    try:
        who = json.loads(data.decode("utf-8"))
        return f"pid {int(who['pid'])} on host {who['host']} since {who['started']}"
    except (ValueError, KeyError, TypeError, AttributeError):
        return "another process (it has not yet written its pid)"


class RunLock:
    """An exclusive lock on a run directory, held from :meth:`acquire` to :meth:`release`."""

    def __init__(self, root: Path, fd: int) -> None:
        self.root = root
        self.path = root / LOCK_NAME
        self._fd: int | None = fd

    @classmethod
    def acquire(cls, root: str | Path) -> RunLock:
        """Lock ``root`` (an existing directory) at once, or raise :class:`RunInUseError`
        naming the holder."""
        folder = Path(root)
        path = folder / LOCK_NAME
        while True:
            fd = os.open(path, os.O_RDWR | os.O_CREAT | os.O_CLOEXEC, 0o666)
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                holder = _holder_text(os.pread(fd, 4096, 0))
                os.close(fd)
                raise RunInUseError(folder, holder) from None
            # a holder letting go unlinks the file: a lock on that old file locks nothing
            try:
                here, mine = os.stat(path), os.fstat(fd)
                current = (here.st_dev, here.st_ino) == (mine.st_dev, mine.st_ino)
            except FileNotFoundError:
                current = False
            if current:
                break
            os.close(fd)
        started = time.strftime("%Y-%m-%d %H:%M:%S UTC", time.gmtime())
        who = {"pid": os.getpid(), "host": socket.gethostname(), "started": started}
        os.ftruncate(fd, 0)
        os.pwrite(fd, (json.dumps(who) + "\n").encode("utf-8"), 0)
        return cls(folder, fd)

    @property
    def held(self) -> bool:
        """Whether this lock is still held."""
        return self._fd is not None

    def release(self, *, remove: bool = True) -> None:
        """Let go, removing the lock file first unless ``remove`` is false (the next writer
        then locks a fresh file or takes this one over)."""
        if self._fd is None:
            return
        fd, self._fd = self._fd, None
        try:
            if remove:
                self.path.unlink(missing_ok=True)
        finally:
            os.close(fd)

    def __enter__(self) -> RunLock:
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.release()


__all__ = ["LOCK_NAME", "RunInUseError", "RunLock"]
