"""The robot's pose at a scan's stamp, from the odometry that came before and after it.

A lidar scans at 5-40 Hz and odometry comes at 10-100 Hz, at stamps of their own, so the pose
of the odometry that came last is rarely the pose at which the scan was taken. The planner
pairs by stamp instead, with the scan as the clock (as Nav2's costmaps take the robot's pose
at a scan's stamp from TF): :meth:`OdometryHistory.pose_at` interpolates between the two
odometry poses whose stamps bracket the scan's, linearly in x, y and along the shorter way
round in heading. A scan newer than the newest odometry (or older than the oldest) takes
that pose if it lies within ``tolerance`` of the scan's stamp, else none: the planner then
waits for the odometry to catch up, or its watchdog says why it cannot. A robot at 1 m/s moves
at most ``tolerance`` m between the pose used and the one it had.

Stamps are ns (sim time or the robot's clock); odometry whose stamp goes back (a simulator
that restarts) starts the history afresh.
"""

from __future__ import annotations

import bisect
import math
from collections import deque

Pose = tuple[float, float, float]

#: odometry poses kept: 2 s at 100 Hz, more than any scan waits
CAPACITY = 200


class OdometryHistory:
    """The latest odometry poses by stamp (module docstring).

    Args:
        tolerance_ns: ns a scan may lie beyond the odometry's first or last stamp (>= 0).
        capacity: poses kept (>= 2).
    """

    def __init__(self, tolerance_ns: int, capacity: int = CAPACITY) -> None:
        if tolerance_ns < 0:
            raise ValueError(f"tolerance must be >= 0 ns, got {tolerance_ns}")
        if capacity < 2:
            raise ValueError(f"capacity must be at least 2, got {capacity}")
        self.tolerance_ns = int(tolerance_ns)
        self._stamps: deque[int] = deque(maxlen=capacity)
        self._poses: deque[Pose] = deque(maxlen=capacity)

    def __len__(self) -> int:
        return len(self._stamps)

    @property
    def span(self) -> tuple[int, int] | None:
        """(first, last) stamp held, or None when empty."""
        return (self._stamps[0], self._stamps[-1]) if self._stamps else None

    def add(self, stamp_ns: int, pose: Pose) -> None:
        """An odometry pose; one with the stamp of the last replaces it, an older one starts
        the history afresh."""
        stamp = int(stamp_ns)
        value = (float(pose[0]), float(pose[1]), float(pose[2]))
        if self._stamps and stamp <= self._stamps[-1]:
            if stamp == self._stamps[-1]:
                self._poses[-1] = value
                return
            self.clear()
        self._stamps.append(stamp)
        self._poses.append(value)

    def clear(self) -> None:
        """Forget every pose."""
        self._stamps.clear()
        self._poses.clear()

    def pose_at(self, stamp_ns: int) -> Pose | None:
        """The pose at ``stamp_ns`` (module docstring), or None."""
        stamps = self._stamps
        if not stamps:
            return None
        k = bisect.bisect_left(stamps, stamp_ns)
        if k < len(stamps) and stamps[k] == stamp_ns:
            return self._poses[k]
        if k == 0:
            return self._poses[0] if stamps[0] - stamp_ns <= self.tolerance_ns else None
        if k == len(stamps):
            return self._poses[-1] if stamp_ns - stamps[-1] <= self.tolerance_ns else None
        f = (stamp_ns - stamps[k - 1]) / (stamps[k] - stamps[k - 1])
        return interpolated(self._poses[k - 1], self._poses[k], f)


def interpolated(a: Pose, b: Pose, f: float) -> Pose:
    """The pose a fraction ``f`` of the way from ``a`` to ``b``: x and y linearly, the heading
    along the shorter way round, wrapped to ``(-pi, pi]``."""
    turn = math.remainder(b[2] - a[2], 2.0 * math.pi)
    heading = math.remainder(a[2] + f * turn, 2.0 * math.pi)
    if heading == -math.pi:
        heading = math.pi
    return (a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1]), heading)


__all__ = ["CAPACITY", "OdometryHistory", "Pose", "interpolated"]
