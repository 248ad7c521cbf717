"""rosbag2 (MCAP) bags of MENTOR scenarios and episodes, written and read with rosbags'
typestore, never rclpy.

:mod:`.records` holds the bag layouts and the episode records, :mod:`.messages` the message
builders, QoS profiles and display geometry, :mod:`.writing` and :mod:`.reading` the two
directions.
"""

from mentor_core.files.bags.messages import (
    ARENA_LINE_WIDTH,
    MARKER_CUBE,
    MARKER_LINE_STRIP,
    OBSTACLE_HEIGHT,
    QOS_COMMAND,
    QOS_LATCHED,
    QOS_SENSOR,
    BoxMarker,
    ScanGeometry,
    arena_outline,
    box_markers,
    scan_geometry,
)
from mentor_core.files.bags.reading import read_episode_bag, read_scenario_bag
from mentor_core.files.bags.records import (
    BAG_VERSION,
    EPISODE_FORMAT,
    EVENT_FORMAT,
    EVENT_KINDS,
    GOALS_TOPIC,
    METADATA_TOPIC,
    OBSTACLES_TOPIC,
    ROSBAG2_VERSION,
    SCENARIO_FORMAT,
    STARTS_TOPIC,
    CmdRecord,
    EpisodeLog,
    EventKind,
    EventRecord,
    GoalRecord,
    OdomRecord,
    RobotEpisode,
    ScanRecord,
)
from mentor_core.files.bags.writing import looks_like_bag, write_episode_bag, write_scenario_bag

__all__ = [
    "ARENA_LINE_WIDTH",
    "BAG_VERSION",
    "EPISODE_FORMAT",
    "EVENT_FORMAT",
    "EVENT_KINDS",
    "GOALS_TOPIC",
    "MARKER_CUBE",
    "MARKER_LINE_STRIP",
    "METADATA_TOPIC",
    "OBSTACLES_TOPIC",
    "OBSTACLE_HEIGHT",
    "QOS_COMMAND",
    "QOS_LATCHED",
    "QOS_SENSOR",
    "ROSBAG2_VERSION",
    "SCENARIO_FORMAT",
    "STARTS_TOPIC",
    "BoxMarker",
    "CmdRecord",
    "EpisodeLog",
    "EventKind",
    "EventRecord",
    "GoalRecord",
    "OdomRecord",
    "RobotEpisode",
    "ScanGeometry",
    "ScanRecord",
    "arena_outline",
    "box_markers",
    "looks_like_bag",
    "read_episode_bag",
    "read_scenario_bag",
    "scan_geometry",
    "write_episode_bag",
    "write_scenario_bag",
]
