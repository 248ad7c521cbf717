"""When a stream of messages (a robot's scans, its odometry) has gone stale.

A command re-sent on data that stopped coming drives the robot blind: at 1 m/s, one metre a
second. So each stream is judged by its own pace: it is stale when no message has come for
:data:`INTERVALS` times its typical interval (the median of the last :data:`KEPT`), never less
than ``floor`` (executor jitter) and never more than ``ceiling`` (the planner's
``stale_timeout``); until two messages have come, ``ceiling``. A 5 Hz lidar is then stale
after 0.5 s, 30 Hz odometry after 0.2 s (the floor). Times are the node's steady clock (ns),
so a stream is stale also when sim time stops.

A stream's interval is the longer of the one between its arrivals and the one between its
stamps: a simulator faster than real time (lockstep, answering as fast as the planner decides)
sends scans 0.5 s of sim time apart within a few ms; judged by its arrivals alone, any hiccup
of the machine (a busy core, a collection) would stop the robot, though the simulated robot
waits for its answer. A simulator slower than real time is judged by its arrivals.
"""

from __future__ import annotations

import itertools
import statistics
from collections import deque

#: typical intervals without a message before a stream is stale
INTERVALS = 2.5
#: arrival times kept for the typical interval
KEPT = 9
#: ns: the least a stream may go quiet before it is stale: a Python node's own callbacks (a
#: plan on a large map) hold messages up for tens of ms; 0.2 s is 20 cm at 1 m/s
FLOOR_NS = 200_000_000


class StreamFreshness:
    """One stream's arrivals and whether it is stale (module docstring).

    Args:
        ceiling_ns: ns after which a stream is stale whatever its pace (> 0).
        floor_ns: ns before which it is never stale (>= 0, at most ``ceiling_ns``).
    """

    def __init__(self, ceiling_ns: int, floor_ns: int = FLOOR_NS) -> None:
        if ceiling_ns <= 0:
            raise ValueError(f"ceiling must be positive, got {ceiling_ns} ns")
        self.ceiling_ns = int(ceiling_ns)
        self.floor_ns = min(max(0, int(floor_ns)), self.ceiling_ns)
        # (node time, stamp or None) of the latest messages
        self._arrivals: deque[tuple[int, int | None]] = deque(maxlen=KEPT)

    @property
    def last_ns(self) -> int | None:
        """Node time of the latest message, or None before any."""
        return self._arrivals[-1][0] if self._arrivals else None

    def arrived(self, now_ns: int, stamp_ns: int | None = None) -> None:
        """A message came at node time ``now_ns``, stamped ``stamp_ns`` (its header's time,
        ns; None: unknown)."""
        self._arrivals.append((int(now_ns), None if stamp_ns is None else int(stamp_ns)))

    def limit_ns(self) -> int:
        """ns of quiet after which the stream is stale (module docstring)."""
        if len(self._arrivals) < 2:
            return self.ceiling_ns
        pairs = list(itertools.pairwise(self._arrivals))
        typical = statistics.median(b[0] - a[0] for a, b in pairs)
        # stamps that jump back (a simulator that restarts) say nothing of the pace
        stamped = [b[1] - a[1] for a, b in pairs
                   if a[1] is not None and b[1] is not None and b[1] > a[1]]  # fmt: skip
        if stamped:
            typical = max(typical, statistics.median(stamped))
        return int(min(self.ceiling_ns, max(self.floor_ns, INTERVALS * typical)))

    def stale_for(self, now_ns: int) -> int | None:
        """ns since the latest message when that is beyond :meth:`limit_ns`, else None (also
        before any message: a stream that never came is missing, not stale)."""
        last = self.last_ns
        if last is None:
            return None
        age = int(now_ns) - last
        return age if age > self.limit_ns() else None


__all__ = ["FLOOR_NS", "INTERVALS", "KEPT", "StreamFreshness"]
