"""Recording the simulator's episodes into an episode bag, and reading them back as episodes.

:class:`EpisodeRecorder` collects, per robot namespace, everything the simulator node
publishes (scan, odometry, goal, events) and receives (cmd_vel), stamped with sim time (ns),
plus one metadata entry per episode with the exact setups (world, starts, goals, time
budgets, scenario indices; JSON floats round-trip exactly). :meth:`EpisodeRecorder.save`
writes them with :func:`mentor_core.files.bags.write_episode_bag`.

Without ROS: :func:`record_planners` runs planners in the reference simulator, one episode per
planner and scenario, and records each episode as the simulator node would (``mentor-eval
--record``).

Reading back: :func:`recorded_episodes` splits an :class:`~mentor_core.files.bags.EpisodeLog`
into one :class:`RecordedRun` per robot and episode (the messages stamped from its
``started`` event up to its end event, both included) and gives the setups to re-simulate it
(:func:`episode_setups`). The simulator leaves one control period between episodes, so no
stamp belongs to two episodes.

Metadata layout (under the bag's ``metadata`` key)::

    {"recorder": "mentor-sim-recording", "version": 1,
     "world": {"size": 5.0, "name": "...", "obstacles": [[xmin, ymin, xmax, ymax], ...]},
     "control_period": 1.0,
     "episodes": [{"episode": 0, "start_ns": 0, "robots": [
         {"name": "robot_0", "profile": "swarm", "scenario": 0,
          "start": [x, y, theta], "goal": [x, y], "time_budget": 40.0}]}],
     ...user keys}
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from mentor_core.errors import FileFormatError, is_version
from mentor_core.files.bags import (
    CmdRecord,
    EpisodeLog,
    EventKind,
    EventRecord,
    GoalRecord,
    OdomRecord,
    RobotEpisode,
    ScanRecord,
    write_episode_bag,
)
from mentor_core.runtime.simulator import Decide, RobotSetup, RobotTrace, run_reference_episode
from mentor_core.sim.frames import MAP_FRAME, ODOM_FRAME
from mentor_core.sim.observation import twist_from_action
from mentor_core.sim.robot_description import FrameLink, robot_links
from mentor_core.sim.robots import RobotProfile, get_profile
from mentor_core.sim.transforms import IDENTITY, Transform2D
from mentor_core.sim.world import Scenario, World

RECORDER_FORMAT = "mentor-sim-recording"
RECORDER_VERSION = 1
_END = frozenset({"reached", "collided", "timed_out"})


@dataclass
class _Streams:
    scans: list[ScanRecord]
    odometry: list[OdomRecord]
    commands: list[CmdRecord]
    goals: list[GoalRecord]
    events: list[EventRecord]


class EpisodeRecorder:
    """Collects one simulator run for an episode bag (see the module docstring).

    ``map_to_odom``: the pose of ``odom`` in ``map`` (the odometry recorded is in ``odom``);
    ``lidar``: the robots' lidar mount, if they have one (a frame of the bag's TF tree).
    """

    def __init__(
        self,
        world: World,
        control_period: float,
        namespaces: Sequence[str],
        map_to_odom: Transform2D = IDENTITY,
        lidar: Transform2D | None = None,
    ) -> None:
        self.world = world
        self.control_period = float(control_period)
        self.map_to_odom = map_to_odom
        self.lidar = lidar
        self._streams = {ns: _Streams([], [], [], [], []) for ns in namespaces}
        self._episodes: list[dict[str, Any]] = []

    @property
    def n_episodes(self) -> int:
        """Episodes begun so far."""
        return len(self._episodes)

    def begin_episode(self, episode: int, start_ns: int, setups: Sequence[RobotSetup]) -> None:
        """Note the exact setups of an episode that starts at ``start_ns``."""
        self._episodes.append(
            {
                "episode": int(episode),
                "start_ns": int(start_ns),
                "robots": [_setup_json(s) for s in setups],
            }
        )

    def join(self, stamp_ns: int, setup: RobotSetup) -> None:
        """A robot that waited for its goal starts in the current episode at ``stamp_ns`` (its
        setup: where it stands, the goal it was given)."""
        if not self._episodes:
            raise ValueError("no episode begun")
        entry = _setup_json(setup)
        entry["start_ns"] = int(stamp_ns)
        self._episodes[-1]["robots"].append(entry)
        self.goal(setup.name, stamp_ns, setup.goal)

    def goal_changed(
        self, ns: str, stamp_ns: int, goal: Sequence[float], time_budget: float, steps: int
    ) -> None:
        """``ns`` took a new goal (x, y in ``map``) with a new time budget (s) after ``steps``
        decisions of the current episode. Before its first decision the episode's setup is
        that goal (it is re-simulated with it); later ones are listed under ``goal_changes``
        (re-simulation does not follow them)."""
        xy = (float(goal[0]), float(goal[1]))
        self.goal(ns, stamp_ns, xy)
        robots = self._episodes[-1]["robots"] if self._episodes else []
        entry = next((r for r in robots if r["name"] == ns), None)
        if entry is None:
            return
        if steps == 0:
            entry["goal"] = list(xy)
            entry["time_budget"] = float(time_budget)
        else:
            change = {"stamp_ns": int(stamp_ns), "step": int(steps), "goal": list(xy),
                      "time_budget": float(time_budget)}
            entry.setdefault("goal_changes", []).append(change)

    def scan(self, ns: str, stamp_ns: int, ranges: ArrayLike) -> None:
        """A published scan (m, +inf beyond range)."""
        r = tuple(float(v) for v in np.asarray(ranges, dtype=np.float64).reshape(-1))
        self._streams[ns].scans.append(ScanRecord(int(stamp_ns), r))

    def odometry(
        self, ns: str, stamp_ns: int, pose: Sequence[float], twist: Sequence[float]
    ) -> None:
        """Published odometry: pose (x, y, theta), body twist (v, omega)."""
        p = (float(pose[0]), float(pose[1]), float(pose[2]))
        t = (float(twist[0]), float(twist[1]))
        self._streams[ns].odometry.append(OdomRecord(int(stamp_ns), p, t))

    def command(self, ns: str, stamp_ns: int, linear_x: float, angular_z: float) -> None:
        """A received (accepted) velocity command, stamped with the observation it answers."""
        self._streams[ns].commands.append(CmdRecord(int(stamp_ns), linear_x, angular_z))

    def goal(self, ns: str, stamp_ns: int, goal: Sequence[float]) -> None:
        """A published goal (x, y)."""
        xy = (float(goal[0]), float(goal[1]))
        self._streams[ns].goals.append(GoalRecord(int(stamp_ns), xy))

    def event(self, ns: str, stamp_ns: int, kind: EventKind, scenario: int) -> None:
        """A published episode event."""
        self._streams[ns].events.append(EventRecord(int(stamp_ns), kind, int(scenario)))

    def robots(self) -> tuple[RobotEpisode, ...]:
        """Everything recorded, one :class:`RobotEpisode` per namespace (given order)."""
        return tuple(
            RobotEpisode(
                ns,
                tuple(st.scans),
                tuple(st.odometry),
                tuple(st.commands),
                tuple(st.goals),
                tuple(st.events),
            )
            for ns, st in self._streams.items()
        )

    def metadata(self, extra: Mapping[str, Any] | None = None) -> dict[str, Any]:
        """The metadata written with the bag (module docstring), ``extra`` keys added."""
        meta: dict[str, Any] = dict(extra or {})
        meta.update(
            {
                "recorder": RECORDER_FORMAT,
                "version": RECORDER_VERSION,
                "world": world_to_json(self.world),
                "control_period": self.control_period,
                "episodes": list(self._episodes),
            }
        )
        if not self.map_to_odom.is_identity:
            meta["map_to_odom"] = list(self.map_to_odom.as_tuple())
        return meta

    def static_frames(self, profile: RobotProfile) -> list[FrameLink]:
        """The fixed part of the bag's TF tree: ``map -> odom`` and every robot's frames."""
        links = [FrameLink(MAP_FRAME, ODOM_FRAME, self.map_to_odom)]
        for ns in self._streams:
            links.extend(robot_links(profile, ns, self.lidar))
        return links

    def save(
        self,
        path: str | Path,
        profile: RobotProfile,
        extra: Mapping[str, Any] | None = None,
        *,
        overwrite: bool = False,
    ) -> None:
        """Write the episode bag (all-or-nothing), with its TF tree; every robot must be of
        ``profile``."""
        write_episode_bag(
            path,
            self.robots(),
            profile,
            self.metadata(extra),
            world=self.world,
            overwrite=overwrite,
            static_frames=self.static_frames(profile),
        )


def _setup_json(s: RobotSetup) -> dict[str, Any]:
    budget = s.profile.time_budget(s.start[:2], s.goal) if s.time_budget is None else s.time_budget
    return {
        "name": s.name,
        "profile": s.profile.name,
        "scenario": int(s.scenario),
        "start": [float(v) for v in s.start],
        "goal": [float(v) for v in s.goal],
        "time_budget": float(budget),
    }


def record_trace(
    recorder: EpisodeRecorder, episode: int, start_ns: int, setup: RobotSetup, trace: RobotTrace
) -> int:
    """Add a finished single-robot reference episode to ``recorder``, stamped as the simulator
    node stamps it; returns the stamp of its last message (ns).

    At ``start_ns``: the goal and the ``started`` event; at each decision ``i`` (stamp
    ``start_ns + i dt``): scan, odometry (with the previous decision's twist) and the command
    answering them; at the end: the end event and the final odometry at rest.
    """
    dt = recorder.control_period
    dt_ns = round(dt * 1e9)
    ns = setup.name
    recorder.begin_episode(episode, start_ns, [setup])
    recorder.goal(ns, start_ns, setup.goal)
    recorder.event(ns, start_ns, "started", setup.scenario)
    twist = (0.0, 0.0)
    for i in range(trace.steps):
        stamp = start_ns + i * dt_ns
        recorder.scan(ns, stamp, trace.ranges[i])
        recorder.odometry(ns, stamp, trace.poses[i], twist)
        dtheta, ds = (float(v) for v in trace.decisions[i])
        angular_z, linear_x = twist_from_action(dtheta, ds, dt)
        recorder.command(ns, stamp, float(linear_x), float(angular_z))
        twist = (float(linear_x), float(angular_z))
    end = start_ns + trace.steps * dt_ns
    outcome = trace.outcome
    if outcome == "reached" or outcome == "collided" or outcome == "timed_out":
        recorder.event(ns, end, outcome, setup.scenario)
    recorder.odometry(ns, end, trace.poses[trace.steps], (0.0, 0.0))
    return end


def record_planners(
    world: World,
    profile: RobotProfile,
    planners: Mapping[str, Decide],
    scenarios: Sequence[Scenario],
    time_limit: float | None = None,
    numbers: Sequence[int] | None = None,
    resets: Mapping[str, Callable[[], None]] | None = None,
) -> tuple[EpisodeRecorder, dict[str, list[RobotTrace]]]:
    """Run each planner alone on each scenario in the reference simulator and record it.

    ``planners`` maps a robot namespace to its decision function; episodes run planner by
    planner, scenario by scenario, one control period apart. ``time_limit`` (s) replaces the
    profile's time budget when given; ``numbers`` are the scenarios' numbers in their source
    (default 0, 1, ...), as the bag records them; ``resets`` maps a namespace to what starts
    its planner blank, called before each of its episodes (a planner with a memory,
    :meth:`mentor_core.runtime.planner.GenomePlanner.reset`). Returns the recorder (save it
    with :meth:`EpisodeRecorder.save`) and each planner's traces in scenario order.
    """
    recorder = EpisodeRecorder(world, profile.control_period, list(planners))
    dt_ns = round(profile.control_period * 1e9)
    traces: dict[str, list[RobotTrace]] = {ns: [] for ns in planners}
    ids = list(range(len(scenarios))) if numbers is None else [int(n) for n in numbers]
    stamp = 0
    for ns, decide in planners.items():
        for k, scenario in zip(ids, scenarios, strict=True):
            setup = RobotSetup(ns, profile, scenario.start, scenario.goal, k, time_limit)
            if resets is not None and ns in resets:
                resets[ns]()
            ran = run_reference_episode(world, [setup], {ns: decide})
            if ns not in ran:
                raise ValueError(f"scenario {k}: the start pose overlaps an obstacle or a wall")
            trace = ran[ns]
            end = record_trace(recorder, recorder.n_episodes, stamp, setup, trace)
            traces[ns].append(trace)
            stamp = end + dt_ns
    return recorder, traces


def world_to_json(world: World) -> dict[str, Any]:
    """``{"size", "name", "obstacles"}`` of a world (exact floats)."""
    return {
        "size": float(world.size),
        "name": str(world.name),
        "obstacles": [[float(v) for v in box] for box in world.obstacles],
    }


def world_from_json(d: Any, source: str | Path = "<metadata>") -> World:
    """The world of :func:`world_to_json`; FileFormatError naming ``source`` otherwise."""
    try:
        return World(
            size=float(d["size"]),
            obstacles=np.array(d["obstacles"], dtype=np.float64).reshape(-1, 4),
            name=str(d.get("name", "")),
        )
    except (KeyError, TypeError, ValueError, AttributeError) as err:
        raise FileFormatError(source, f"bad world in the recording metadata ({err})") from None


@dataclass(frozen=True)
class RecordedRun:
    """One robot's recorded episode.

    Attributes:
        episode: index of the episode in the recording; setup: its exact setup.
        outcome: the end event (``reached``, ``collided``, ``timed_out``), None if it never
            ended in the recording.
        scans, odometry, commands: the records stamped within the episode (odometry
            turned from ``odom`` into ``map``, as the setup).
    """

    episode: int
    setup: RobotSetup
    outcome: str | None
    scans: tuple[ScanRecord, ...]
    odometry: tuple[OdomRecord, ...]
    commands: tuple[CmdRecord, ...]


def episode_setups(log: EpisodeLog, source: str | Path = "<bag>") -> list[list[RobotSetup]]:
    """Per episode, the exact robot setups of a recording (its metadata), each profile at the
    recording's control period (as the simulator node steps it).

    FileFormatError naming ``source`` when the metadata is not a simulator recording.
    """
    meta = log.metadata
    version = meta.get("version")
    if meta.get("recorder") != RECORDER_FORMAT or not is_version(version, RECORDER_VERSION):
        raise FileFormatError(source, "not a simulator recording (no recorder metadata)")
    out = []
    try:
        period = float(meta["control_period"])
        if not (math.isfinite(period) and period > 0.0):
            raise ValueError(f"control_period {period}")
        for ep in meta["episodes"]:
            out.append(
                [
                    RobotSetup(
                        name=str(r["name"]),
                        profile=replace(get_profile(str(r["profile"])), control_period=period),
                        start=(float(r["start"][0]), float(r["start"][1]), float(r["start"][2])),
                        goal=(float(r["goal"][0]), float(r["goal"][1])),
                        scenario=int(r["scenario"]),
                        time_budget=float(r["time_budget"]),
                    )
                    for r in ep["robots"]
                ]
            )
    except (KeyError, TypeError, ValueError, IndexError) as err:
        raise FileFormatError(source, f"bad episode metadata ({err})") from None
    return out


def recording_world(log: EpisodeLog, source: str | Path = "<bag>") -> World:
    """The world of a recording (metadata; it equals the bag's ``/mentor/obstacles``)."""
    return world_from_json(log.metadata.get("world"), source)


def recording_map_to_odom(log: EpisodeLog, source: str | Path = "<bag>") -> Transform2D:
    """The pose of ``odom`` in ``map`` the recording was made with (identity when absent)."""
    raw = log.metadata.get("map_to_odom")
    if raw is None:
        return IDENTITY
    try:
        return Transform2D.of([float(v) for v in raw])
    except (TypeError, ValueError) as err:
        raise FileFormatError(source, f"bad map_to_odom in the metadata ({err})") from None


def _in_map(record: OdomRecord, map_to_odom: Transform2D) -> OdomRecord:
    if map_to_odom.is_identity:
        return record
    return OdomRecord(record.stamp_ns, map_to_odom.apply_pose(record.pose), record.twist)


def recorded_episodes(log: EpisodeLog, source: str | Path = "<bag>") -> list[RecordedRun]:
    """Split a recording into one :class:`RecordedRun` per robot and episode.

    The episodes of a namespace are the intervals from each ``started`` event to the next
    end event (inclusive); they are matched with the metadata's episodes in order.
    """
    setups = episode_setups(log, source)
    to_map = recording_map_to_odom(log, source)
    per_robot: dict[str, list[tuple[int, RobotSetup]]] = {}
    for e, ep in enumerate(setups):
        for s in ep:
            per_robot.setdefault(s.name, []).append((e, s))
    runs = []
    for robot in log.robots:
        events = sorted(robot.events, key=lambda ev: ev.stamp_ns)
        starts = [ev for ev in events if ev.kind == "started"]
        planned = per_robot.get(robot.namespace, [])
        if len(starts) != len(planned):
            raise FileFormatError(
                source,
                f"{robot.namespace}: {len(starts)} started events, metadata lists "
                f"{len(planned)} episodes",
            )
        for (episode, setup), begin in zip(planned, starts, strict=True):
            end = next(
                (ev for ev in events if ev.kind in _END and ev.stamp_ns >= begin.stamp_ns),
                None,
            )
            hi = end.stamp_ns if end is not None else np.iinfo(np.int64).max
            lo = begin.stamp_ns

            def within(stamp: int, lo: int = lo, hi: int = hi) -> bool:
                return lo <= stamp <= hi

            runs.append(
                RecordedRun(
                    episode=episode,
                    setup=setup,
                    outcome=None if end is None else end.kind,
                    scans=tuple(r for r in robot.scans if within(r.stamp_ns)),
                    odometry=tuple(
                        _in_map(r, to_map) for r in robot.odometry if within(r.stamp_ns)
                    ),
                    commands=tuple(r for r in robot.commands if within(r.stamp_ns)),
                )
            )
    return runs
