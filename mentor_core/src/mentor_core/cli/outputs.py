"""The output policy of every ``mentor-*`` command that writes, checked before the work starts.

One policy (``docs/files.md``), for a file (``mentor-eval --out``, ``mentor-draw --out``), a
bag (``mentor-eval --record``) and a folder of results (``mentor-bench --out``,
``mentor-report --out``); ``mentor-train --out`` is a run directory, held to the same rules by
:func:`mentor_core.training.run_directory.open_run`:

* never an input, a folder holding an input or a path inside an input folder (not even with
  ``--force``: the result would be computed from what it destroys);
* never an existing file, bag or non-empty folder unless ``--force`` is given;
* never a training run directory, nor a bag where a folder of results goes, nor a file where a
  folder goes (not even with ``--force``);
* a target that cannot be written (a read-only file system, a path through a file) is refused
  at once, not after hours of work.

Each refusal is one :class:`OutputError` line naming the option and the path. A command checks
every output before it reads or computes anything else, so a refusal costs nothing and
nothing is half-written; what it then writes is written atomically (``mentor_core.atomic``).
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Iterable
from pathlib import Path

from mentor_core.atomic import remove_stale_temps, temp_target
from mentor_core.errors import MentorError
from mentor_core.files.bags import looks_like_bag
from mentor_core.files.bags.writing import remove_stale_staging
from mentor_core.training.run_directory import is_run_directory

#: the files a folder of results holds (``bench.json``, ``report.md``, figures)
RESULT_SUFFIXES = (".json", ".md", ".png")


class OutputError(MentorError):
    """An output path the command may not write."""

    def __init__(self, option: str, path: Path, fault: str) -> None:
        super().__init__(f"{option} {path}: {fault}")


def check_file(option: str, path: Path, inputs: Iterable[Path], force: bool) -> None:
    """``path`` may be written as a file: it is no input, and no existing file unless
    ``force`` (a directory never), and its folder takes new files. The temporary file of an
    earlier write of it that was killed is removed."""
    _not_an_input(option, path, inputs)
    if path.is_dir():
        raise OutputError(option, path, "is a directory")
    if exists(path) and not force:
        raise OutputError(option, path, "already exists; pass --force to replace it")
    check_writable(option, path)
    remove_stale_temps([path])  # a killed earlier write's temporary file


def check_bag(option: str, path: Path, inputs: Iterable[Path], force: bool) -> None:
    """``path`` may be written as a bag directory: it is no input and holds none, it is no
    existing bag unless ``force`` (anything else that exists never), and its folder takes new
    files. The staging folders of an earlier write of it that was killed are removed first
    (``files.bags.writing.remove_stale_staging``)."""
    _not_an_input(option, path, inputs)
    if path.parent.is_dir():
        remove_stale_staging(path)
    check_writable(option, path)
    if not exists(path):
        return
    if not looks_like_bag(path):
        raise OutputError(option, path, "already exists and is not a bag; not replacing it")
    if not force:
        raise OutputError(option, path, "already exists; pass --force to replace it")


def check_folder(option: str, path: Path, inputs: Iterable[Path], force: bool) -> None:
    """``path`` may receive a command's files (``bench.json``, ``report.md``, figures): it is
    no input, holds none and lies in none; it is no file, no bag and no training run
    directory; unless ``force`` it is new or empty; and it takes new files. The temporary
    files that killed writes of results (``.json``, ``.md``, ``.png``) left there are
    removed."""
    _not_an_input(option, path, inputs)
    if exists(path) and not path.is_dir():
        raise OutputError(option, path, "is not a directory")
    if is_run_directory(path):
        raise OutputError(option, path, "is a training run directory; not writing there")
    if (path / "metadata.yaml").is_file():  # a rosbag2 bag (an empty folder is none here)
        raise OutputError(option, path, "is a rosbag2 bag; not writing there")
    if path.is_dir() and any(path.iterdir()) and not force:
        raise OutputError(option, path, "already exists and is not empty; pass --force to "
                                        "write into it")  # fmt: skip
    check_writable(option, path)
    if path.is_dir():
        targets = [temp_target(entry) for entry in path.iterdir()]
        remove_stale_temps(t for t in targets if t is not None and t.suffix in RESULT_SUFFIXES)


def check_writable(option: str, path: Path) -> None:
    """Refuse ``path`` when it cannot be made: a file on its way, or a nearest existing folder
    that takes no new file (a read-only file system; tried with a file created and removed
    at once, since permission bits do not bind root)."""
    folder = path if path.is_dir() else path.parent
    while not exists(folder):
        folder = folder.parent
    if not folder.is_dir():
        raise OutputError(option, path, f"{folder} is not a directory")
    try:
        with tempfile.TemporaryFile(dir=folder):
            pass
    except OSError as err:
        raise OutputError(option, path, f"cannot write in {folder} ({err.strerror})") from None


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


__all__ = [
    "OutputError",
    "check_bag",
    "check_distinct",
    "check_file",
    "check_folder",
    "check_writable",
    "exists",
]
