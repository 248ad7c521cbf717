"""A run directory as one transaction: one writer at a time, one run in it.

:func:`open_run` locks the directory for the writer's whole run
(:class:`~mentor_core.training.run_lock.RunLock`), refuses a directory that holds something
other than what the writer asked for, with one line saying what is there, and removes the
temporary files that interrupted writes of the run's files left (``mentor_core.atomic``).

What a writer may open:

* a new run (no ``--resume``): a new or empty directory; the lock file or temporary files that
  a run stopped before its first file left count as empty;
* ``--resume``: a directory holding a run: its ``checkpoint.json`` or, for a run killed before
  its first checkpoint, its ``config.yaml`` (the trainer checks that both name the config and
  seed it is given) or only the lock or temporary files of its start. A missing or empty
  directory is refused: there is nothing to resume.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from types import TracebackType

from mentor_core.atomic import remove_stale_temps, temp_target
from mentor_core.errors import FileFormatError, MentorError
from mentor_core.training.run_files import RunPaths
from mentor_core.training.run_lock import LOCK_NAME, RunLock


@dataclass
class RunDirectory:
    """A run directory opened by :func:`open_run`: locked until :meth:`close`."""

    paths: RunPaths
    lock: RunLock
    resume: bool
    created: bool  # made by open_run: removed again by a clean close that leaves it empty
    found_lock: bool  # the lock file was there: the trace of a run that started before

    def close(self, *, keep_lock_file: bool = False) -> None:
        """Release the lock, removing the lock file unless ``keep_lock_file`` (and the
        directory, when open_run made it and it is empty now)."""
        self.lock.release(remove=not keep_lock_file)
        if not keep_lock_file and self.created and not any(self.paths.root.iterdir()):
            self.paths.root.rmdir()

    def __enter__(self) -> RunDirectory:
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        # a run stopped (interrupted, failed) leaves the lock file as the trace of its start,
        # so that --resume continues even one stopped before its first file; a refusal
        # (MentorError) leaves the directory as it was
        refused = isinstance(exc, MentorError)
        self.close(keep_lock_file=exc is not None and (not refused or self.found_lock))


def is_run_directory(path: str | Path) -> bool:
    """Whether ``path`` is a folder holding a training run, or the start of one: one of the
    files a run writes (:attr:`RunPaths.files`) or the lock of its writer. Other commands
    never write there."""
    root = Path(path)
    if not root.is_dir():
        return False
    return (root / LOCK_NAME).exists() or any(p.exists() for p in RunPaths(root).files)


def open_run(out_dir: str | Path, *, resume: bool) -> RunDirectory:
    """Open ``out_dir`` for a new run or, with ``resume``, for continuing the run in it.

    Raises :class:`~mentor_core.training.run_lock.RunInUseError` naming the holder when
    another process writes there, and FileFormatError naming the directory and what it holds
    when it is no place for that run (see the module docstring)."""
    root = Path(out_dir)
    if root.exists() and not root.is_dir():
        raise FileFormatError(root, "is not a directory")
    if resume and not root.exists():
        raise FileFormatError(
            root, "nothing to resume: no such directory (start the run without --resume)"
        )
    paths = RunPaths(root)
    created = not root.exists()
    root.mkdir(parents=True, exist_ok=True)
    found_lock = (root / LOCK_NAME).exists()
    lock = RunLock.acquire(root)
    run_dir = RunDirectory(paths, lock, resume, created, found_lock)
    try:
        _check_contents(paths, resume, found_lock)
        remove_stale_temps(paths.files)
    except BaseException:
        run_dir.close(keep_lock_file=found_lock)  # refused: the directory as it was
        raise
    return run_dir


def _check_contents(paths: RunPaths, resume: bool, found_lock: bool) -> None:
    """Refuse a directory that is no place for the run asked for (module docstring)."""
    ours = set(paths.files)
    temps = [p for p in paths.root.iterdir() if temp_target(p) in ours]
    others = sorted(
        p.name for p in paths.root.iterdir() if p.name != LOCK_NAME and p not in temps
    )
    if paths.checkpoint.exists():
        if not resume:
            raise FileFormatError(
                paths.root, f"already holds {_describe_run(paths.checkpoint)}"
            )
    elif resume:
        if paths.config.exists():
            return  # stopped before its first checkpoint: the trainer checks config and seed
        if others:
            raise FileFormatError(
                paths.root, f"nothing to resume: holds {_names(others)} but no checkpoint.json "
                "or config.yaml of a run"
            )
        if not (found_lock or temps):  # no trace of a start either
            raise FileFormatError(
                paths.root, "nothing to resume: the directory is empty (start the run without "
                "--resume)"
            )
    elif paths.config.exists():
        raise FileFormatError(
            paths.root, "holds config.yaml of a run stopped before its first checkpoint; "
            "continue it with --resume, or choose another --out"
        )
    elif others:
        raise FileFormatError(
            paths.root, f"holds {_names(others)} and no run; choose a new or empty --out"
        )


def _describe_run(checkpoint: Path) -> str:
    """What a directory with this checkpoint holds, and what to do about it, in words."""
    try:
        state = json.loads(checkpoint.read_text(encoding="utf-8"))
        done, total = int(state["generation"]), int(state["config"]["generations"])
    except (OSError, ValueError, KeyError, TypeError):
        return "a run (checkpoint.json); continue it with --resume, or choose another --out"
    if done >= total:
        return f"a finished run ({total} generations); choose another --out"
    return (
        f"a run stopped after generation {done} of {total}; continue it with --resume, "
        "or choose another --out"
    )


def _names(names: list[str], shown: int = 3) -> str:
    """``a, b, c and 4 more``."""
    head = ", ".join(names[:shown])
    return head if len(names) <= shown else f"{head} and {len(names) - shown} more"


__all__ = ["RunDirectory", "open_run"]
