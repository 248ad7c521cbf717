"""How the simulator collects its robots' commands between two steps.

Lockstep (:class:`CommandBarrier`): after an observation every driving robot owes one
command; the simulator steps when all have answered. A command that arrives while no
observation waits for it (a late answer, a robot that is not driving) is refused, so it can
never be applied to a later observation. While answers are missing the observation is
repeated every ``resend_period`` s (planners answer a stamp once, so a repeat is harmless),
and with ``answer_timeout`` > 0 a robot that has not answered by then holds still: its
decision becomes ``(0, 0)``.

Real time (:class:`LatestCommands`): the simulator steps on a timer with each robot's latest
command since the last step; a robot without one holds still.

Continuous (:class:`HeldCommands`): physics steps at a fixed step; each robot keeps driving its
latest velocity command ``(v, omega)`` (m/s, rad/s) until another replaces it, or until it is
older than the command timeout (sim time), when the robot stops, as a ``diff_drive``
controller does.

Times are wall-clock seconds (any monotonic clock); decisions are ``(dtheta, ds)`` (rad, m).
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import Literal

Decision = tuple[float, float]
HOLD: Decision = (0.0, 0.0)
Poll = Literal["idle", "wait", "resend", "timeout"]


class CommandBarrier:
    """The lockstep barrier (module docstring).

    Args:
        resend_period: s between repeats of an unanswered observation (> 0).
        answer_timeout: s after which missing answers count as holding still; 0: never.
    """

    def __init__(self, resend_period: float, answer_timeout: float = 0.0) -> None:
        if not resend_period > 0.0:
            raise ValueError(f"resend_period must be positive, got {resend_period}")
        if not answer_timeout >= 0.0:
            raise ValueError(f"answer_timeout must be >= 0, got {answer_timeout}")
        self.resend_period = float(resend_period)
        self.answer_timeout = float(answer_timeout)
        self._waiting: set[str] = set()
        self._decisions: dict[str, Decision] = {}
        self._asked_at = 0.0
        self._sent_at = 0.0

    @property
    def waiting(self) -> tuple[str, ...]:
        """Robots that still owe an answer, sorted."""
        return tuple(sorted(self._waiting))

    @property
    def complete(self) -> bool:
        """Everyone asked has answered (and someone was asked)."""
        return not self._waiting and bool(self._decisions)

    def ask(self, robots: Iterable[str], now: float) -> None:
        """An observation went out to ``robots`` at ``now``; earlier answers are forgotten."""
        self._waiting = set(robots)
        self._decisions = {}
        self._asked_at = self._sent_at = float(now)

    def answer(self, robot: str, decision: Decision) -> bool:
        """Take ``robot``'s answer; False (refused) when no observation waits for it."""
        if robot not in self._waiting:
            return False
        self._waiting.discard(robot)
        self._decisions[robot] = (float(decision[0]), float(decision[1]))
        return True

    def drop(self, robot: str) -> None:
        """``robot`` owes no answer any more (its episode ended between two steps)."""
        self._waiting.discard(robot)

    def poll(self, now: float) -> Poll:
        """What to do at ``now``: ``idle`` (nothing asked or all answered), ``wait``,
        ``resend`` (repeat the observation to :attr:`waiting`; the repeat is noted) or
        ``timeout`` (the missing answers now hold still: :attr:`complete` becomes true)."""
        if not self._waiting:
            return "idle"
        if self.answer_timeout > 0.0 and now - self._asked_at > self.answer_timeout:
            for robot in self._waiting:
                self._decisions[robot] = HOLD
            self._waiting.clear()
            return "timeout"
        if now - self._sent_at >= self.resend_period:
            self._sent_at = float(now)
            return "resend"
        return "wait"

    def waited(self, now: float) -> float:
        """Seconds since the observation went out."""
        return float(now) - self._asked_at

    def take(self) -> dict[str, Decision]:
        """The decisions of the step (once :attr:`complete`); the barrier is then empty."""
        out, self._decisions, self._waiting = self._decisions, {}, set()
        return out

    def clear(self) -> None:
        """Forget everything (an episode ended or was reset)."""
        self._waiting.clear()
        self._decisions = {}


