"""When the planner node decides, on which pose, and when its data is stale.

:class:`DecisionGate` is the planner node's bookkeeping, kept here so that it is tested
without a ROS graph. The node feeds it every scan, odometry, goal and episode event with its
stamp (ns, sim time) and the node time it came at (ns, steady clock), and asks it

* :meth:`DecisionGate.take`: a new observation to answer: the latest scan, with the pose at
  the scan's stamp (:class:`~mentor_core.runtime.odometry_history.OdometryHistory`: between
  the odometry before and after it, or the nearest within ``sync_tolerance``), once per scan
  stamp (a repeated observation is answered only once; a clock that jumps back, as when the
  simulator restarts, is followed) or per new goal (a new goal is a new question);
* :meth:`DecisionGate.stale`: whether the scans or the odometry have stopped coming, judged
  by each stream's own pace (:class:`~mentor_core.runtime.stream_freshness.StreamFreshness`);
  the node then sends a zero Twist at once instead of its last command again;
* :meth:`DecisionGate.watchdog`: once per control period, whether the planner has gone
  ``stale_after`` without answering (missing, stale or unpaired data), or a stream is stale;
  the node then sends a zero Twist and a warning naming why. The node's times are its steady
  clock's, so the watchdog fires when sim time stops;
* :meth:`DecisionGate.end_goal`: the goal is done (reached, aborted or canceled, as
  :class:`~mentor_core.runtime.goal_tracker.GoalTracker` judges) and dropped.

A refused scan (:meth:`DecisionGate.refuse_scan`: invalid ranges the planner cannot read) drops
the scan held, so that nothing is decided on an older one until a good scan comes.

A planner with a memory decides from what it decided before: the gate marks the first
observation it answers for a new goal or a new episode (:attr:`Observation.new_goal`) so that
the node resets the planner there, as each episode of training starts blank. An observation
is answered once, so a repeated one (lockstep resends) never advances the memory twice.

Goals: a goal within :data:`~mentor_core.runtime.goal_intake.SAME_GOAL` m of the current one
is the same goal (the simulator's ``started`` event and a goal topic may carry one goal through
different frames).

Episode events (optional; a planner fed by something other than the simulator never gets
any): after an end event (reached, collided, timed out) the robot no longer drives and its goal
is done, so the gate answers nothing and the watchdog stays quiet until the next ``started``
event, which may carry the new goal; the scan and odometry of the episode that ended are
dropped at its end. The simulator publishes the next episode's ``started`` event before its
first observation, and the planner node handles events before observations
(its events subscription comes first), so an observation of a new episode is never answered
with the previous episode's goal, whatever order the goal topic and the observations arrive
in.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from mentor_core.runtime.goal_intake import same_goal
from mentor_core.runtime.odometry_history import OdometryHistory, Pose
from mentor_core.runtime.stream_freshness import StreamFreshness
from mentor_core.sim.scan_adapter import MountedScan

FloatArray = NDArray[np.float64]
_NS_PER_S = 1_000_000_000
_END_EVENTS = frozenset({"reached", "collided", "timed_out"})


@dataclass(frozen=True)
class Observation:
    """What the planner answers: stamp (ns) of the scan, readings, the pose at that stamp and
    the goal (None when no goal has been received); ``new_goal``: the first observation
    answered since a new goal or a ``started`` event (a planner with a memory starts blank on
    it); ``new_episode``: the first since a ``started`` event (a new episode, perhaps in
    another world); ``scan``: the lidar scan the readings were read off (None: per-sensor
    readings), for a map of all its rays."""

    stamp_ns: int
    ranges: FloatArray
    pose: Pose
    goal: tuple[float, float] | None
    new_goal: bool = False
    new_episode: bool = False
    scan: MountedScan | None = None


class DecisionGate:
    """When the planner node decides, on which pose, and when its data is stale (module
    docstring).

    Message stamps (sim time of the scan and odometry) decide which observation is new and
    pair the scan with its pose; node times (the node's steady clock when a message is
    handled) drive the watchdog and the streams' freshness, so the two time bases never mix.

    Args:
        stale_after: s (node time) without an answered observation after which the
            watchdog fires, and the longest any stream may go quiet; larger than the control
            period.
        sync_tolerance: s a scan's stamp may lie beyond the odometry's newest (or oldest)
            stamp and still take that pose.
    """

    def __init__(self, stale_after: float, sync_tolerance: float) -> None:
        if not (np.isfinite(stale_after) and stale_after > 0.0):
            raise ValueError(f"stale_after must be positive, got {stale_after}")
        if not (np.isfinite(sync_tolerance) and sync_tolerance >= 0.0):
            raise ValueError(f"sync_tolerance must be >= 0, got {sync_tolerance}")
        self.stale_after_ns = round(stale_after * _NS_PER_S)
        self.sync_tolerance_ns = round(sync_tolerance * _NS_PER_S)
        self._scan: tuple[int, FloatArray, MountedScan | None] | None = None
        self._last_scan_stamp: int | None = None
        self._odometry = OdometryHistory(self.sync_tolerance_ns)
        self._streams = {name: StreamFreshness(self.stale_after_ns)
                         for name in ("scan", "odometry")}  # fmt: skip
        self._goal: tuple[float, float] | None = None
        self._answered_stamp: int | None = None  # stamp of the last observation answered
        self._answered_goal: tuple[float, float] | None = None  # the goal it was answered with
        self._answered_at: int | None = None  # node time of that answer
        self._since: int | None = None  # node time the watchdog counts from before an answer
        self._idle = False
        self._new_goal = False  # no observation answered since a new goal or episode
        self._new_episode = False  # no observation answered since a started event

    @property
    def idle(self) -> bool:
        """The robot's episode has ended (no ``started`` event since)."""
        return self._idle

    def on_scan(self, stamp_ns: int, ranges: ArrayLike, received_ns: int | None = None,
                scan: MountedScan | None = None) -> None:  # fmt: skip
        """The latest scan (readings checked by the caller), stamped ``stamp_ns``, handled at
        node time ``received_ns`` (None: not counted for freshness); ``scan``: the lidar scan
        the readings were read off, kept for :attr:`Observation.scan`. A scan older than the
        last one (a clock that jumped back) starts the odometry afresh too."""
        stamp = int(stamp_ns)
        if self._last_scan_stamp is not None and stamp < self._last_scan_stamp:
            self._odometry.clear()
        self._last_scan_stamp = stamp
        self._scan = (stamp, np.asarray(ranges, dtype=np.float64).copy(), scan)
        if received_ns is not None:
            self._streams["scan"].arrived(received_ns, stamp)

    def refuse_scan(self, received_ns: int | None = None) -> None:
        """A scan came that the planner could not read: nothing is decided on an older one
        until a good one comes (the stream itself is alive)."""
        self._scan = None
        if received_ns is not None:
            self._streams["scan"].arrived(received_ns)

    def on_odometry(self, stamp_ns: int, pose: Pose, received_ns: int | None = None) -> None:
        """An odometry pose, stamped ``stamp_ns``, handled at node time ``received_ns``."""
        self._odometry.add(int(stamp_ns), (float(pose[0]), float(pose[1]), float(pose[2])))
        if received_ns is not None:
            self._streams["odometry"].arrived(received_ns, int(stamp_ns))

    @property
    def goal(self) -> tuple[float, float] | None:
        """The goal being driven to (None: none)."""
        return self._goal

    def on_goal(self, goal: tuple[float, float]) -> bool:
        """A goal (x, y) in the frame the planner decides in; False when it is the goal
        already held."""
        new = (float(goal[0]), float(goal[1]))
        if same_goal(self._goal, new):
            return False
        self._goal = new
        self._new_goal = True
        return True

    def end_goal(self) -> None:
        """The goal is done (reached, aborted or canceled: :class:`GoalTracker` judges): it
        is dropped, and nothing is answered until another comes."""
        self._goal = None

    def on_event(
        self, kind: str, now_ns: int, goal: tuple[float, float] | None = None
    ) -> None:
        """An episode event of this robot, handled at node time ``now_ns``; a ``started``
        event may carry the episode's goal (x, y)."""
        if kind in _END_EVENTS:
            # what was seen in the episode that ended is never answered with the next goal,
            # nor a pose interpolated across the robot's move to its next start
            self._idle = True
            self._goal = None
            self._scan = None
            self._odometry.clear()
        elif kind == "started":
            self._idle = False
            self._new_goal = True  # a new episode, even towards the goal held
            self._new_episode = True
            self._since = int(now_ns)
            self._answered_at = None
            if goal is not None:
                self.on_goal(goal)

    def take(self, now_ns: int) -> Observation | None:
        """The next observation to answer at node time ``now_ns``, or None (nothing new, no
        goal yet, no pose at the scan's stamp, or the episode has ended). Taking it marks it
        answered."""
        if self._idle or self._scan is None or self._goal is None:
            return None
        stamp, ranges, scan = self._scan
        pose = self._odometry.pose_at(stamp)
        if pose is None:
            return None
        if stamp == self._answered_stamp and self._goal == self._answered_goal:
            return None
        self._answered_stamp = stamp
        self._answered_goal = self._goal
        self._answered_at = int(now_ns)
        new_goal, self._new_goal = self._new_goal, False
        new_episode, self._new_episode = self._new_episode, False
        return Observation(stamp, ranges.copy(), pose, self._goal, new_goal, new_episode, scan)

    def stale(self, now_ns: int) -> str | None:
        """Why the last command must not be sent again at node time ``now_ns`` (a stream has
        stopped: one line), or None. Quiet while idle or without a goal (nothing is being
        driven)."""
        if self._idle or self._goal is None:
            return None
        for name, stream in self._streams.items():
            age = stream.stale_for(now_ns)
            if age is not None:
                return (f"no {name} for {age / _NS_PER_S:.3f} s (stale after "
                        f"{stream.limit_ns() / _NS_PER_S:.3f} s)")  # fmt: skip
        return None

    def watchdog(self, now_ns: int) -> str | None:
        """Why the planner should send a zero Twist at node time ``now_ns`` (one line), or None.

        Quiet while idle and without a goal: a node with nothing to drive to publishes nothing
        (it would fight a teleoperator; the goal's end sent its zero Twist). Otherwise it fires
        when a stream is :meth:`stale`, or when the last answer (or, before any, the first
        watchdog call, the last ``started`` event or the goal's arrival) lies more than
        ``stale_after`` back.
        """
        if self._since is None:
            self._since = int(now_ns)
        if self._idle or self._goal is None:
            # a goal that comes later is given stale_after afresh
            self._since, self._answered_at = int(now_ns), None
            return None
        stopped = self.stale(now_ns)
        if stopped is not None:
            return stopped
        ref = self._answered_at if self._answered_at is not None else self._since
        age = now_ns - ref
        if age <= self.stale_after_ns:
            return None
        missing = [what for what, absent in (("scan", self._scan is None),
                                             ("odometry", not len(self._odometry))) if absent]
        if missing:
            return f"no {', '.join(missing)} received"
        assert self._scan is not None
        span = self._odometry.span
        if span is not None and self._odometry.pose_at(self._scan[0]) is None:
            return (f"no odometry within {self.sync_tolerance_ns / _NS_PER_S:.3f} s of the "
                    f"scan's stamp {self._scan[0] / _NS_PER_S:.3f} s (odometry from "
                    f"{span[0] / _NS_PER_S:.3f} to {span[1] / _NS_PER_S:.3f} s)")  # fmt: skip
        return f"no new scan and odometry for {age / _NS_PER_S:.3f} s"


__all__ = ["DecisionGate", "Observation"]
