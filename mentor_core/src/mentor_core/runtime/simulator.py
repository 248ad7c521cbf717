"""The reference simulator: robots of any profiles in one world, one decision per control period.

The ROS simulator node (``mentor_sim_node``) only converts messages around this module; the
end-to-end and bag regression tests re-run its episodes in-process with
:func:`run_reference_episode`. Physics is :class:`mentor_core.sim.pymunk_world.PymunkWorld`: a
fresh space per episode, robots placed (never stepped), so an episode depends only on its
scenario and its decisions.

An episode gives each robot a start pose, a goal and a time budget ``T_tot`` (default
:meth:`RobotProfile.time_budget`, the paper's T_tot,i) and follows
:func:`mentor_core.controller.episodes.run_episodes` robot by robot:

* start: robots are placed in the order given; a robot whose body at its start overlaps an
  obstacle, a wall or a robot placed before it is *rejected* (it takes no part in the
  episode). A robot already within its goal radius has reached the goal (no decision); one
  with no decision allowed has timed out. Every placed robot gets a ``started`` event first.
* step: every active robot, in name order, drives its decision ``(dtheta, ds)`` along the arc
  (:meth:`PymunkWorld.drive`); robots driven earlier in the step are already at their new
  poses. A robot stops for good on ``reached`` or ``collided``, or ``timed_out`` when it has
  used its ``ceil(T_tot / dt)`` decisions. Finished robots stay in the world as obstacles.
* time: a decision takes one control period ``dt``, except the arriving one, which takes the
  share of the period spent up to the arriving sample (as in ``run_episodes``). A simulator
  stepping physics finer than ``dt`` (``step_period``, the node's continuous mode) counts its
  steps and time per physics step instead, and a robot times out when its time is used.
* goals: :meth:`ReferenceSimulator.set_goal` gives a robot a new goal, whoever set it, and a
  time budget for it from where the robot stands; a robot started with ``wait_for_goals`` is
  placed (an obstacle to the others) but waits, without a ``started`` event, until its first
  goal. ``goal_radius``, when set, replaces the profiles' goal radius.

What a robot's planner receives through ROS is :func:`wire_ranges` (a LaserScan carries
float32 ranges) and :func:`wire_pose` (the heading travels as a quaternion), and what the
simulator applies is :func:`wire_decision` (a decision travels as a Twist, a rate over dt);
the reference episode does the same, so an episode through ROS equals it bit for bit.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from mentor_core.runtime.wiring import Wiring
from mentor_core.runtime.wiring import wire_decision as wire_decision  # re-exported
from mentor_core.runtime.wiring import wire_pose as wire_pose
from mentor_core.runtime.wiring import wire_ranges as wire_ranges
from mentor_core.sim.pymunk_world import PymunkWorld
from mentor_core.sim.robots import RobotProfile
from mentor_core.sim.scenarios import start_overlap
from mentor_core.sim.world import World

FloatArray = NDArray[np.float64]
Pose = tuple[float, float, float]
EndKind = Literal["reached", "collided", "timed_out"]
EventKind = Literal["started", "reached", "collided", "timed_out"]
Status = Literal["waiting", "active", "reached", "collided", "timed_out"]
#: ``decide(ranges (k,), pose (x, y, theta), goal (x, y)) -> (dtheta, ds)`` (rad, m)
Decide = Callable[[FloatArray, Pose, tuple[float, float]], tuple[float, float]]


@dataclass(frozen=True)
class RobotSetup:
    """One robot's part in an episode.

    Attributes:
        name: the robot's name (its ROS namespace), unique in the episode.
        profile: body, sensors, action limits and goal radius.
        start: start pose (x, y, theta) in ``map`` (m, m, rad).
        goal: goal (x, y) in ``map``, m.
        scenario: index of the scenario it comes from (-1: none), reported in its events.
        time_budget: T_tot in s; None for :meth:`RobotProfile.time_budget`.
    """

    name: str
    profile: RobotProfile
    start: Pose
    goal: tuple[float, float]
    scenario: int = -1
    time_budget: float | None = None


@dataclass(frozen=True)
class Event:
    """An episode event of one robot."""

    robot: str
    kind: EventKind
    scenario: int


@dataclass(frozen=True)
class Rejection:
    """A robot that could not take part in an episode, and why (one line)."""

    robot: str
    scenario: int
    reason: str


@dataclass(frozen=True)
class RobotState:
    """Where one robot of the episode stands.

    Attributes:
        status: ``active`` or how its episode ended.
        steps: decisions taken; allowed: decisions its time budget allows.
        time_used: s (fractional on the arriving decision); time_budget: T_tot, s.
        pose: current pose (x, y, theta); goal: (x, y); scenario: its scenario index.
    """

    status: Status
    steps: int
    allowed: int
    time_used: float
    time_budget: float
    pose: Pose
    goal: tuple[float, float]
    scenario: int


def decision_limit(time_budget: float, control_period: float) -> int:
    """Decisions a time budget allows: ``ceil(T_tot / dt)`` (as ``run_episodes``)."""
    if not (math.isfinite(time_budget) and time_budget >= 0.0):
        raise ValueError(f"time budget must be finite and >= 0, got {time_budget}")
    return math.ceil(time_budget / control_period)


def scenario_for(episode: int, robot: int, n_robots: int, n_scenarios: int, first: int = 0) -> int:
    """Scenario index of robot number ``robot`` in episode ``episode`` (all 0-based).

    Episode ``e`` gives robot ``j`` scenario ``(first + e * n_robots + j) mod n_scenarios``:
    one robot walks through the scenarios in order, several robots take consecutive ones.
    """
    if n_scenarios < 1 or n_robots < 1:
        raise ValueError("need at least one scenario and one robot")
    return (first + episode * n_robots + robot) % n_scenarios


class ReferenceSimulator:
    """Episodes of several robots in one :class:`World` (see the module docstring).

    Args:
        world: arena and obstacles.
        control_period: dt, s; every robot of an episode decides once per dt.
        step_period: s of one :meth:`step` (default: dt); smaller for continuous driving.
    """

    def __init__(
        self, world: World, control_period: float, step_period: float | None = None
    ) -> None:
        if not (math.isfinite(control_period) and control_period > 0.0):
            raise ValueError(f"control period must be positive, got {control_period}")
        step = control_period if step_period is None else step_period
        if not (math.isfinite(step) and step > 0.0):
            raise ValueError(f"step period must be positive, got {step_period}")
        self.world = world
        self.control_period = float(control_period)
        self.step_period = float(step)
        #: goal radius of every robot, m (None: each profile's)
        self.goal_radius: float | None = None
        self._physics: PymunkWorld | None = None
        self._setups: dict[str, RobotSetup] = {}
        self._status: dict[str, Status] = {}
        self._steps: dict[str, int] = {}
        self._allowed: dict[str, int] = {}
        self._budget: dict[str, float] = {}
        self._time: dict[str, float] = {}

    @property
    def robots(self) -> tuple[str, ...]:
        """The robots of the current episode (rejected ones excluded), sorted."""
        return tuple(sorted(self._setups))

    @property
    def active(self) -> tuple[str, ...]:
        """The robots still driving, sorted."""
        return tuple(n for n in self.robots if self._status[n] == "active")

    @property
    def done(self) -> bool:
        """No robot is driving (also before the first episode)."""
        return not self.active

    @property
    def waiting(self) -> tuple[str, ...]:
        """The robots placed but waiting for a goal, sorted."""
        return tuple(n for n in self.robots if self._status[n] == "waiting")

    def radius(self, name: str) -> float:
        """Goal radius of a robot, m."""
        return self.profile(name).goal_radius if self.goal_radius is None else self.goal_radius

    def start(
        self, setups: Sequence[RobotSetup], wait_for_goals: bool = False
    ) -> tuple[list[Event], list[Rejection]]:
        """Begin a new episode (a fresh physics space); returns its first events and the
        rejected robots. With ``wait_for_goals`` the robots are placed waiting for a goal
        (:meth:`set_goal`; their setups' goals are not used). ValueError for duplicate names
        or another control period."""
        names = [s.name for s in setups]
        if len(set(names)) != len(names):
            raise ValueError(f"robot names must be unique, got {names}")
        for s in setups:
            if s.profile.control_period != self.control_period:
                raise ValueError(
                    f"robot {s.name!r}: profile {s.profile.name!r} decides every "
                    f"{s.profile.control_period} s, the simulator every {self.control_period} s"
                )
        for d in (self._setups, self._status, self._steps, self._allowed, self._budget):
            d.clear()
        self._time.clear()
        self._physics = None
        events: list[Event] = []
        rejected: list[Rejection] = []
        if not setups:
            return events, rejected
        physics = PymunkWorld(self.world, setups[0].profile)
        self._physics = physics
        for s in setups:
            fault = _start_fault(physics, s)
            if fault:
                rejected.append(Rejection(s.name, s.scenario, fault))
                continue
            physics.add_robot(s.name, s.start, s.profile)
            budget = (
                s.profile.time_budget(s.start[:2], s.goal)
                if s.time_budget is None
                else float(s.time_budget)
            )
            self._setups[s.name] = s
            self._budget[s.name] = budget
            self._allowed[s.name] = decision_limit(budget, self.step_period)
            self._steps[s.name] = 0
            self._time[s.name] = 0.0
            self._status[s.name] = "waiting" if wait_for_goals else "active"
            if not wait_for_goals:
                events.append(Event(s.name, "started", s.scenario))
        for name in self.active:  # already there, or no decision allowed (as run_episodes)
            events.extend(self._end_at_start(name))
        return events, rejected

    def _end_at_start(self, name: str) -> list[Event]:
        """End event of a robot that starts within its goal radius or with no decision."""
        assert self._physics is not None
        s = self._setups[name]
        end: EndKind
        if _distance(self._physics.pose(name), s.goal) <= self.radius(name):
            end = "reached"
        elif self._allowed[name] == self._steps[name]:
            end = "timed_out"
        else:
            return []
        self._status[name] = end
        return [Event(name, end, s.scenario)]

    def set_goal(
        self, name: str, goal: Sequence[float], time_budget: float | None = None
    ) -> list[Event]:
        """Give a waiting or driving robot a new goal (x, y) in ``map`` and a time budget for
        it, from where it stands (None: :meth:`RobotProfile.time_budget`); its decisions and
        time so far stay counted. A waiting robot starts (``started``); a robot within the goal
        radius has reached it at once. ValueError for a robot whose episode has ended or a
        goal that is not finite."""
        status = self._status[self._known(name)]
        if status not in ("waiting", "active"):
            raise ValueError(f"robot {name!r} has ended its episode ({status})")
        g = (float(goal[0]), float(goal[1]))
        if not all(math.isfinite(v) for v in g):
            raise ValueError(f"goal {g} is not finite")
        s = self._setups[name]
        pose = self.pose(name)
        budget = s.profile.time_budget(pose[:2], g) if time_budget is None else time_budget
        self._setups[name] = dataclasses.replace(s, goal=g, time_budget=float(budget))
        self._budget[name] = self._time[name] + float(budget)
        self._allowed[name] = self._steps[name] + decision_limit(budget, self.step_period)
        events = []
        if status == "waiting":
            self._status[name] = "active"
            events.append(Event(name, "started", s.scenario))
        return events + self._end_at_start(name)

    def state(self, name: str) -> RobotState:
        """Status, counters, pose and goal of a robot of the current episode."""
        s = self._setups[self._known(name)]
        assert self._physics is not None
        return RobotState(
            status=self._status[name],
            steps=self._steps[name],
            allowed=self._allowed[name],
            time_used=self._time[name],
            time_budget=self._budget[name],
            pose=self._physics.pose(name),
            goal=(float(s.goal[0]), float(s.goal[1])),
            scenario=s.scenario,
        )

    def profile(self, name: str) -> RobotProfile:
        """The profile of a robot of the current episode."""
        return self._setups[self._known(name)].profile

    def pose(self, name: str) -> Pose:
        """Current pose (x, y, theta) of a robot (m, m, rad)."""
        self._known(name)
        assert self._physics is not None
        return self._physics.pose(name)

    def scan(self, name: str, wiring: Wiring, rng: np.random.Generator | None) -> FloatArray:
        """The lidar scan of a robot at its pose (m, REP-117 coded), as ``wiring`` says."""
        self._known(name)
        assert self._physics is not None
        return wiring.scan(self._physics, name, rng)

    def observe(self, name: str) -> FloatArray:
        """Range readings (k,) of a robot at its pose, m, +inf beyond range (float64)."""
        self._known(name)
        assert self._physics is not None
        return self._physics.ranges(self._physics.pose(name), robot=name)

    def step(self, decisions: Mapping[str, tuple[float, float]]) -> list[Event]:
        """Drive every active robot by its decision ``(dtheta, ds)`` (rad, m), in name order.

        Decisions of robots that are not active are ignored. Returns the events of the step
        (reached, collided, timed_out). ValueError when an active robot has no decision or a
        non-finite one (nothing moves then).
        """
        active = self.active
        for name in active:
            if name not in decisions:
                raise ValueError(f"no decision for active robot {name!r}")
            dtheta, ds = decisions[name]
            if not (math.isfinite(dtheta) and math.isfinite(ds)):
                raise ValueError(f"decision of {name!r} is not finite ({dtheta}, {ds})")
        assert self._physics is not None or not active
        events: list[Event] = []
        for name in active:
            assert self._physics is not None
            s = self._setups[name]
            dtheta, ds = decisions[name]
            move = self._physics.drive(name, float(dtheta), float(ds), s.goal, self.radius(name))
            self._steps[name] += 1
            self._time[name] += (move.fraction if move.reached else 1.0) * self.step_period
            end: EndKind
            if move.collided:
                end = "collided"
            elif move.reached:
                end = "reached"
            elif self._steps[name] >= self._allowed[name]:
                end = "timed_out"
            else:
                continue
            self._status[name] = end
            events.append(Event(name, end, s.scenario))
        return events

    def _known(self, name: str) -> str:
        if name not in self._setups:
            raise KeyError(f"no robot {name!r} in the episode (robots: {list(self.robots)})")
        return name


def start_fault(world: World, setup: RobotSetup) -> str:
    """Why ``setup`` cannot start in ``world`` alone (a value is not finite, or its body
    overlaps an obstacle or a wall: :func:`mentor_core.sim.scenarios.start_overlap`, the
    screen mentor-eval applies too), or '' when it can. Used to screen scenarios before a
    run."""
    return _value_fault(setup) or start_overlap(world, setup.start, setup.profile)


def _start_fault(physics: PymunkWorld, s: RobotSetup) -> str:
    fault = _value_fault(s)
    # a free probe of the robot's own body: it sees obstacles, walls and every placed robot
    if not fault and physics.collides(s.start, profile=s.profile):
        x, y, th = (float(v) for v in s.start)
        fault = (
            f"its body at the start ({x:.3f}, {y:.3f}, {th:.3f}) overlaps an obstacle, "
            "a wall or a robot"
        )
    return fault


def _value_fault(s: RobotSetup) -> str:
    start = np.asarray(s.start, dtype=np.float64)
    goal = np.asarray(s.goal, dtype=np.float64)
    if start.shape != (3,) or goal.shape != (2,):
        return "start must be (x, y, theta) and goal (x, y)"
    if not (np.isfinite(start).all() and np.isfinite(goal).all()):
        return f"start {tuple(s.start)} or goal {tuple(s.goal)} is not finite"
    if s.time_budget is not None and not (math.isfinite(s.time_budget) and s.time_budget >= 0.0):
        return f"time budget {s.time_budget} s is not finite and >= 0"
    return ""


def _distance(pose: Sequence[float], goal: Sequence[float]) -> float:
    return float(np.hypot(pose[0] - goal[0], pose[1] - goal[1]))


@dataclass(frozen=True)
class RobotTrace:
    """One robot's reference episode.

    Attributes:
        name, scenario: the robot and its scenario index.
        outcome: how the episode ended (``reached``, ``collided`` or ``timed_out``).
        time_used: s; steps: decisions taken.
        poses: ``(steps + 1, 3)`` pose before the first decision and after each one.
        ranges: ``(steps, k)`` readings as delivered to the policy (:func:`wire_ranges`).
        decisions: ``(steps, 2)`` the decisions ``(dtheta, ds)`` taken (rad, m).
    """

    name: str
    scenario: int
    outcome: Status
    time_used: float
    steps: int
    poses: FloatArray
    ranges: FloatArray
    decisions: FloatArray


def run_reference_episode(
    world: World,
    setups: Sequence[RobotSetup],
    policies: Mapping[str, Decide],
    *,
    control_period: float | None = None,
    max_steps: int = 100_000,
    wiring: Wiring | None = None,
) -> dict[str, RobotTrace]:
    """Run one episode of ``setups`` to the end, each robot deciding with its policy.

    Every control period each active robot's policy gets :func:`wire_ranges` of its readings,
    :func:`wire_pose` of its pose and its goal, exactly what the planner node receives over
    ROS. With ``wiring`` (:class:`mentor_core.runtime.wiring.Wiring`) it gets instead what the
    planner receives from a simulator with a lidar and an ``odom`` frame: the readings it
    derives from the lidar scan (robot ``i`` of ``setups`` drawing the noise of generator
    ``i``), pose and goal in ``odom``. Rejected robots are left out of the result.
    ``control_period`` defaults to the first profile's.
    """
    if not setups:
        return {}
    dt = setups[0].profile.control_period if control_period is None else control_period
    wire = Wiring() if wiring is None else wiring
    sim = ReferenceSimulator(world, dt)
    sim.start(setups)
    rngs = {s.name: wire.generator(i) for i, s in enumerate(setups)}
    poses: dict[str, list[Pose]] = {n: [sim.pose(n)] for n in sim.robots}
    seen: dict[str, list[FloatArray]] = {n: [] for n in sim.robots}
    taken: dict[str, list[tuple[float, float]]] = {n: [] for n in sim.robots}
    for _ in range(max_steps):
        if sim.done:
            break
        decisions = {}
        for name in sim.active:
            state = sim.state(name)
            profile = sim.profile(name)
            if wire.lidar is None:
                r = wire_ranges(sim.observe(name), profile)
            else:
                r = wire.readings(sim.scan(name, wire, rngs[name]), profile)
            pose = wire.wire_pose(state.pose)
            dtheta, ds = policies[name](r, pose, wire.odom_goal(state.goal))
            decisions[name] = wire_decision(dtheta, ds, dt)
            seen[name].append(r)
            taken[name].append((float(decisions[name][0]), float(decisions[name][1])))
        sim.step(decisions)
        for name in decisions:
            poses[name].append(sim.pose(name))
    else:
        raise RuntimeError(f"episode did not end within {max_steps} steps")
    out = {}
    for name in sim.robots:
        state = sim.state(name)
        k = sim.profile(name).n_sensors
        out[name] = RobotTrace(
            name=name,
            scenario=state.scenario,
            outcome=state.status,
            time_used=state.time_used,
            steps=state.steps,
            poses=np.array(poses[name], dtype=np.float64).reshape(-1, 3),
            ranges=np.array(seen[name], dtype=np.float64).reshape(-1, k),
            decisions=np.array(taken[name], dtype=np.float64).reshape(-1, 2),
        )
    return out
