"""Experience gains computed on background threads while the next genomes are simulated.

A generation's simulation steps all its robots in one Python thread, and its experience gains
(G, paper eqs. 5-8) are compiled kernels that need the simulation's points. Done one after the
other, G's minimum spanning trees are a large share of a generation (experiment E011,
"The experience gain beside the simulation"), and while the simulation runs, every core
but one is idle. With a :class:`GainOverlap`,
:meth:`~mentor_core.training.problem.NavigationProblem.evaluate` simulates the genomes in
``chunks`` contiguous parts and hands each part's point sets to background threads as soon as
the part is simulated (the kernels release the GIL). Once the last part is simulated, the
calling thread computes the sets no thread has claimed yet. Every G is one point set's exact
MST length computed by one thread (or by two, to the same value), so the values are those of
:func:`~mentor_core.objectives.experience.experience_gains_packed` bit for bit, whatever the
chunks and threads; and a genome's F does not depend on which genomes share its simulation.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor

import numpy as np
from numpy.typing import NDArray

from mentor_core.objectives.experience import experience_gains_shared
from mentor_core.objectives.jit import HAVE_NUMBA, thread_count


def default_chunks(threads: int) -> int:
    """Parts a generation is simulated in, for numba's ``threads``.

    Each part is a batch of its own, so each part more costs the simulation its per-decision
    overhead again (0.03-0.05 s for the shipped UGV config on two cores); fewer parts leave
    more of G after the last one. With two threads, four parts cost a generation least
    (measured: "The experience gain beside the simulation"). With four threads or more, the
    background threads keep up and G after the simulation is short anyway, so two parts (a
    model from those figures; not measured on more than two cores).
    """
    return 4 if threads < 4 else 2


#: fewest robots a part is simulated with: below it, a part's per-decision overhead costs more
#: than its G saves (measured: the shipped UGV config's 6,000 robots a generation cost least
#: in 4 parts of 1,500, more in 6 of 1,000; the Swarm-Robot's 2,000 gained nothing in 2 parts
#: and lost in 4 of 500: "The experience gain beside the simulation")
MIN_PART_ROBOTS = 1500


def split_evenly(n: int, parts: int) -> list[tuple[int, int]]:
    """``range(n)`` in at most ``parts`` contiguous, near-equal (lo, hi) slices."""
    parts = max(1, min(parts, n))
    bounds = np.linspace(0, n, parts + 1).round().astype(int)
    return [(int(lo), int(hi)) for lo, hi in itertools.pairwise(bounds) if hi > lo]


class GainOverlap:
    """Background threads for the experience gains of a generation simulated in parts.

    Args:
        chunks: parts the genomes of an ``evaluate`` call are simulated in (at least 1);
            default :func:`default_chunks` of numba's threads.
        threads: background threads; default one fewer than numba's threads (the simulation
            keeps one core, and the calling thread helps at the end), at least one.
        min_part_robots: fewest robots a part is simulated with (:data:`MIN_PART_ROBOTS`);
            a generation too small for two parts is evaluated as without the overlap.

    Use :meth:`available` to ask whether overlapping can pay here: it needs numba (the
    kernels release the GIL) and at least two of its threads.
    """

    def __init__(
        self,
        chunks: int | None = None,
        threads: int | None = None,
        min_part_robots: int | None = None,
    ) -> None:
        chunks = default_chunks(thread_count()) if chunks is None else chunks
        if chunks < 1:
            raise ValueError(f"chunks must be at least 1, got {chunks}")
        if threads is not None and threads < 1:
            raise ValueError(f"threads must be at least 1, got {threads}")
        min_part_robots = MIN_PART_ROBOTS if min_part_robots is None else min_part_robots
        if min_part_robots < 1:
            raise ValueError(f"min_part_robots must be at least 1, got {min_part_robots}")
        self.chunks = chunks
        self.min_part_robots = min_part_robots
        self.threads = threads or max(1, thread_count() - 1)
        self._pool = ThreadPoolExecutor(self.threads, thread_name_prefix="mentor-gain")

    @staticmethod
    def available() -> bool:
        """True where overlapping can pay: numba present, and two threads or more."""
        return HAVE_NUMBA and thread_count() >= 2

    def parts(self, n: int, robots_per_genome: int = 1) -> list[tuple[int, int]]:
        """The slices of ``n`` genomes (of ``robots_per_genome`` robots each: the problem's
        scenarios) simulated one after the other: at most ``chunks``, each of at least
        ``min_part_robots`` robots where there are two or more."""
        most = (n * robots_per_genome) // self.min_part_robots
        return split_evenly(n, max(1, min(self.chunks, most)))

    def submit(
        self, points: NDArray[np.float64], offsets: NDArray[np.int64]
    ) -> Callable[[], NDArray[np.float64]]:
        """Start the G of each slice ``points[offsets[s]:offsets[s + 1]]`` on the background
        threads; returns a function that gives them in order (as
        ``experience_gains_packed(points, offsets)``). That function first computes, last
        first, the slices no thread has claimed yet: the calling thread, idle once its
        simulation is done, shares what is left."""
        n_sets = len(offsets) - 1
        gains = np.zeros(n_sets, dtype=np.float64)
        claimed = np.zeros(n_sets, dtype=np.int8)
        # one call per thread and part: a call takes the GIL only to start and to end (the
        # simulation holds it most of the time, and a thread waits about 5 ms for it)
        futures = [
            self._pool.submit(experience_gains_shared, points, offsets, gains, claimed)
            for _ in range(min(self.threads, n_sets))
        ]

        def gather() -> NDArray[np.float64]:
            experience_gains_shared(points, offsets, gains, claimed, reverse=True)
            for future in futures:
                future.result()
            return gains

        return gather

    def close(self, wait: bool = True) -> None:
        """Stop the threads; ``wait=False`` drops the parts not started (an interrupted run;
        a thread already on a part ends it, a fraction of a second)."""
        self._pool.shutdown(wait=wait, cancel_futures=not wait)
