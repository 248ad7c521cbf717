"""What a simulator session runs and what it tells its node: settings, output port, results.

:class:`SessionConfig` holds the simulator node's parameters (``docs/ros.md``),
:class:`ContinuousConfig` those of its continuous mode, :class:`SessionPort` is where a
:class:`~mentor_core.runtime.sim_session.SimSession`'s output goes, :class:`Outcome` how a
robot's episode ended and :class:`Tick` what a timer tick did or asks for.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any, Literal, NamedTuple, Protocol

from mentor_core.runtime.simulator import EventKind, FloatArray, Pose
from mentor_core.runtime.wiring import Wiring
from mentor_core.sim.robots import RobotProfile

#: body twist ``(v, omega)`` of a robot (m/s, rad/s)
BodyTwist = tuple[float, float]
TickAction = Literal["idle", "start", "observe", "wait", "resend", "timeout", "step"]
_NS_PER_S = 1_000_000_000


class SessionPort(Protocol):
    """Where a session's output goes, called in the order it happens. Poses are in ``odom``
    (the session's ``map_to_odom`` applied), goals in ``map``."""

    def clock(self, time_ns: int) -> None:
        """Sim time changed (or an episode started)."""

    def goal(self, robot: str, goal: tuple[float, float], time_ns: int) -> None:
        """A robot's goal (x, y) in ``map``: its new episode's, or one it was given."""

    def event(
        self,
        robot: str,
        kind: EventKind,
        scenario: int,
        time_ns: int,
        goal: tuple[float, float] | None,
    ) -> None:
        """An episode event; ``goal`` is given with ``started`` only."""

    def observation(
        self, robot: str, ranges: FloatArray, pose: Pose, twist: BodyTwist, time_ns: int
    ) -> None:
        """A robot's readings (m, +inf beyond range, float64), pose and body twist."""

    def lidar(self, robot: str, ranges: FloatArray, time_ns: int) -> None:
        """A robot's lidar scan (m, REP-117 coded), just before its observation (only with a
        lidar configured)."""

    def odometry(self, robot: str, pose: Pose, twist: BodyTwist, time_ns: int) -> None:
        """A robot's pose without readings (its episode ended, or it waits for a goal)."""

    def info(self, text: str) -> None:
        """A log line."""

    def warning(self, text: str) -> None:
        """A log line about input that was refused or a command that ran out."""

    def error(self, text: str) -> None:
        """A log line about something that went wrong (the session goes on)."""


@dataclass(frozen=True)
class ContinuousConfig:
    """The continuous mode (like Gazebo or Stage): physics every ``physics_step`` sim s with
    each robot's held velocity command, scans every ``scan_period`` and odometry every
    ``odom_period`` sim s; a command older than ``command_timeout`` sim s stops the robot
    (0: never). ValueError for a value that is not positive (the timeout: negative)."""

    physics_step: float = 0.05
    scan_period: float = 0.1
    odom_period: float = 0.05
    command_timeout: float = 0.5

    def __post_init__(self) -> None:
        for key in ("physics_step", "scan_period", "odom_period"):
            value = getattr(self, key)
            if not (math.isfinite(value) and value > 0.0):
                raise ValueError(f"{key}: must be a positive number of s, got {value}")
        if not (math.isfinite(self.command_timeout) and self.command_timeout >= 0.0):
            raise ValueError(f"command_timeout: must be >= 0 s, got {self.command_timeout}")

    def ns(self, key: str) -> int:
        """One of the periods, in ns."""
        return round(float(getattr(self, key)) * _NS_PER_S)


@dataclass(frozen=True)
class SessionConfig:
    """What a session runs (the simulator node's parameters, see ``docs/ros.md``).

    Attributes:
        robots: ``(name, profile)`` of each robot, in order; all decide at one control period.
        first_scenario: offset of the first scenario handed out.
        time_limit: T_tot of every episode, s; None for the profiles' time budgets.
        episodes: episodes to run, then stop (and write the recording); 0: no limit.
        auto_advance: start the next scenario when an episode ends (else: ``reset``).
        real_time_factor: 0: lockstep; r > 0: a step every ``dt / r`` wall s (or, continuous,
            every ``physics_step / r``).
        answer_timeout: lockstep: wall s before a silent robot holds still; 0: wait.
        resend_period: lockstep: wall s between repeats of an unanswered observation.
        record: episode bag to write ('': none); robots of one profile.
        record_metadata: written with the recording's metadata.
        wiring: the robots' lidar (and its noise seed) and the pose of ``odom`` in ``map``.
        wait_for_goals: each episode's robots wait at their starts for a goal given them on a
            goal topic (the scenario's goal is not used).
        continuous: the continuous mode's settings (None: decisions of one control period).
        goal_radius: m, for every robot (None: each profile's).
    """

    robots: tuple[tuple[str, RobotProfile], ...]
    first_scenario: int = 0
    time_limit: float | None = None
    episodes: int = 0
    auto_advance: bool = True
    real_time_factor: float = 0.0
    answer_timeout: float = 0.0
    resend_period: float = 0.1
    record: str = ""
    record_metadata: Mapping[str, Any] = field(default_factory=dict)
    wiring: Wiring = field(default_factory=Wiring)
    wait_for_goals: bool = False
    continuous: ContinuousConfig | None = None
    goal_radius: float | None = None


class Outcome(NamedTuple):
    """How one robot's episode ended (:attr:`SimSession.outcomes`)."""

    episode: int
    robot: str
    event: str  # reached, collided or timed_out
    scenario: int
    steps: int  # decisions taken (continuous mode: physics steps)
    time_used: float  # s
    pose: tuple[float, float, float]  # where it stopped (x, y, theta) in map


class Tick(NamedTuple):
    """What a :meth:`SimSession.tick` did or asks for.

    ``action``: ``idle`` or ``wait`` (nothing to do), ``start`` (an episode started),
    ``observe`` (the first observation went out), ``resend`` (publish the observation of
    ``robots`` again; ``waited`` s since it first went out), ``timeout`` (``robots`` did not
    answer in time and hold still: call :meth:`SimSession.step`), ``step`` (real time or
    continuous: call :meth:`SimSession.step`; ``robots`` sent no command and hold still).
    """

    action: TickAction
    robots: tuple[str, ...] = ()
    waited: float = 0.0
