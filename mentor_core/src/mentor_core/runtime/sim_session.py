"""A run of the simulator node: episodes one after another, stepping, goals, events, bookkeeping.

:class:`SimSession` is everything the ROS simulator node decides; the node only wires rclpy to
it. It hands every robot its scenario per episode (:class:`ScenarioPlan`), steps the
:class:`~mentor_core.runtime.simulator.ReferenceSimulator`, collects the robots' commands
(:mod:`mentor_core.runtime.lockstep`), takes the goals users give the robots
(:mod:`mentor_core.runtime.goal_intake`), keeps sim time (from 0; the next episode starts one
step after the last one ended, so no stamp belongs to two episodes), the episode counters and
every robot's :class:`Outcome`, and records. Its output goes, in order, to a
:class:`SessionPort` (:mod:`mentor_core.runtime.session_output`): poses in ``odom``, goals in
``map``.

Driving: the node calls :meth:`SimSession.tick` from one wall timer, hands commands to
:meth:`SimSession.command` (after :meth:`SimSession.accepts`) and calls
:meth:`SimSession.step` when a tick says ``timeout`` or ``step``. Lockstep
(``real_time_factor`` 0): an episode starts at a tick, its first observation goes out at the
next (planners have the goals and ``started`` events first), the step (one control period)
follows once every driving robot has answered, or at a ``timeout`` tick; a ``resend`` tick asks
for the unanswered observation again. Real time (``real_time_factor`` > 0): each ``step`` tick
steps one control period with every robot's latest command. Continuous
(:class:`ContinuousConfig`): each ``step`` tick is one physics step with every robot's held
velocity; scans and odometry at their own periods. Goals (:meth:`SimSession.give_goal`): see
:mod:`mentor_core.runtime.goal_intake` and ``docs/ros.md``.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Mapping, Sequence

from mentor_core.runtime.goal_intake import goal_in_map, same_goal, session_frames
from mentor_core.runtime.lockstep import (
    HOLD,
    CommandBarrier,
    Decision,
    HeldCommands,
    LatestCommands,
    PublishSchedule,
)
from mentor_core.runtime.recording import EpisodeRecorder
from mentor_core.runtime.scenario_plan import ScenarioPlan, ScenarioSource
from mentor_core.runtime.session_config import (
    BodyTwist,
    ContinuousConfig,
    Outcome,
    SessionConfig,
    SessionPort,
    Tick,
)
from mentor_core.runtime.session_output import SessionOutput, session_recorder
from mentor_core.runtime.simulator import Event, EventKind, ReferenceSimulator, RobotSetup
from mentor_core.sim.transforms import FrameTree
from mentor_core.sim.world import World

__all__ = ["BodyTwist", "ContinuousConfig", "Outcome", "SessionConfig", "SessionPort",
           "SimSession", "Tick"]  # fmt: skip  (the types live in session_config)

_NS_PER_S = 1_000_000_000


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
        cont = config.continuous
        self._step_ns = round((cont.physics_step if cont else self.dt) * _NS_PER_S)
        self.world: World = source.world
        self._sim = ReferenceSimulator(self.world, self.dt, self._step_ns / _NS_PER_S)
        self._sim.goal_radius = config.goal_radius
        self._profiles = dict(config.robots)
        self._wiring = config.wiring
        self._rngs = {name: self._wiring.generator(i) for i, (name, _) in enumerate(config.robots)}
        self._twist: dict[str, BodyTwist] = {name: HOLD for name, _ in config.robots}
        self._time_ns = 0
        self._episode = -1
        self._episodes_done = 0
        self._finished = False
        self._pending_start = True
        self._pending_observe = False
        self._barrier = CommandBarrier(config.resend_period, config.answer_timeout)
        self._latest = LatestCommands()
        self._held = HeldCommands(cont.ns("command_timeout") if cont else 0)
        self._schedule = PublishSchedule(
            cont.ns("scan_period") if cont else self._step_ns,
            cont.ns("odom_period") if cont else self._step_ns,
        )
        #: goals given to robots that wait for one, taken at the next step boundary
        self._pending_goals: dict[str, tuple[float, float]] = {}
        self.recorder: EpisodeRecorder | None = session_recorder(config, self.world, self.dt)
        self._out = SessionOutput(port, self.recorder, self._wiring, self._profiles)
        self._saved = False
        #: every scenario skipped and every robot that could not start, one line each
        self.rejections: list[str] = list(self.plan.skipped)
        #: every robot episode that has ended, in order
        self.outcomes: list[Outcome] = []

    # ------------------------------------------------------------------ state

    @property
    def lockstep(self) -> bool:
        """Steps wait for the robots' answers (``real_time_factor`` 0, not continuous)."""
        return self.config.real_time_factor == 0.0 and self.config.continuous is None

    @property
    def continuous(self) -> bool:
        """Physics steps at a fixed step with held velocity commands."""
        return self.config.continuous is not None

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

    @property
    def goal_radius(self) -> float | None:
        """The goal radius of every robot, m (None: each profile's)."""
        return self._sim.goal_radius

    @goal_radius.setter
    def goal_radius(self, radius: float | None) -> None:
        if radius is not None and not radius > 0.0:
            raise ValueError(f"goal radius must be positive, got {radius}")
        self._sim.goal_radius = radius

    def frames(self) -> FrameTree:
        """The frames now (:func:`~mentor_core.runtime.goal_intake.session_frames`)."""
        return session_frames(self._sim, self._wiring)

    # ------------------------------------------------------------------ driving

    def tick(self) -> Tick:
        """One timer tick (module docstring)."""
        if self._finished:
            return Tick("idle")
        if self._pending_start:
            self._start_episode()
            return Tick("start")
        if self.continuous:
            return Tick("idle" if self._episode_over() else "step")
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
        ``(linear.x, angular.z)``, recorded (continuous: the velocity held); None for one
        refused as invalid (the robot then holds still: give
        :data:`~mentor_core.runtime.lockstep.HOLD`). False (nothing happens) when
        :meth:`accepts` says no."""
        if not self.accepts(robot):
            return False
        if received is not None:
            self._out.command(robot, self._time_ns, received)
        if self.continuous:
            velocity = HOLD if received is None else (float(received[0]), float(received[1]))
            self._held.answer(robot, velocity, self._time_ns)
        elif self.lockstep:
            self._barrier.answer(robot, decision)
            if self._barrier.complete:
                self._advance(self._barrier.take())
        else:
            self._latest.answer(robot, decision)
        return True

    def step(self) -> None:
        """Step every driving robot with the decisions collected (after a ``timeout`` or
        ``step`` tick); a robot without one holds still. Continuous: one physics step."""
        if self.continuous:
            self._drive()
        elif self.lockstep:
            self._advance(self._barrier.take())
        else:
            self._advance(self._latest.take(self._sim.active)[0])

    def give_goal(
        self, robots: Sequence[str], frame: str, xy: Sequence[float]
    ) -> tuple[float, float] | None:
        """A goal ``xy`` (m) in ``frame`` for ``robots`` (module docstring); returns it in
        ``map``, or None when it was refused (a warning says why)."""
        goal, why = goal_in_map(self.frames(), frame, xy, self.world.size)
        if goal is None:
            self._port.warning(why)
            return None
        for name in robots:
            if name not in self._profiles:
                continue
            if name in self._sim.active:
                if not same_goal(self._sim.state(name).goal, goal):
                    self._change_goal(name, goal)
            else:
                self._pending_goals[name] = goal
                if name in self._sim.waiting and self._at_boundary():
                    if self.lockstep:
                        self._pending_observe = True
                    else:
                        self._activate_pending()
        return goal

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
        self._held.clear()
        if cut or self._sim.waiting:
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
        if not self._saved:
            self._saved = True
            cfg = self.config
            self._out.save(cfg.record, cfg.robots[0][1], cfg.record_metadata)

    # ------------------------------------------------------------------ episodes

    def _start_episode(self) -> None:
        self._pending_start = False
        self._latest.clear()
        self._held.clear()
        if self._episode >= 0:
            self._time_ns += self._step_ns  # one step between episodes: no stamp in two
        self._episode += 1
        wait = self.config.wait_for_goals
        if not wait:
            self._pending_goals.clear()
        setups = self.plan.setups(self._episode)
        events, rejected = self._sim.start(setups, wait_for_goals=wait)
        for rej in rejected:
            line = f"episode {self._episode}: {rej.robot} cannot start scenario {rej.scenario}: "
            self._port.error(line + rej.reason)
            self.rejections.append(line + rej.reason)
        accepted = [s for s in setups if s.name in self._sim.robots]
        if self.recorder is not None:
            self.recorder.begin_episode(self._episode, self._time_ns, [] if wait else accepted)
        self._out.clock(self._time_ns)
        for s in [] if wait else accepted:
            self._twist[s.name] = HOLD
            self._out.goal(s.name, s.goal, self._time_ns, record=True)
        self._events(events)
        self._port.info(
            f"episode {self._episode}: "
            + ", ".join(f"{s.name} scenario {s.scenario}" for s in accepted)
            + (" (waiting for goals)" if wait else "")
            if accepted
            else f"episode {self._episode}: no robot could start"
        )
        self._schedule.restart(self._time_ns)
        if self._episode_over():
            self._end_episode([s.name for s in accepted])
        elif self.continuous:
            self._activate_pending()
            self._publish()
        elif not self.lockstep:
            self._observe()
        else:
            # lockstep: the first observation goes out at the next tick, one resend period
            # after the goals and started events, so that planners in other processes have
            # them first
            self._pending_observe = True

    def _episode_over(self) -> bool:
        return self._sim.done and not self._sim.waiting

    def _end_episode(self, final: Sequence[str]) -> None:
        self._final_odometry(final)
        self._episodes_done += 1
        self._barrier.clear()
        self._held.clear()
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
        self._after_step(events)
        if not self._episode_over():
            self._observe()

    def _drive(self) -> None:
        """Continuous: one physics step of every driving robot at its held velocity."""
        if self._activate_pending():
            return
        h = self._step_ns / _NS_PER_S
        decisions = {}
        for name in self._sim.active:
            (v, omega), expired = self._held.velocity(name, self._time_ns)
            if expired:
                self._port.warning(f"{name}: no cmd_vel for the command timeout; stopping")
            self._twist[name] = (v, omega)
            decisions[name] = (omega * h, v * h)
        self._after_step(self._sim.step(decisions))
        if not self._episode_over():
            self._publish()

    def _after_step(self, events: Sequence[Event]) -> None:
        self._time_ns += self._step_ns
        self._out.clock(self._time_ns)
        self._events(events)
        ended = [e.robot for e in events]
        if self._episode_over():
            self._end_episode(ended)
        else:
            self._final_odometry(ended)

    def _publish(self) -> None:
        """Continuous: the observations, or the odometry alone, due now."""
        due = self._schedule.due(self._time_ns)
        if due == "scan":
            self._observe(waiting_too=True)
        elif due == "odom":
            for name in (*self._sim.active, *self._sim.waiting):
                self._out.odometry(name, self._sim.pose(name), self._twist[name], self._time_ns)

    def _at_boundary(self) -> bool:
        """Nothing is in flight: no lockstep observation waits for answers."""
        return not self.lockstep or not self._barrier.waiting

    def _activate_pending(self) -> bool:
        """Robots waiting for a goal that was given them start with it; True when that ended
        the episode (every robot had reached its goal at once)."""
        for name in sorted(self._pending_goals):
            if name not in self._sim.waiting:
                continue
            goal = self._pending_goals.pop(name)
            events = self._sim.set_goal(name, goal)
            state = self._sim.state(name)
            self._twist[name] = HOLD
            setup = RobotSetup(
                name, self._profiles[name], state.pose, goal, state.scenario, state.time_budget
            )
            self._out.joined(setup, self._time_ns)
            self._events(events)
            if self._episode_over():
                self._end_episode([e.robot for e in events if e.kind != "started"])
                return True
        return False

    def _change_goal(self, name: str, goal: tuple[float, float]) -> None:
        """A driving robot takes a new goal now."""
        before = self._sim.state(name)
        events = self._sim.set_goal(name, goal)
        state = self._sim.state(name)
        budget = state.time_budget - before.time_used
        self._out.goal_changed(name, goal, budget, state.steps, self._time_ns)
        if events:  # reached at once: it owes no answer any more
            self._events(events)
            self._barrier.drop(name)
            if self._episode_over():
                self._end_episode([name])
            else:
                self._final_odometry([name])
                if self.lockstep and self._barrier.complete:
                    self._advance(self._barrier.take())

    def _observe(self, waiting_too: bool = False) -> None:
        """Output (and record) the readings and odometry of every driving robot (and, with
        ``waiting_too``, of every waiting one; else their odometry); the drivers now owe an
        answer."""
        if not waiting_too and self._activate_pending():
            return
        lidar = self._wiring.lidar is not None
        for name in self._sim.active + (self._sim.waiting if waiting_too else ()):
            scan = self._sim.scan(name, self._wiring, self._rngs[name]) if lidar else None
            self._out.observation(
                name, self._sim.observe(name), self._sim.pose(name), self._twist[name],
                self._time_ns, scan,
            )  # fmt: skip
        if not waiting_too:  # shown, not recorded: its episode starts at the same stamp
            for name in self._sim.waiting:
                self._out.odometry(name, self._sim.pose(name), HOLD, self._time_ns, False)
        self._barrier.ask(self._sim.active, self._clock())

    def _final_odometry(self, names: Sequence[str]) -> None:
        """Odometry of robots whose episode just ended: where they stopped, at rest."""
        for name in names:
            self._twist[name] = HOLD
            self._out.odometry(name, self._sim.pose(name), HOLD, self._time_ns)

    def _events(self, events: Sequence[Event]) -> None:
        for ev in events:
            self._event(ev.robot, ev.kind, ev.scenario)

    def _event(self, name: str, kind: EventKind, scenario: int) -> None:
        goal = self._sim.state(name).goal if kind == "started" else None
        self._out.event(name, kind, scenario, self._time_ns, goal)
        if kind != "started":
            state = self._sim.state(name)
            self.outcomes.append(
                Outcome(
                    self._episode, name, kind, scenario, state.steps, state.time_used, state.pose
                )
            )
            self._port.info(
                f"{name}: {kind} after {state.steps} "
                f"{'physics steps' if self.continuous else 'decisions'} "
                f"({state.time_used:.2f} s), "
                f"scenario {scenario}"
            )
