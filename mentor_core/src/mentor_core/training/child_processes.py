"""Child processes that die with their parent: pool workers and a local Ray runtime.

A ``kill -9`` of a training run must not leave its helpers running (each pool worker holds a
copy of the problem, some 180 MB). Two mechanisms, one per kind of helper:

- :func:`die_with_parent`, a process pool's initializer: on Linux the kernel sends the worker
  SIGKILL when its parent dies (``prctl(PR_SET_PDEATHSIG)``); elsewhere a watchdog thread
  polls the parent's pid. Workers also ignore SIGINT: on Ctrl-C the parent stops them, rather
  than each printing a traceback. They start with SIGINT blocked (:class:`QuietSpawnProcess`),
  so a Ctrl-C while one is still importing waits for the initializer instead of ending it
  with a traceback. (The pool's resource tracker then exits on its own: it lives as long as a
  process holds its pipe.)
- :class:`Reaper`, a small process that outlives its parent. Ray's local runtime ties its
  raylet and GCS to the driver the same way (PR_SET_PDEATHSIG), but the raylet's agents
  (``ray::DashboardAgent``, ``ray::RuntimeEnvAgent``) outlive a killed raylet for a minute or
  more, retrying the dead GCS. The reaper remembers, every :data:`REAPER_INTERVAL_S`, the
  processes its parent started after it (and theirs); if the parent dies without saying
  ``stop``, it sends those that remain SIGTERM, then SIGKILL after :data:`REAPER_GRACE_S`.
  Linux only (it reads ``/proc``); elsewhere Ray kills its own process group when the
  driver dies.

``python -I child_processes.py PARENT_PID`` runs the reaper (this file imports only the
standard library, so it runs whatever the parent's ``sys.path``).
"""

from __future__ import annotations

import contextlib
import ctypes
import os
import select
import signal
import subprocess
import sys
import threading
import time
from collections.abc import Callable, Collection
from concurrent.futures import ProcessPoolExecutor
from multiprocessing import resource_tracker
from multiprocessing.context import SpawnContext, SpawnProcess
from pathlib import Path
from typing import Any

PR_SET_PDEATHSIG = 1  # linux/prctl.h
WATCHDOG_PERIOD_S = 0.5
REAPER_INTERVAL_S = 0.5
REAPER_GRACE_S = 2.0


def die_with_parent(parent_pid: int) -> None:
    """Pool initializer: end this worker when ``parent_pid`` dies; ignore SIGINT.

    Linux: the parent death signal is tied to the parent *thread* that started the worker, so
    a pool must be used from the thread that created it (the trainer's main thread does).
    """
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    if sys.platform.startswith("linux"):
        libc = ctypes.CDLL(None, use_errno=True)
        if libc.prctl(PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0) == 0:
            if os.getppid() != parent_pid:  # the parent died before prctl took effect
                os._exit(1)
            return
    threading.Thread(target=_watch_parent, args=(parent_pid,), daemon=True).start()


class QuietSpawnProcess(SpawnProcess):
    """A spawned process that starts with SIGINT blocked.

    A blocked signal stays blocked through fork and exec, so a Ctrl-C that reaches the worker
    while it imports (before :func:`die_with_parent` ignores SIGINT) stays pending and is then
    discarded, instead of a KeyboardInterrupt traceback from ``spawn_main``. The parent's
    thread only holds it back while it starts the process: a Ctrl-C then arrives right
    after (or at once, through another thread)."""

    def start(self) -> None:
        before = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
        try:
            super().start()
        finally:
            signal.pthread_sigmask(signal.SIG_SETMASK, before)


class QuietSpawnContext(SpawnContext):
    """multiprocessing's spawn context, with :class:`QuietSpawnProcess` processes."""

    Process = QuietSpawnProcess


def spawn_pool(
    workers: int, initializer: Callable[..., object], initargs: tuple[Any, ...]
) -> ProcessPoolExecutor:
    """A pool of ``workers`` spawned processes (spawn, not fork: numba's OpenMP threads do not
    survive a fork) whose initializer should call :func:`die_with_parent`.

    Multiprocessing's resource tracker is started first with its stderr on /dev/null: after a
    ``kill -9`` of this process it unlinks the pool's semaphores, as it should, but would say
    so in a two-line UserWarning under the command's last line."""
    _start_quiet_resource_tracker()
    return ProcessPoolExecutor(
        max_workers=workers,
        mp_context=QuietSpawnContext(),
        initializer=initializer,
        initargs=initargs,
    )


def _start_quiet_resource_tracker() -> None:
    sys.stderr.flush()
    saved = os.dup(2)
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, 2)
        os.close(devnull)
        resource_tracker.ensure_running()  # a no-op when it runs already
    finally:
        os.dup2(saved, 2)
        os.close(saved)


def stop_pool(pool: ProcessPoolExecutor) -> None:
    """Stop ``pool``'s workers now (SIGTERM, then SIGKILL after 5 s) and shut it down,
    dropping the tasks not started: its workers ignore Ctrl-C (:func:`die_with_parent`)."""
    # the executor has no public way to stop a busy worker (Python 3.14 adds one)
    processes = list((pool._processes or {}).values())
    for process in processes:
        process.terminate()
    for process in processes:
        process.join(timeout=5)
        if process.is_alive():
            process.kill()
            process.join()
    pool.shutdown(wait=True, cancel_futures=True)


