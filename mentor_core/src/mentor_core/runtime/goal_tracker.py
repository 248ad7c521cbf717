"""One navigation goal from its acceptance to its end, as Nav2's goal and progress checkers
judge it.

A goal ends one of three ways (:class:`GoalTracker`, fed each pose the planner decides at):

* **reached**: the robot stands within ``radius`` of the goal's position and, for a goal with a
  heading (``yaw``, where ``yaw_tolerance`` is set), faces it within ``yaw_tolerance``. Between
  the two it turns in place (:meth:`GoalTracker.step` answers a turn rate) as Nav2's
  controllers do after the xy goal tolerance is met;
* **aborted, no progress**: Nav2's ``SimpleProgressChecker``: the robot must move
  ``movement_radius`` m from where it last made progress within ``movement_time`` s;
* **aborted, out of time**: the goal's time limit, ``time_limit`` s, or where it is 0 the
  budget of the goal's distance ``d`` at the robot's ``speed`` (the paper's time budget
  written for a goal of any length: :data:`TIME_FLOOR` + :data:`TIME_SLACK` ``d / speed``).

A goal the map says cannot be reached (it lies in an obstacle, or no path leads to it) is the
caller's to refuse or abort (:meth:`mentor_core.ScanGuidedPlanner.goal_fault`). Times are
seconds on any clock that does not jump (the node's steady clock).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from mentor_core.runtime.velocity_limits import VelocityLimits
from mentor_core.sim.robots import RobotProfile

#: s, the least time limit of a goal given none (room for turning to face it)
TIME_FLOOR = 30.0
#: how many times the straight drive's time a goal given no time limit may take
TIME_SLACK = 3.0
#: s, Nav2's SimpleProgressChecker movement_time_allowance
MOVEMENT_TIME = 10.0
#: rad/s, the turn rate of a yaw alignment where the robot sets none
ALIGN_TURN_RATE = 1.0

Pose = tuple[float, float, float]


@dataclass(frozen=True)
class GoalRules:
    """When a goal is reached and when it is given up (module docstring); m, s, rad.

    Attributes:
        radius: the xy goal tolerance.
        yaw_tolerance: the heading tolerance of a goal with a heading (0: headings ignored).
        movement_radius: the progress checker's required movement (0: no progress check).
        movement_time: the time allowed to move it.
        time_limit: a goal's time limit (0: from its distance, module docstring; inf: none).
        speed: m/s the default time limit assumes (the robot's rated or limited speed).
        turn_rate: rad/s of the turn in place that aligns the heading, at most.
        period: s a command stands for: the turn is slowed so as not to pass the heading.
    """

    radius: float
    yaw_tolerance: float = 0.0
    movement_radius: float = 0.0
    movement_time: float = MOVEMENT_TIME
    time_limit: float = 0.0
    speed: float = 1.0
    turn_rate: float = ALIGN_TURN_RATE
    period: float = 1.0

    def __post_init__(self) -> None:
        for name in ("radius", "speed", "turn_rate", "movement_time", "period"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0.0):
                raise ValueError(f"{name} must be a positive number, got {value}")
        for name in ("yaw_tolerance", "movement_radius"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value >= 0.0):
                raise ValueError(f"{name} must be a number >= 0 (0: off), got {value}")
        if not self.time_limit >= 0.0:
            raise ValueError(f"time_limit must be >= 0 s (0: from the distance, inf: none), "
                             f"got {self.time_limit}")
        if self.yaw_tolerance >= math.pi:
            raise ValueError(f"yaw_tolerance must be below pi rad, got {self.yaw_tolerance}")

    def limit_for(self, distance: float) -> float:
        """The time limit (s) of a goal ``distance`` m away."""
        if self.time_limit > 0.0:
            return self.time_limit
        return TIME_FLOOR + TIME_SLACK * distance / self.speed


def goal_rules(
    profile: RobotProfile, radius: float, limits: VelocityLimits, period: float, *,
    yaw_tolerance: float = 0.0, movement_radius: float = 0.0,
    movement_time: float = MOVEMENT_TIME, time_limit: float = 0.0,
) -> GoalRules:  # fmt: skip
    """A robot's :class:`GoalRules` from its node's settings, each 0 taking its default: the
    progress check's ``movement_radius`` half the goal ``radius`` (``movement_time`` 0: no
    progress check), the default time limit at the profile's rated speed or ``max_vel_x``
    where slower, the heading turned to at :data:`ALIGN_TURN_RATE` or ``max_vel_theta``
    where slower, a command standing for ``period`` s."""
    speed = profile.rated_speed
    if 0.0 < limits.max_vel_x < speed:
        speed = limits.max_vel_x
    turn = ALIGN_TURN_RATE
    if 0.0 < limits.max_vel_theta < turn:
        turn = limits.max_vel_theta
    movement = (movement_radius or radius / 2.0) if movement_time > 0.0 else 0.0
    return GoalRules(radius, yaw_tolerance, movement, movement_time or MOVEMENT_TIME,
                     time_limit, speed, turn, period)  # fmt: skip


@dataclass(frozen=True)
class GoalStep:
    """What a goal needs now: ``kind`` is ``drive`` (the planner decides), ``turn`` (turn in
    place at ``turn`` rad/s), ``reached`` or ``aborted`` (``reason`` says why); ``distance``:
    m from the robot to the goal's position."""

    kind: str
    distance: float
    turn: float = 0.0
    reason: str = ""


