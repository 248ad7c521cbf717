"""A run of the simulator node: episodes one after another, stepping, events and bookkeeping.

:class:`SimSession` is everything the ROS simulator node (``mentor_sim_node``) decides; the
node only wires rclpy to it. It hands every robot its scenario per episode
(:class:`~mentor_core.runtime.scenario_plan.ScenarioPlan`), steps the
:class:`~mentor_core.runtime.simulator.ReferenceSimulator`, collects the robots' commands
(:mod:`mentor_core.runtime.lockstep`), keeps sim time, the episode counters and the
:class:`Outcome` of every robot episode, and records into an
:class:`~mentor_core.runtime.recording.EpisodeRecorder`. What it outputs (clock, goals,
events, observations, odometry, log lines) goes, in order, to a :class:`SessionPort`.

Sim time starts at 0 and advances one control period ``dt`` per step; the next episode starts
one period after the last one ended, so no stamp belongs to two episodes.

Driving: the node calls :meth:`SimSession.tick` from one wall timer (lockstep: every
``resend_period`` s; real time: every ``dt / real_time_factor`` s), hands every command to
:meth:`SimSession.command` (after :meth:`SimSession.accepts`) and calls
:meth:`SimSession.step` when a tick says a step is due (``timeout`` or ``step``).

* Lockstep (``real_time_factor`` 0): a pending episode starts at a tick; its first
  observation goes out at the next tick (so that planners have the goals and ``started``
  events first); the step follows as soon as every driving robot has answered, or after a
  ``timeout`` tick (``answer_timeout`` > 0) with the silent robots holding still; a
  ``resend`` tick asks the node to publish the unanswered observation again.
* Real time (``real_time_factor`` > 0): the first observation goes out with the start; each
  ``step`` tick steps with every robot's latest command (none: it holds still).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, Literal, NamedTuple, Protocol

from mentor_core.runtime.lockstep import HOLD, CommandBarrier, Decision, LatestCommands
from mentor_core.runtime.recording import EpisodeRecorder
from mentor_core.runtime.scenario_plan import ScenarioPlan, ScenarioSource
from mentor_core.runtime.simulator import (
    Event,
    EventKind,
    FloatArray,
    Pose,
    ReferenceSimulator,
    wire_ranges,
)
from mentor_core.sim.robots import RobotProfile
from mentor_core.sim.world import World

_NS_PER_S = 1_000_000_000
#: body twist ``(v, omega)`` of a robot's last applied decision (m/s, rad/s)
BodyTwist = tuple[float, float]
TickAction = Literal["idle", "start", "observe", "wait", "resend", "timeout", "step"]


class SessionPort(Protocol):
    """Where a :class:`SimSession`'s output goes, called in the order it happens."""

    def clock(self, time_ns: int) -> None:
        """Sim time changed (or an episode started)."""

    def goal(self, robot: str, goal: tuple[float, float], time_ns: int) -> None:
        """A robot's goal (x, y) in ``map`` for its new episode."""

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
        """A driving robot's readings (m, +inf beyond range, float64), pose and body twist."""

    def odometry(self, robot: str, pose: Pose, twist: BodyTwist, time_ns: int) -> None:
        """A robot whose episode just ended: where it stopped, at rest."""

    def info(self, text: str) -> None:
        """A log line."""

    def error(self, text: str) -> None:
        """A log line about something that went wrong (the session goes on)."""


@dataclass(frozen=True)
class SessionConfig:
    """What a session runs (the simulator node's parameters, see ``docs/ros.md``).

    Attributes:
        robots: ``(name, profile)`` of each robot, in order; all decide at one control period.
        first_scenario: offset of the first scenario handed out.
        time_limit: T_tot of every episode, s; None for the profiles' time budgets.
        episodes: episodes to run, then stop (and write the recording); 0: no limit.
        auto_advance: start the next scenario when an episode ends (else: :meth:`reset`).
        real_time_factor: 0: lockstep; r > 0: a step every ``dt / r`` wall s.
        answer_timeout: lockstep: wall s before a silent robot holds still; 0: wait.
        resend_period: lockstep: wall s between repeats of an unanswered observation.
        record: episode bag to write ('': none); robots of one profile.
        record_metadata: written with the recording's metadata.
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


class Outcome(NamedTuple):
    """How one robot's episode ended (:attr:`SimSession.outcomes`)."""

    episode: int
    robot: str
    event: str  # reached, collided or timed_out
    scenario: int
    steps: int  # decisions taken
    time_used: float  # s
    pose: tuple[float, float, float]  # where it stopped (x, y, theta)