def _watch_parent(parent_pid: int) -> None:
    while os.getppid() == parent_pid:
        time.sleep(WATCHDOG_PERIOD_S)
    os._exit(1)


def process_table() -> dict[int, tuple[int, int]]:
    """Live processes of this machine: pid -> (parent pid, start time in clock ticks).

    Read from ``/proc`` (Linux; empty elsewhere). Zombies are left out: they are dead.
    """
    table: dict[int, tuple[int, int]] = {}
    with contextlib.suppress(OSError):
        for entry in os.scandir("/proc"):
            if not entry.name.isdigit():
                continue
            try:
                stat = Path(entry.path, "stat").read_text()
            except OSError:  # exited meanwhile
                continue
            # "pid (comm) state ppid ... starttime": comm may hold spaces and parentheses
            fields = stat[stat.rindex(")") + 2 :].split()
            if fields[0] != "Z":
                table[int(entry.name)] = (int(fields[1]), int(fields[19]))
    return table


def descendants(
    roots: Collection[int], table: dict[int, tuple[int, int]] | None = None
) -> dict[int, int]:
    """Children of the ``roots`` pids, theirs, and so on: pid -> start time (clock ticks)."""
    table = process_table() if table is None else table
    children: dict[int, list[int]] = {}
    for child, (parent, _) in table.items():
        children.setdefault(parent, []).append(child)
    found: dict[int, int] = {}
    todo = list(roots)
    while todo:
        for child in children.get(todo.pop(), ()):
            if child not in found:
                found[child] = table[child][1]
                todo.append(child)
    return found


class Reaper:
    """A process that stops what this process starts from now on, should this one die.

    :meth:`start` it just before starting helpers (a local Ray), :meth:`stop` it after they
    were shut down: then it ends without touching anything. Does nothing off Linux.
    """

    def __init__(self) -> None:
        self._proc: subprocess.Popen[bytes] | None = None

    def start(self) -> None:
        """Start the reaper process (Linux); returns once it has seen the current children."""
        if not Path("/proc/self/stat").exists() or self._proc is not None:
            return
        self._proc = subprocess.Popen(
            [sys.executable, "-I", os.path.abspath(__file__), str(os.getpid())],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            stderr=subprocess.DEVNULL,
            start_new_session=True,  # no Ctrl-C or hang-up of the terminal reaches it
        )
        if self._proc.stdout is not None:
            self._proc.stdout.readline()  # "ready": what runs now is not its to stop
            self._proc.stdout.close()

    def stop(self) -> None:
        """Tell the reaper that all went well, and wait for it to end; idempotent."""
        proc, self._proc = self._proc, None
        if proc is None:
            return
        if proc.stdin is not None:
            with contextlib.suppress(OSError):
                proc.stdin.write(b"stop\n")
                proc.stdin.close()
        try:
            proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()


def _alive(known: dict[int, int], table: dict[int, tuple[int, int]]) -> dict[int, int]:
    """The processes of ``known`` still running (same pid and start time: not a reused pid)."""
    return {pid: start for pid, start in known.items() if table.get(pid, (0, -1))[1] == start}


def _reap(known: dict[int, int]) -> None:
    """SIGTERM the processes of ``known`` still alive and all their descendants; SIGKILL the
    ones left after :data:`REAPER_GRACE_S`."""
    table = process_table()
    alive = _alive(known, table)
    targets = {**alive, **descendants(alive, table)}
    targets.pop(os.getpid(), None)
    for sig in (signal.SIGTERM, signal.SIGKILL):
        for pid in targets:
            with contextlib.suppress(OSError):
                os.kill(pid, sig)
        deadline = time.monotonic() + REAPER_GRACE_S
        while targets and time.monotonic() < deadline:
            time.sleep(0.05)
            targets = _alive(targets, process_table())
        if not targets:
            return


def _reaper_main(parent_pid: int) -> int:
    """Watch ``parent_pid`` (see :class:`Reaper`): it died when stdin ends or this process got
    another parent, unless it said ``stop`` first."""
    existing = set(descendants([parent_pid])) | {os.getpid()}
    print("ready", flush=True)
    known: dict[int, int] = {}
    stdin = sys.stdin.fileno()
    while True:
        table = process_table()
        known = _alive(known, table)
        known.update(
            (pid, start)
            for pid, start in descendants([parent_pid], table).items()
            if pid not in existing
        )
        known.update(descendants(known, table))  # orphans of a dead child stay known
        readable, _, _ = select.select([stdin], [], [], REAPER_INTERVAL_S)
        message = os.read(stdin, 64) if readable else b"?"
        if message.startswith(b"stop"):
            return 0
        if not message or os.getppid() != parent_pid:
            _reap(known)
            return 0


if __name__ == "__main__":
    sys.exit(_reaper_main(int(sys.argv[1])))
