"""What a simulator session outputs, to its node (a :class:`SessionPort`) and to its recording
at once, with every pose turned from ``map`` into ``odom`` on the way (the session's wiring).

The recording holds what the node publishes: scans as a LaserScan carries them (float32,
+inf beyond range), odometry in ``odom``, goals and events.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from mentor_core.runtime.recording import EpisodeRecorder
from mentor_core.runtime.session_config import BodyTwist, SessionConfig, SessionPort
from mentor_core.runtime.simulator import EventKind, FloatArray, Pose, RobotSetup
from mentor_core.runtime.wiring import Wiring, wire_ranges
from mentor_core.sim.robots import RobotProfile
from mentor_core.sim.world import World


def session_recorder(
    config: SessionConfig, world: World, control_period: float
) -> EpisodeRecorder | None:
    """The recorder of a session that records (``config.record``), else None."""
    if not config.record:
        return None
    lidar = config.wiring.lidar.mount if config.wiring.lidar else None
    names = [name for name, _ in config.robots]
    return EpisodeRecorder(world, control_period, names, config.wiring.map_to_odom, lidar)


class SessionOutput:
    """A session's output (module docstring); ``recorder`` None: nothing is recorded."""

    def __init__(
        self,
        port: SessionPort,
        recorder: EpisodeRecorder | None,
        wiring: Wiring,
        profiles: Mapping[str, RobotProfile],
    ) -> None:
        self.port = port
        self.recorder = recorder
        self.wiring = wiring
        self._profiles = dict(profiles)

    def clock(self, time_ns: int) -> None:
        """Sim time changed."""
        self.port.clock(time_ns)

    def goal(self, robot: str, goal: tuple[float, float], time_ns: int, record: bool) -> None:
        """A robot's goal in ``map`` (``record``: into the recording too)."""
        self.port.goal(robot, goal, time_ns)
        if record and self.recorder is not None:
            self.recorder.goal(robot, time_ns, goal)

    def event(
        self,
        robot: str,
        kind: EventKind,
        scenario: int,
        time_ns: int,
        goal: tuple[float, float] | None,
    ) -> None:
        """An episode event (``goal`` with ``started``)."""
        self.port.event(robot, kind, scenario, time_ns, goal)
        if self.recorder is not None:
            self.recorder.event(robot, time_ns, kind, scenario)

    def observation(
        self,
        robot: str,
        ranges: FloatArray,
        pose: Pose,
        twist: BodyTwist,
        time_ns: int,
        lidar: FloatArray | None,
    ) -> None:
        """A robot's lidar scan (if any), readings, and odometry of its pose in ``map``."""
        odom = self.wiring.odom_pose(pose)
        if lidar is not None:
            self.port.lidar(robot, lidar, time_ns)
        self.port.observation(robot, ranges, odom, twist, time_ns)
        if self.recorder is not None:
            wired = wire_ranges(ranges, self._profiles[robot])
            self.recorder.scan(robot, time_ns, wired)
            self.recorder.odometry(robot, time_ns, odom, twist)

    def odometry(
        self, robot: str, pose: Pose, twist: BodyTwist, time_ns: int, record: bool = True
    ) -> None:
        """Odometry alone of a robot's pose in ``map`` (``record``: into the recording too)."""
        odom = self.wiring.odom_pose(pose)
        self.port.odometry(robot, odom, twist, time_ns)
        if record and self.recorder is not None:
            self.recorder.odometry(robot, time_ns, odom, twist)


    def command(self, robot: str, time_ns: int, received: Sequence[float]) -> None:
        """A command accepted, ``(linear.x, angular.z)``, stamped with the current time."""
        if self.recorder is not None:
            self.recorder.command(robot, time_ns, float(received[0]), float(received[1]))

    def joined(self, setup: RobotSetup, time_ns: int) -> None:
        """A robot that waited starts with the goal it was given (its setup)."""
        if self.recorder is not None:
            self.recorder.join(time_ns, setup)
        self.port.goal(setup.name, setup.goal, time_ns)

    def goal_changed(
        self, robot: str, goal: tuple[float, float], budget: float, steps: int, time_ns: int
    ) -> None:
        """A driving robot took a new goal with a new time budget (s) after ``steps``."""
        if self.recorder is not None:
            self.recorder.goal_changed(robot, time_ns, goal, budget, steps)
        self.port.goal(robot, goal, time_ns)
        self.port.info(f"{robot}: new goal ({goal[0]:.3f}, {goal[1]:.3f})")

    def save(self, path: str, profile: RobotProfile, metadata: Mapping[str, Any]) -> None:
        """Write the recording (no recorder: nothing); a failure is an error line."""
        if self.recorder is None:
            return
        try:
            self.recorder.save(path, profile, metadata, overwrite=True)
        except (OSError, ValueError) as err:
            self.port.error(f"{path}: recording not written: {err}")
        else:
            self.port.info(f"recorded {self.recorder.n_episodes} episodes: {path}")