class Tick(NamedTuple):
    """What a :meth:`SimSession.tick` did or asks for.

    ``action``: ``idle`` or ``wait`` (nothing to do), ``start`` (an episode started),
    ``observe`` (the first observation went out), ``resend`` (publish the observation of
    ``robots`` again; ``waited`` s since it first went out), ``timeout`` (``robots`` did not
    answer in time and hold still: call :meth:`SimSession.step`), ``step`` (real time: call
    :meth:`SimSession.step`; ``robots`` sent no command and hold still).
    """

    action: TickAction
    robots: tuple[str, ...] = ()
    waited: float = 0.0


class SimSession:
    """Episodes of the simulator node (see the module docstring).

    Args:
        source: world and scenarios.
        config: robots and run settings.
        port: receives the output.
        clock: wall clock (s, monotonic) for the lockstep resend and timeout.

    Raises what :class:`ScenarioPlan` raises (FileFormatError when a robot can run none of
    the scenarios), ValueError when the robots decide at different periods.
    """

    def __init__(
        self,
        source: ScenarioSource,
        config: SessionConfig,
        port: SessionPort,
        clock: Callable[[], float] = time.monotonic,
    ) -> None:
        self.config = config
        self._port = port
        self._clock = clock
        self.plan = ScenarioPlan(
            source, config.robots, first=config.first_scenario, time_limit=config.time_limit
        )
        for line in self.plan.skipped:
            port.error(f"{source.origin}: {line}")
        periods = {profile.control_period for _, profile in config.robots}
        if len(periods) != 1:
            raise ValueError(f"robots decide at different periods {sorted(periods)}")
        self.dt = periods.pop()
        self._dt_ns = round(self.dt * _NS_PER_S)
        self.world: World = source.world
        self._sim = ReferenceSimulator(self.world, self.dt)
        self._profiles = dict(config.robots)
        self._twist: dict[str, BodyTwist] = {name: HOLD for name, _ in config.robots}
        self._time_ns = 0
        self._episode = -1
        self._episodes_done = 0
        self._finished = False
        self._pending_start = True
        self._pending_observe = False
        self._barrier = CommandBarrier(config.resend_period, config.answer_timeout)
        self._latest = LatestCommands()
        self.recorder: EpisodeRecorder | None = None
        if config.record:
            names = [name for name, _ in config.robots]
            self.recorder = EpisodeRecorder(self.world, self.dt, names)
        self._saved = False
        #: every scenario skipped and every robot that could not start, one line each
        self.rejections: list[str] = list(self.plan.skipped)
        #: every robot episode that has ended, in order
        self.outcomes: list[Outcome] = []

    # ------------------------------------------------------------------ state

    @property
    def lockstep(self) -> bool:
        """Steps wait for the robots' answers (``real_time_factor`` 0)."""
        return self.config.real_time_factor == 0.0

    @property
    def finished(self) -> bool:
        """All ``episodes`` have run (never with ``episodes`` 0)."""
        return self._finished

    @property
    def episodes_done(self) -> int:
        """Episodes that have ended."""
        return self._episodes_done

    @property
    def episode(self) -> int:
        """Index of the current (or last) episode; -1 before the first."""
        return self._episode

    @property
    def time_ns(self) -> int:
        """Current simulation time, ns."""
        return self._time_ns

    @property
    def active(self) -> tuple[str, ...]:
        """The robots still driving in the current episode, sorted."""
        return self._sim.active

    # ------------------------------------------------------------------ driving

    def tick(self) -> Tick:
        """One timer tick (module docstring)."""
        if self._finished:
            return Tick("idle")
        if self._pending_start:
            self._start_episode()
            return Tick("start")
        if not self.lockstep:
            if self._sim.done:
                return Tick("idle")
            return Tick("step", tuple(self._latest.missing(self._sim.active)))
        if self._pending_observe:
            self._pending_observe = False
            self._observe()
            return Tick("observe")
        now = self._clock()
        late = self._barrier.waiting
        action = self._barrier.poll(now)
        return Tick(action, late, self._barrier.waited(now) if action == "resend" else 0.0)

    def accepts(self, robot: str) -> bool:
        """A command of ``robot`` counts now: it drives and (lockstep) an observation waits
        for its answer. Any other command is to be dropped."""
        return robot in self._sim.active and (
            not self.lockstep or robot in self._barrier.waiting
        )

    def command(self, robot: str, decision: Decision, received: BodyTwist | None = None) -> bool:
        """``robot``'s decision ``(dtheta, ds)`` for this period; lockstep steps at once when
        every driving robot has answered. ``received``: the command as it came
        ``(linear.x, angular.z)``, recorded; None for one refused as invalid (the robot then
        holds still: give :data:`~mentor_core.runtime.lockstep.HOLD`). False (nothing
        happens) when :meth:`accepts` says no."""
        if not self.accepts(robot):
            return False
        if received is not None and self.recorder is not None:
            self.recorder.command(robot, self._time_ns, float(received[0]), float(received[1]))
        if self.lockstep:
            self._barrier.answer(robot, decision)
            if self._barrier.complete:
                self._advance(self._barrier.take())
        else:
            self._latest.answer(robot, decision)
        return True

    def step(self) -> None:
        """Step every driving robot with the decisions collected (after a ``timeout`` or
        ``step`` tick); a robot without one holds still."""
        if self.lockstep:
            self._advance(self._barrier.take())
        else:
            self._advance(self._latest.take(self._sim.active)[0])

    def reset(self) -> tuple[bool, str]:
        """End the robots still driving (``timed_out``); the next episode starts at the next
        tick. Returns ``(success, message)``: no success once all episodes are done."""
        limit = self.config.episodes
        if self._finished:
            return False, f"all {limit} episodes are done"
        cut = list(self._sim.active)
        for name in cut:  # a reset ends the robots still driving: out of time
            self._event(name, "timed_out", self._sim.state(name).scenario)
        self._barrier.clear()
        self._latest.clear()
        if cut:
            self._final_odometry(cut)
            self._sim.start([])  # nothing drives until the next episode starts
            self._episodes_done += 1
            if limit and self._episodes_done >= limit:
                self.save_recording()
                self._finished = True
                return True, f"episode {self._episode} ended; all episodes are done"
        # started by the next tick, so that commands still in flight find nothing waiting
        # for them and are dropped
        self._pending_start = True
        return True, f"starting episode {self._episode + 1}"

    def save_recording(self) -> None:
        """Write the episode bag now (once; no ``record``: nothing). A failure is an error
        line, not an exception."""
        if self.recorder is None or self._saved:
            return
        self._saved = True
        path = self.config.record
        try:
            self.recorder.save(
                path, self.config.robots[0][1], self.config.record_metadata, overwrite=True
            )
        except (OSError, ValueError) as err:
            self._port.error(f"{path}: recording not written: {err}")
        else:
            self._port.info(f"recorded {self.recorder.n_episodes} episodes: {path}")

    # ------------------------------------------------------------------ episodes

    def _start_episode(self) -> None:
        self._pending_start = False
        self._latest.clear()
        if self._episode >= 0:
            self._time_ns += self._dt_ns  # one period between episodes: no stamp in two
        self._episode += 1
        setups = self.plan.setups(self._episode)
        events, rejected = self._sim.start(setups)
        for rej in rejected:
            line = f"episode {self._episode}: {rej.robot} cannot start scenario {rej.scenario}: "
            self._port.error(line + rej.reason)
            self.rejections.append(line + rej.reason)
        accepted = [s for s in setups if s.name in self._sim.robots]
        if self.recorder is not None:
            self.recorder.begin_episode(self._episode, self._time_ns, accepted)
        self._port.clock(self._time_ns)
        for s in accepted:
            self._twist[s.name] = HOLD
            self._port.goal(s.name, s.goal, self._time_ns)
            if self.recorder is not None:
                self.recorder.goal(s.name, self._time_ns, s.goal)
        self._events(events)
        self._port.info(
            f"episode {self._episode}: "
            + ", ".join(f"{s.name} scenario {s.scenario}" for s in accepted)
            if accepted
            else f"episode {self._episode}: no robot could start"
        )
        if self._sim.done:
            self._end_episode([s.name for s in accepted])
        elif not self.lockstep:
            self._observe()
        else:
            # lockstep: the first observation goes out at the next tick, one resend period
            # after the goals and started events, so that planners in other processes have
            # them first
            self._pending_observe = True

    def _end_episode(self, final: Sequence[str]) -> None:
        self._final_odometry(final)
        self._episodes_done += 1
        self._barrier.clear()
        limit = self.config.episodes
        if limit and self._episodes_done >= limit:
            self._port.info(f"all {limit} episodes done")
            self.save_recording()
            self._finished = True  # after the bag is written: callers may read it at once
        elif self.config.auto_advance:
            self._pending_start = True
        else:
            self._port.info("episode over; call ~/reset to start the next scenario")

    def _advance(self, decisions: Mapping[str, Decision]) -> None:
        """Step every driving robot by its decision; output what follows."""
        driving = self._sim.active
        for name in driving:
            dtheta, ds = decisions.get(name, HOLD)
            self._twist[name] = (ds / self.dt, dtheta / self.dt)
        events = self._sim.step({n: decisions.get(n, HOLD) for n in driving})
        self._time_ns += self._dt_ns
        self._port.clock(self._time_ns)
        self._events(events)
        ended = [e.robot for e in events]
        if self._sim.done:
            self._end_episode(ended)
        else:
            self._final_odometry(ended)
            self._observe()

    def _observe(self) -> None:
        """Output (and record) the readings and odometry of every driving robot; they now
        owe an answer."""
        for name in self._sim.active:
            ranges = self._sim.observe(name)
            pose = self._sim.pose(name)
            twist = self._twist[name]
            self._port.observation(name, ranges, pose, twist, self._time_ns)
            if self.recorder is not None:
                # the readings as the LaserScan carries them (float32, +inf beyond range)
                wired = wire_ranges(ranges, self._profiles[name])
                self.recorder.scan(name, self._time_ns, wired)
                self.recorder.odometry(name, self._time_ns, pose, twist)
        self._barrier.ask(self._sim.active, self._clock())

    def _final_odometry(self, names: Sequence[str]) -> None:
        """Odometry of robots whose episode just ended: where they stopped, at rest."""
        for name in names:
            self._twist[name] = HOLD
            pose = self._sim.pose(name)
            self._port.odometry(name, pose, HOLD, self._time_ns)
            if self.recorder is not None:
                self.recorder.odometry(name, self._time_ns, pose, HOLD)

    def _events(self, events: Sequence[Event]) -> None:
        for ev in events:
            self._event(ev.robot, ev.kind, ev.scenario)

    def _event(self, name: str, kind: EventKind, scenario: int) -> None:
        goal = self._sim.state(name).goal if kind == "started" else None
        self._port.event(name, kind, scenario, self._time_ns, goal)
        if self.recorder is not None:
            self.recorder.event(name, self._time_ns, kind, scenario)
        if kind != "started":
            state = self._sim.state(name)
            self.outcomes.append(
                Outcome(
                    self._episode, name, kind, scenario, state.steps, state.time_used, state.pose
                )
            )
            self._port.info(
                f"{name}: {kind} after {state.steps} decisions ({state.time_used:.2f} s), "
                f"scenario {scenario}"
            )