def _wrap(angle: float) -> float:
    return math.atan2(math.sin(angle), math.cos(angle))


class GoalTracker:
    """One goal (x, y) with an optional heading ``yaw`` (rad), accepted at ``now`` s with the
    robot at ``pose`` (module docstring)."""

    def __init__(self, rules: GoalRules, goal: tuple[float, float], yaw: float | None,
                 pose: Pose, now: float) -> None:  # fmt: skip
        if yaw is not None and not math.isfinite(yaw):
            raise ValueError(f"goal yaw must be finite, got {yaw}")
        self.rules = rules
        self.goal = (float(goal[0]), float(goal[1]))
        self.yaw = yaw if rules.yaw_tolerance > 0.0 else None
        self.started = float(now)
        self.limit = rules.limit_for(self._distance(pose))
        self._anchor = (float(pose[0]), float(pose[1]))
        self._anchor_time = float(now)

    def _distance(self, pose: Pose) -> float:
        return math.hypot(pose[0] - self.goal[0], pose[1] - self.goal[1])

    def step(self, pose: Pose, now: float) -> GoalStep:
        """The goal's state with the robot at ``pose`` at ``now`` s."""
        distance = self._distance(pose)
        if distance <= self.rules.radius:
            if self.yaw is None:
                return GoalStep("reached", distance)
            error = _wrap(self.yaw - pose[2])
            if abs(error) <= self.rules.yaw_tolerance:
                return GoalStep("reached", distance)
            if now - self.started <= self.limit:  # no progress check while turning in place
                self._anchor, self._anchor_time = (pose[0], pose[1]), now
                rate = min(self.rules.turn_rate, abs(error) / self.rules.period)
                return GoalStep("turn", distance, math.copysign(rate, error))
        if now - self.started > self.limit:  # inf: never
            return GoalStep("aborted", distance, reason=(
                f"out of time: {now - self.started:.1f} s past the goal's limit of "
                f"{self.limit:.1f} s"))  # fmt: skip
        need = self.rules.movement_radius
        if need > 0.0:
            if math.hypot(pose[0] - self._anchor[0], pose[1] - self._anchor[1]) >= need:
                self._anchor, self._anchor_time = (pose[0], pose[1]), now
            elif now - self._anchor_time > self.rules.movement_time:
                return GoalStep("aborted", distance, reason=(
                    f"no progress: moved less than {need:g} m in "
                    f"{self.rules.movement_time:g} s"))  # fmt: skip
        return GoalStep("drive", distance)


__all__ = ["ALIGN_TURN_RATE", "MOVEMENT_TIME", "TIME_FLOOR", "TIME_SLACK", "GoalRules",
           "GoalStep", "GoalTracker", "goal_rules"]  # fmt: skip