class LatestCommands:
    """Real time: each robot's latest decision since the last step (module docstring)."""

    def __init__(self) -> None:
        self._latest: dict[str, Decision] = {}

    def answer(self, robot: str, decision: Decision) -> None:
        """A command of ``robot``; a later one replaces it."""
        self._latest[robot] = (float(decision[0]), float(decision[1]))

    def missing(self, robots: Iterable[str]) -> list[str]:
        """The robots of ``robots`` that sent no command since the last step (in order)."""
        return [r for r in robots if r not in self._latest]

    def take(self, robots: Iterable[str]) -> tuple[dict[str, Decision], list[str]]:
        """Decisions of ``robots`` for this step and the robots that sent none (they hold
        still); everything else is forgotten."""
        robots = list(robots)
        missing = self.missing(robots)
        out = {r: self._latest.get(r, HOLD) for r in robots}
        self._latest.clear()
        return out, missing

    def clear(self) -> None:
        """Forget everything."""
        self._latest.clear()


#: a body velocity command ``(v, omega)``: m/s along the body's x, rad/s about z
Velocity = tuple[float, float]
STOP: Velocity = (0.0, 0.0)


class HeldCommands:
    """Continuous mode: each robot's latest velocity, held until replaced or timed out.

    Args:
        timeout_ns: sim ns after which a command no longer holds (the robot stops); 0: never.
    """

    def __init__(self, timeout_ns: int) -> None:
        if timeout_ns < 0:
            raise ValueError(f"command timeout must be >= 0, got {timeout_ns} ns")
        self.timeout_ns = int(timeout_ns)
        self._held: dict[str, tuple[Velocity, int]] = {}

    def answer(self, robot: str, velocity: Velocity, now_ns: int) -> None:
        """A command of ``robot`` received at sim time ``now_ns``; it replaces the last."""
        self._held[robot] = ((float(velocity[0]), float(velocity[1])), int(now_ns))

    def velocity(self, robot: str, now_ns: int) -> tuple[Velocity, bool]:
        """The velocity ``robot`` drives at ``now_ns`` and whether its command has just timed
        out (it then stops, and the command is forgotten). A robot never commanded stands."""
        held = self._held.get(robot)
        if held is None:
            return STOP, False
        velocity, since = held
        if self.timeout_ns and now_ns - since > self.timeout_ns:
            del self._held[robot]
            return STOP, velocity != STOP
        return velocity, False

    def clear(self) -> None:
        """Forget every command (an episode ended)."""
        self._held.clear()


class PublishSchedule:
    """Continuous mode: when the simulator publishes a scan (with odometry) and when
    odometry alone, every ``scan_ns`` and ``odom_ns`` sim ns, at the first step on or after
    each due time."""

    def __init__(self, scan_ns: int, odom_ns: int) -> None:
        if scan_ns <= 0 or odom_ns <= 0:
            raise ValueError(f"publish periods must be positive, got {scan_ns}, {odom_ns} ns")
        self.scan_ns, self.odom_ns = int(scan_ns), int(odom_ns)
        self._scan = self._odom = 0

    def restart(self, now_ns: int) -> None:
        """Both are due at ``now_ns`` (an episode starts)."""
        self._scan = self._odom = int(now_ns)

    def due(self, now_ns: int) -> Literal["scan", "odom", ""]:
        """What is due at ``now_ns`` (a scan carries odometry too); it is then counted done."""
        if now_ns >= self._scan:
            while self._scan <= now_ns:
                self._scan += self.scan_ns
            self._odom = now_ns + self.odom_ns
            return "scan"
        if now_ns >= self._odom:
            while self._odom <= now_ns:
                self._odom += self.odom_ns
            return "odom"
        return ""
