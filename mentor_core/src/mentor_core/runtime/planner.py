"""The planner: an evolved genome deciding for one robot, and when to decide.

:class:`GenomePlanner` is the decision chain of the batched episodes
(:class:`mentor_core.controller.pipeline.DecisionChain`) for a single robot, through the stages
of its deployment (:func:`deployed_genome`), and its Twist
(:func:`mentor_core.sim.observation.twist_from_action`). The planner node calls nothing else.

:class:`DecisionGate` is the planner node's bookkeeping, kept here so that it is tested
without a ROS graph. The node feeds it every scan, odometry, goal and episode event with its
stamp (ns, sim time) and asks it

* :meth:`DecisionGate.take`: a new observation to answer, once per pair of latest scan and
  latest odometry whose stamps lie within ``sync_tolerance`` of each other and whose stamp
  differs from the last one answered (a repeated observation is answered only once; a clock
  that jumps back, as when the simulator restarts, is followed), or whose goal differs from
  the one it was answered with (a new goal is a new question);
* :meth:`DecisionGate.watchdog`: once per control period, whether the planner has gone
  ``stale_after`` without answering (missing or stale data); the node then sends a zero
  Twist and a throttled warning. The node's times are its steady clock's, so the watchdog
  fires when sim time stops;
* :meth:`DecisionGate.arrived`: the robot stands within the goal radius of its goal (the
  goal is then done and dropped, as a navigation stack's goal checker does).

A planner with a context (a memory of its previous outputs, ``RobotProfile.n_context``) or
a recurrent network (recurrent connection genes: its previous node values) decides from what
it decided before: :meth:`GenomePlanner.reset` starts it blank, and the
gate marks the first observation it answers for a new goal or a new episode
(:attr:`Observation.new_goal`) so that the node resets the planner there, as each episode of
training starts blank. An observation is answered once, so a repeated one (lockstep resends)
never advances the memory twice.

Goals: a goal within :data:`~mentor_core.runtime.goal_intake.SAME_GOAL` m of the current one
is the same goal (the simulator's ``started`` event and a goal topic may carry one goal through
different frames).

Episode events (optional; a planner fed by something other than the simulator never gets
any): after an end event (reached, collided, timed out) the robot no longer drives and its goal
is done, so the gate answers nothing and the watchdog stays quiet until the next ``started``
event, which may carry the new goal. The simulator publishes the next episode's ``started``
event before its first observation, and the planner node handles events before observations
(its events subscription comes first), so an observation of a new episode is never answered
with the previous episode's goal, whatever order the goal topic and the observations arrive
in.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from mentor_core.controller.deployment import Deployed, Deployment, deploy, trained_stages
from mentor_core.controller.pipeline import DecisionChain
from mentor_core.controller.stage import Stage
from mentor_core.errors import ConfigError, short_repr
from mentor_core.evolution.genome import Genome
from mentor_core.evolution.network import FeedForwardNetwork
from mentor_core.files.genome_file import load_genome_and_metadata
from mentor_core.runtime.goal_intake import same_goal
from mentor_core.sim import observation
from mentor_core.sim.planner_settings import with_planner
from mentor_core.sim.robots import (
    ROBOTS_ENV,
    RobotProfile,
    get_profile,
    load_profiles,
    sensor_record,
)

FloatArray = NDArray[np.float64]
Pose = tuple[float, float, float]
_NS_PER_S = 1_000_000_000
_END_EVENTS = frozenset({"reached", "collided", "timed_out"})
_ONE = np.zeros(1, dtype=np.int64)  # the one robot of a planner's decision chain


def planner_profile(
    profile: RobotProfile, metadata: Mapping[str, Any], source: str | Path = ""
) -> RobotProfile:
    """``profile`` as the genome was trained to use it: its metadata's ``input_encoding``
    (``"paper"`` for a genome saved before the key existed), ``heading_change_max`` (rad),
    ``step_max`` and ``step_min`` (m; each the profile's when absent),
    ``clearance_margin`` (m; absent: none), ``feedback_action``, ``memory_units`` and
    ``proximity_scale`` (m) (absent: off, as every genome saved before they existed) and
    ``control_period`` (s; absent: the robot's). The stages it was trained with are
    :func:`~mentor_core.controller.deployment.trained_stages`'.

    ConfigError naming ``source`` for a bad value, and for metadata whose ``sensors`` record
    (:func:`mentor_core.sim.robots.sensor_record`; absent in genomes saved before it existed)
    differs from the profile's: such a genome was trained with other sensors.
    """
    trained_for = metadata.get("robot", profile.name)  # absent in hand-made genomes
    if trained_for != profile.name:
        known = sorted(load_profiles())
        fault = (
            f"the genome was trained for robot {trained_for!r}, not {profile.name!r}"
            if trained_for in known
            else f"{short_repr(trained_for)} is no known robot (known: {', '.join(known)})"
        )
        raise ConfigError(fault, key="robot", path=source or None)
    trained = metadata.get("sensors")
    if trained is not None and trained != sensor_record(profile):
        raise ConfigError(
            f"the genome was trained with other sensors than robot {profile.name!r} has now "
            f"(mounts, range or beam); use the robot file it was trained with (${ROBOTS_ENV} "
            "names the file in use)",
            key="sensors",
            path=source or None,
        )
    return with_planner(
        profile,
        input_encoding=metadata.get("input_encoding", "paper"),
        heading_change_max=metadata.get("heading_change_max"),
        step_max=metadata.get("step_max"),
        step_min=metadata.get("step_min"),
        clearance_margin=metadata.get("clearance_margin"),
        feedback_action=metadata.get("feedback_action"),
        memory_units=metadata.get("memory_units"),
        control_period=metadata.get("control_period"),
        proximity_scale=metadata.get("proximity_scale"),
        source=source,
    )


def genome_profile(genome_path: str | Path, profile_name: str) -> RobotProfile:
    """The profile of robot ``profile_name`` as the genome in ``genome_path`` was trained to
    use it (:func:`planner_profile` of its metadata). The same errors as
    :meth:`GenomePlanner.load`."""
    _, metadata = load_genome_and_metadata(genome_path)
    return planner_profile(get_profile(profile_name), metadata, genome_path)


def genome_control_period(genome_path: str | Path, profile_name: str) -> float:
    """The control period (s) the genome in ``genome_path`` decides at on robot
    ``profile_name``: its metadata's ``control_period``, the robot's where absent. The same
    errors as :meth:`GenomePlanner.load`."""
    return genome_profile(genome_path, profile_name).control_period


def deployed_genome(
    genome_path: str | Path, profile_name: str, deployment: Deployment | None = None
) -> tuple[Genome, Deployed]:
    """The genome in ``genome_path`` and how it runs on robot ``profile_name`` as
    ``deployment`` (None: as trained, with the stages its metadata names). FileFormatError
    (corrupt or missing genome), ConfigError (unknown profile, a genome for another robot, a
    bad setting), each one line naming the file or key."""
    genome, metadata = load_genome_and_metadata(genome_path)
    profile = planner_profile(get_profile(profile_name), metadata, genome_path)
    trained = trained_stages(metadata, genome_path)
    return genome, deploy(profile, trained, deployment or Deployment(), genome_path)


class GenomePlanner:
    """One robot's decisions from an evolved genome, exactly as in training and in the
    benchmark: the decision chain of one robot
    (:class:`~mentor_core.controller.pipeline.DecisionChain`) through ``stages``.

    A planner with a context (``profile.n_context``), a recurrent network or a stage that
    remembers (a rotation shim: whether it has turned onto its goal yet; a collision guard:
    the last decisions' readings) is stateful, as in an episode of training, until
    :meth:`reset`. A collision guard counts only what was read as an obstacle unless
    ``arena`` (m) names the side of the simulated arena the robot drives in, whose border it
    then counts as known, as the batched episodes do.

    Raises ConfigError when the genome's inputs/outputs do not fit the profile.
    """

    def __init__(
        self, genome: Genome, profile: RobotProfile, source: str = "<genome>",
        arena: float | None = None, stages: tuple[Stage, ...] = (),
    ) -> None:  # fmt: skip
        fault = profile.network_mismatch(genome.n_inputs, genome.n_outputs)
        if fault:
            raise ConfigError(fault, path=source)
        self.genome = genome
        self.profile = profile
        self.network = FeedForwardNetwork.from_genome(genome)
        self.chain = DecisionChain(profile, stages, 1, arena)
        self._memory = self.network.new_memory(1)

    @property
    def stages(self) -> tuple[Stage, ...]:
        """The stages its decisions pass, in order."""
        return self.chain.stages

    def reset(self) -> None:
        """Start blank: the next decision reads the context of a first decision (a new goal or
        episode; :func:`mentor_core.sim.observation.initial_context`) and a zero memory, and
        every stage forgets (a rotation shim turns onto the goal again, a collision guard
        forgets what it read)."""
        self.chain.reset()
        self._memory = self.network.new_memory(1)

    @classmethod
    def load(
        cls, genome_path: str | Path, profile_name: str, deployment: Deployment | None = None,
        arena: float | None = None,
    ) -> GenomePlanner:  # fmt: skip
        """Planner of a genome JSON file for a named profile, run as ``deployment`` (None:
        as trained; :func:`deployed_genome`; its plan is the caller's to follow). The errors
        of :func:`deployed_genome`, and ConfigError for a genome that does not fit the
        profile."""
        genome, deployed = deployed_genome(genome_path, profile_name, deployment)
        return cls(genome, deployed.profile, str(genome_path), arena, deployed.stages)

    def decide(
        self, ranges: ArrayLike, pose: ArrayLike, goal: ArrayLike
    ) -> tuple[float, float]:
        """Decision ``(dtheta, ds)`` (rad, m) for readings (k,) (m, +inf out of range), pose
        (x, y, theta) and goal (x, y) in ``map``. ValueError for NaN or malformed input (the
        planner is then left as it was). Behind a collision guard ``ds`` may be negative (a
        step back)."""
        memory = self._memory.copy()  # kept as it was if the decision fails

        def policy(inputs: FloatArray, robots: NDArray[np.int64]) -> FloatArray:
            return self.network.activate(inputs, memory)

        decision = self.chain.decide(
            _ONE,
            np.asarray(ranges, dtype=np.float64).reshape(1, -1),
            np.asarray(pose, dtype=np.float64).reshape(1, 3),
            np.asarray(goal, dtype=np.float64).reshape(1, 2),
            policy,
        )
        self._memory = memory
        return float(decision.dtheta[0]), float(decision.ds[0])

    def command(
        self, ranges: ArrayLike, pose: ArrayLike, goal: ArrayLike, dt: float | None = None
    ) -> tuple[float, float]:
        """Twist of the decision, ``(linear_x, angular_z) = (ds / dt, dtheta / dt)`` (m/s,
        rad/s); ``dt`` defaults to the profile's control period."""
        dtheta, ds = self.decide(ranges, pose, goal)
        period = self.profile.control_period if dt is None else dt
        angular_z, linear_x = observation.twist_from_action(dtheta, ds, period)
        return float(linear_x), float(angular_z)


@dataclass(frozen=True)
class Observation:
    """What the planner answers: stamp (ns) of the scan, readings, pose and goal (None when
    no goal has been received); ``new_goal``: the first observation answered since a new goal
    or a ``started`` event (a planner with a memory starts blank on it); ``new_episode``:
    the first since a ``started`` event (a new episode, perhaps in another world)."""

    stamp_ns: int
    ranges: FloatArray
    pose: Pose
    goal: tuple[float, float] | None
    new_goal: bool = False
    new_episode: bool = False


class DecisionGate:
    """When the planner node decides, and when its data is stale (module docstring).

    Message stamps (sim time of the scan and odometry) decide which observation is new;
    node times (the node's steady clock when a message is handled) drive the watchdog, so the
    two time bases never mix.

    Args:
        stale_after: s (node time) without an answered observation after which the
            watchdog fires; larger than the control period.
        sync_tolerance: s, largest stamp difference of a scan and the odometry used with it.
    """

    def __init__(self, stale_after: float, sync_tolerance: float) -> None:
        if not (np.isfinite(stale_after) and stale_after > 0.0):
            raise ValueError(f"stale_after must be positive, got {stale_after}")
        if not (np.isfinite(sync_tolerance) and sync_tolerance >= 0.0):
            raise ValueError(f"sync_tolerance must be >= 0, got {sync_tolerance}")
        self.stale_after_ns = round(stale_after * _NS_PER_S)
        self.sync_tolerance_ns = round(sync_tolerance * _NS_PER_S)
        self._scan: tuple[int, FloatArray] | None = None
        self._odom: tuple[int, Pose] | None = None
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

    def on_scan(self, stamp_ns: int, ranges: ArrayLike) -> None:
        """The latest scan (readings checked by the caller), stamped ``stamp_ns``."""
        self._scan = (int(stamp_ns), np.asarray(ranges, dtype=np.float64).copy())

    def on_odometry(self, stamp_ns: int, pose: Pose) -> None:
        """The latest odometry pose, stamped ``stamp_ns``."""
        self._odom = (int(stamp_ns), (float(pose[0]), float(pose[1]), float(pose[2])))

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

    def arrived(self, pose: Pose, radius: float) -> bool:
        """The robot at ``pose`` stands within ``radius`` (m) of its goal; the goal is then
        dropped (nothing is answered until another comes)."""
        if self._goal is None:
            return False
        if np.hypot(pose[0] - self._goal[0], pose[1] - self._goal[1]) > radius:
            return False
        self._goal = None
        return True

    def on_event(
        self, kind: str, now_ns: int, goal: tuple[float, float] | None = None
    ) -> None:
        """An episode event of this robot, handled at node time ``now_ns``; a ``started``
        event may carry the episode's goal (x, y)."""
        if kind in _END_EVENTS:
            self._idle = True
            self._goal = None
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
        goal yet, scan and odometry not in step, or the episode has ended). Taking it marks
        it answered."""
        if self._idle or self._scan is None or self._odom is None or self._goal is None:
            return None
        scan_ns, ranges = self._scan
        odom_ns, pose = self._odom
        if abs(scan_ns - odom_ns) > self.sync_tolerance_ns:
            return None
        stamp = max(scan_ns, odom_ns)
        if stamp == self._answered_stamp and self._goal == self._answered_goal:
            return None
        self._answered_stamp = stamp
        self._answered_goal = self._goal
        self._answered_at = int(now_ns)
        new_goal, self._new_goal = self._new_goal, False
        new_episode, self._new_episode = self._new_episode, False
        return Observation(stamp, ranges.copy(), pose, self._goal, new_goal, new_episode)

    def watchdog(self, now_ns: int) -> str | None:
        """Why the planner should send a zero Twist at node time ``now_ns`` (one line), or None.

        Quiet while idle. Otherwise it fires when the last answer (or, before any, the first
        watchdog call or the last ``started`` event) lies more than ``stale_after`` back.
        """
        if self._since is None:
            self._since = int(now_ns)
        if self._idle:
            return None
        ref = self._answered_at if self._answered_at is not None else self._since
        age = now_ns - ref
        if age <= self.stale_after_ns:
            return None
        missing = [
            what
            for what, value in (
                ("scan", self._scan), ("odometry", self._odom), ("goal", self._goal)
            )
            if value is None
        ]
        if missing:
            return f"no {', '.join(missing)} received"
        assert self._scan is not None and self._odom is not None
        gap = abs(self._scan[0] - self._odom[0])
        if gap > self.sync_tolerance_ns:
            return f"scan and odometry stamps differ by {gap / _NS_PER_S:.3f} s"
        return f"no new scan and odometry for {age / _NS_PER_S:.3f} s"
