"""What MENTOR's bags hold: formats, versions, topic names and the episode records.

Scenario bag (``format: mentor-scenario-bag``, version 1), every message at bag time 0:

=====================  =============================  ==========================================
topic                  type                           content
=====================  =============================  ==========================================
``/mentor/metadata``   ``std_msgs/msg/String``        JSON: format, version, profile, arena size,
                                                      world name, scenario count, user metadata
``/mentor/obstacles``  ``visualization_msgs/msg/      ns ``arena``: LINE_STRIP around the arena;
                       MarkerArray``                  ns ``obstacles``: one CUBE per box (pose =
                                                      centre, scale = size, frame ``map``);
                                                      ``points`` = the exact corners
                                                      ``(xmin, ymin, 0), (xmax, ymax, h)``
``/mentor/starts``     ``geometry_msgs/msg/PoseArray``  one pose per scenario, yaw quaternion
``/mentor/goals``      ``geometry_msgs/msg/PoseArray``  one pose per scenario, identity rotation
=====================  =============================  ==========================================

Episode bag (``format: mentor-episode-bag``, version 1): ``/mentor/metadata`` as above (with
the robot namespaces) and, per robot namespace ``<ns>``, ``/<ns>/scan``
(``sensor_msgs/LaserScan``, +inf out of range, REP-117), ``/<ns>/odom`` (``nav_msgs/Odometry``,
``odom`` -> ``<ns>/base_link``), ``/<ns>/cmd_vel`` (``geometry_msgs/Twist``), ``/<ns>/goal``
(``geometry_msgs/PoseStamped`` in ``map``) and ``/<ns>/events`` (``std_msgs/String`` JSON).
Bag times and header stamps are simulation time in ns. A simulator recording also holds the
frames: ``/tf_static`` (``tf2_msgs/msg/TFMessage`` at time 0: ``map -> odom`` and each robot's
``<ns>/base_link -> <ns>/sensor_<i>``, ``-> <ns>/lidar``) and ``/tf`` (``odom ->
<ns>/base_link`` at every odometry stamp), so that viewers place everything in one tree.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Final, Literal, get_args

if TYPE_CHECKING:
    from mentor_core.sim.world import World

SCENARIO_FORMAT: Final = "mentor-scenario-bag"
EPISODE_FORMAT: Final = "mentor-episode-bag"
EVENT_FORMAT: Final = "mentor-episode-event"
BAG_VERSION: Final = 1
ROSBAG2_VERSION: Final = 9  # rosbag2 metadata version written (Jazzy writes 9)

METADATA_TOPIC: Final = "/mentor/metadata"
OBSTACLES_TOPIC: Final = "/mentor/obstacles"
STARTS_TOPIC: Final = "/mentor/starts"
GOALS_TOPIC: Final = "/mentor/goals"
TF_TOPIC: Final = "/tf"
TF_STATIC_TOPIC: Final = "/tf_static"

EventKind = Literal["started", "reached", "collided", "timed_out"]
EVENT_KINDS: Final[tuple[str, ...]] = get_args(EventKind)


@dataclass(frozen=True)
class ScanRecord:
    """One range scan: sim time (ns) and ranges (m, sensor order, +inf out of range)."""

    stamp_ns: int
    ranges: tuple[float, ...]


@dataclass(frozen=True)
class OdomRecord:
    """Odometry: pose ``(x, y, theta)`` (m, m, rad) in ``odom`` (= ``map`` in the sim) and
    body twist ``(v, omega)`` (m/s along body x, rad/s about z)."""

    stamp_ns: int
    pose: tuple[float, float, float]
    twist: tuple[float, float]


@dataclass(frozen=True)
class CmdRecord:
    """A velocity command: ``linear_x = ds/dt`` (m/s), ``angular_z = dtheta/dt`` (rad/s)."""

    stamp_ns: int
    linear_x: float
    angular_z: float


@dataclass(frozen=True)
class GoalRecord:
    """A goal ``(x, y)`` (m, ``map`` frame) given at ``stamp_ns``."""

    stamp_ns: int
    goal: tuple[float, float]


@dataclass(frozen=True)
class EventRecord:
    """An episode event; ``scenario`` is the scenario index or -1 when not given."""

    stamp_ns: int
    kind: EventKind
    scenario: int = -1


@dataclass(frozen=True)
class RobotEpisode:
    """Everything recorded for one robot namespace (``ns`` without leading slash)."""

    namespace: str
    scans: tuple[ScanRecord, ...] = ()
    odometry: tuple[OdomRecord, ...] = ()
    commands: tuple[CmdRecord, ...] = ()
    goals: tuple[GoalRecord, ...] = ()
    events: tuple[EventRecord, ...] = ()


@dataclass(frozen=True)
class EpisodeLog:
    """The content of an episode bag."""

    profile_name: str
    robots: tuple[RobotEpisode, ...]
    metadata: Mapping[str, Any] = field(default_factory=dict)
    world: World | None = None  # when the bag holds /mentor/obstacles


def _robot_topics(ns: str) -> dict[str, str]:
    """The five topics of robot namespace ``ns``: ``scan``, ``odom``, ``cmd_vel``, ``goal``,
    ``events``."""
    return {
        "scan": f"/{ns}/scan",
        "odom": f"/{ns}/odom",
        "cmd_vel": f"/{ns}/cmd_vel",
        "goal": f"/{ns}/goal",
        "events": f"/{ns}/events",
    }
