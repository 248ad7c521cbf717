"""The pose at a scan's stamp (runtime/odometry_history.py) and a stream's freshness
(runtime/stream_freshness.py): issue 56, points 1 and 2."""

from __future__ import annotations

import math

import pytest

from mentor_core.runtime.odometry_history import OdometryHistory, interpolated
from mentor_core.runtime.stream_freshness import FLOOR_NS, StreamFreshness

MS = 1_000_000


def test_the_heading_is_interpolated_the_shorter_way_round() -> None:
    a, b = (0.0, 0.0, math.radians(170)), (1.0, 2.0, math.radians(-170))
    x, y, heading = interpolated(a, b, 0.5)
    assert (x, y) == (0.5, 1.0)
    assert heading == pytest.approx(math.pi)  # through 180 deg, not through 0
    assert interpolated(a, b, 0.0)[2] == pytest.approx(a[2])
    assert interpolated(a, b, 1.0)[2] == pytest.approx(b[2])


def test_pose_at_brackets_holds_within_the_tolerance_and_restarts_when_time_goes_back() -> None:
    h = OdometryHistory(tolerance_ns=50 * MS, capacity=4)
    assert h.pose_at(0) is None and h.span is None
    h.add(100 * MS, (1.0, 0.0, 0.0))
    h.add(200 * MS, (2.0, 0.0, 0.0))
    assert h.pose_at(150 * MS) == (1.5, 0.0, 0.0)
    assert h.pose_at(200 * MS) == (2.0, 0.0, 0.0)
    assert h.pose_at(240 * MS) == (2.0, 0.0, 0.0)  # newer than the newest: held
    assert h.pose_at(260 * MS) is None
    assert h.pose_at(60 * MS) == (1.0, 0.0, 0.0) and h.pose_at(40 * MS) is None
    h.add(200 * MS, (2.5, 0.0, 0.0))  # the same stamp again: replaced
    assert h.pose_at(200 * MS) == (2.5, 0.0, 0.0) and len(h) == 2
    for k in range(3, 7):  # capacity 4: the oldest go
        h.add(k * 100 * MS, (float(k), 0.0, 0.0))
    assert h.span == (300 * MS, 600 * MS)
    h.add(10 * MS, (9.0, 9.0, 0.0))  # a clock that jumped back: a fresh history
    assert h.span == (10 * MS, 10 * MS) and h.pose_at(300 * MS) is None
    with pytest.raises(ValueError):
        OdometryHistory(tolerance_ns=-1)


def test_a_stream_is_stale_after_a_few_of_its_own_intervals() -> None:
    ceiling = 1500 * MS
    scans = StreamFreshness(ceiling)
    assert scans.stale_for(10**12) is None  # never came: missing, not stale
    scans.arrived(0)
    assert scans.limit_ns() == ceiling  # one message: no pace yet
    for k in range(1, 9):
        scans.arrived(k * 200 * MS)  # 5 Hz
    assert scans.limit_ns() == 500 * MS
    assert scans.stale_for(1600 * MS + 500 * MS) is None
    assert scans.stale_for(1600 * MS + 501 * MS) == 501 * MS
    odometry = StreamFreshness(ceiling)
    for k in range(9):
        odometry.arrived(k * 10 * MS)  # 100 Hz: the floor
    assert odometry.limit_ns() == FLOOR_NS
    slow = StreamFreshness(ceiling)
    for k in range(9):
        slow.arrived(k * 1000 * MS)  # 1 Hz: the ceiling
    assert slow.limit_ns() == ceiling


def test_a_simulator_faster_than_real_time_is_judged_by_its_stamps() -> None:
    ceiling = 1500 * MS
    lockstep = StreamFreshness(ceiling)
    for k in range(9):  # 0.5 s of sim time apart, answered within 12 ms
        lockstep.arrived(k * 12 * MS, stamp_ns=k * 500 * MS)
    assert lockstep.limit_ns() == 1250 * MS
    # a machine that stalls for 0.3 s (a busy core) stops no robot that waits for its answer
    assert lockstep.stale_for(8 * 12 * MS + 300 * MS) is None
    assert lockstep.stale_for(8 * 12 * MS + 1251 * MS) == 1251 * MS
    slower = StreamFreshness(ceiling)
    for k in range(9):  # a simulator at half real time: judged by its arrivals
        slower.arrived(k * 400 * MS, stamp_ns=k * 200 * MS)
    assert slower.limit_ns() == 1000 * MS
    restarted = StreamFreshness(ceiling)
    for k in range(9):  # 100 Hz, its stamps jumping back to 0 halfway (a restart)
        restarted.arrived(k * 10 * MS, stamp_ns=(k % 5) * 10 * MS)
    assert restarted.limit_ns() == FLOOR_NS
