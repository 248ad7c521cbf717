"""The simulator node's publishers and subscriptions per robot, as the session's output port.

Per robot ``<ns>``: ``scan`` (its per-sensor LaserScan), ``lidar/scan`` (a simulated lidar,
when ``lidar_rays`` > 0), ``odom``, ``goal`` (latched; also subscribed, latched and volatile,
so that any publisher's goal reaches the simulator), ``events``, ``robot_description``
(latched URDF) and the ``cmd_vel`` subscription. Shared: ``/clock``,
``/mentor/obstacles`` and, where ``tf2_msgs`` imports (a full ROS 2 install), ``/tf`` and
``/tf_static``.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

from geometry_msgs.msg import PoseStamped, Twist
from nav_msgs.msg import Odometry
from numpy.typing import ArrayLike
from rclpy.node import Node
from rclpy.qos import (
    DurabilityPolicy,
    HistoryPolicy,
    QoSProfile,
    ReliabilityPolicy,
    qos_profile_sensor_data,
)
from rosgraph_msgs.msg import Clock as ClockMsg
from sensor_msgs.msg import LaserScan
from std_msgs.msg import String
from visualization_msgs.msg import MarkerArray

from mentor_core import (
    BASE_LINK,
    LIDAR_LINK,
    MAP_FRAME,
    ODOM_FRAME,
    EventKind,
    FrameLink,
    RobotProfile,
    Transform2D,
    Wiring,
    frame_id,
    robot_links,
    robot_urdf,
)
from mentor_sim_node import conversions

try:  # a full ROS 2 install has tf2_msgs; the pip-only one has no wheel (bags still carry TF)
    from tf2_msgs.msg import TFMessage
except ImportError:  # pragma: no cover - depends on the installation
    TFMessage = None

OBSTACLES_TOPIC = "/mentor/obstacles"
COMMAND_DEPTH = 10
EVENT_DEPTH = 10
LATCHED_DEPTH = 1
GOAL_DEPTH = 10
TF_DEPTH = 100
#: goals and obstacles: latched (transient local), reliable, the latest one
QOS_LATCHED = QoSProfile(
    history=HistoryPolicy.KEEP_LAST,
    depth=LATCHED_DEPTH,
    reliability=ReliabilityPolicy.RELIABLE,
    durability=DurabilityPolicy.TRANSIENT_LOCAL,
)
#: goals from ordinary publishers (RViz, Foxglove, a plain rclpy publisher)
QOS_GOAL = QoSProfile(depth=GOAL_DEPTH, reliability=ReliabilityPolicy.RELIABLE)
QOS_COMMAND = QoSProfile(depth=COMMAND_DEPTH, reliability=ReliabilityPolicy.RELIABLE)
QOS_EVENTS = QoSProfile(depth=EVENT_DEPTH, reliability=ReliabilityPolicy.RELIABLE)
QOS_CLOCK = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE)
QOS_TF = QoSProfile(depth=TF_DEPTH, reliability=ReliabilityPolicy.RELIABLE)
Vec = Sequence[float]
GoalCallback = Callable[[PoseStamped], None]


def subscribe_goals(
    node: Node, topic: str, callback: GoalCallback, latched: bool
) -> list[Any]:
    """A volatile subscription to a goal topic (it matches every publisher) and, with
    ``latched``, a latched one (the last goal a latched publisher sent before)."""
    subs = [node.create_subscription(PoseStamped, topic, callback, QOS_GOAL)]
    if latched:
        subs.append(node.create_subscription(PoseStamped, topic, callback, QOS_LATCHED))
    return subs


class _Robot:
    """Publishers, subscriptions and the last observation of one robot namespace."""

    def __init__(
        self,
        node: Node,
        name: str,
        profile: RobotProfile,
        on_cmd: Callable[[Twist], None],
        on_goal: GoalCallback,
        lidar: bool,
    ) -> None:
        self.profile = profile
        sensor = qos_profile_sensor_data
        self.scan_pub = node.create_publisher(LaserScan, f"{name}/scan", sensor)
        self.lidar_pub = node.create_publisher(LaserScan, f"{name}/lidar/scan", sensor) if (
            lidar
        ) else None
        self.odom_pub = node.create_publisher(Odometry, f"{name}/odom", sensor)
        self.goal_pub = node.create_publisher(PoseStamped, f"{name}/goal", QOS_LATCHED)
        self.events_pub = node.create_publisher(String, f"{name}/events", QOS_EVENTS)
        self.urdf_pub = node.create_publisher(String, f"{name}/robot_description", QOS_LATCHED)
        self.cmd_sub = node.create_subscription(Twist, f"{name}/cmd_vel", on_cmd, QOS_COMMAND)
        self.goal_subs = subscribe_goals(node, f"{name}/goal", on_goal, latched=True)
        self.last: list[tuple[Any, Any]] = []  # (publisher, message) of the last observation
        self.lidar_msg: tuple[Any, Any] | None = None  # the scan going with the next one
        #: (stamp, x, y) of the goals this node published: their echo is not a new goal
        self.sent_goals: list[tuple[int, float, float]] = []


class Topics:
    """The node's publishers as the session's port (:class:`mentor_core.SessionPort`)."""

    def __init__(
        self,
        node: Node,
        robots: Sequence[tuple[str, RobotProfile]],
        wiring: Wiring,
        on_command: Callable[[str], Callable[[Twist], None]],
        on_goal: Callable[[str], GoalCallback],
    ) -> None:
        self._log = node.get_logger()
        self._wiring = wiring
        self.clock_pub = node.create_publisher(ClockMsg, "/clock", QOS_CLOCK)
        self.markers_pub = node.create_publisher(MarkerArray, OBSTACLES_TOPIC, QOS_LATCHED)
        lidar = wiring.lidar is not None
        self.robots = {
            n: _Robot(node, n, p, on_command(n), on_goal(n), lidar) for n, p in robots
        }
        self.tf_pub = node.create_publisher(TFMessage, "/tf", QOS_TF) if TFMessage else None
        self.tf_static_pub = (
            node.create_publisher(TFMessage, "/tf_static", QOS_LATCHED) if TFMessage else None
        )

    def static_frames(self) -> list[FrameLink]:
        """``map -> odom`` and every robot's sensor (and lidar) frames."""
        mount = self._wiring.lidar.mount if self._wiring.lidar else None
        links = [FrameLink(MAP_FRAME, ODOM_FRAME, self._wiring.map_to_odom)]
        for name, robot in self.robots.items():
            links.extend(robot_links(robot.profile, name, mount))
        return links

    def publish_description(self, stamp_ns: int) -> None:
        """Each robot's URDF (latched) and, with tf2_msgs, the static frames."""
        mount = self._wiring.lidar.mount if self._wiring.lidar else None
        for name, robot in self.robots.items():
            robot.urdf_pub.publish(String(data=robot_urdf(robot.profile, name, mount)))
        if self.tf_static_pub is not None and TFMessage is not None:
            stamp = conversions.time_from_ns(stamp_ns)
            msg = TFMessage(transforms=conversions.transforms(self.static_frames(), stamp))
            self.tf_static_pub.publish(msg)

    def clock(self, time_ns: int) -> None:
        self.clock_pub.publish(ClockMsg(clock=conversions.time_from_ns(time_ns)))

    def goal(self, robot: str, goal: Vec, time_ns: int) -> None:
        msg = conversions.pose_stamped_from_goal(goal, conversions.time_from_ns(time_ns))
        r = self.robots[robot]
        r.sent_goals = [*r.sent_goals[-4:], (time_ns, float(goal[0]), float(goal[1]))]
        r.goal_pub.publish(msg)

    def echo(self, robot: str, msg: PoseStamped) -> bool:
        """``msg`` is a goal this node published itself (it comes back on its subscription)."""
        stamp = conversions.ns_from_time(msg.header.stamp)
        key = (stamp, float(msg.pose.position.x), float(msg.pose.position.y))
        return msg.header.frame_id == MAP_FRAME and key in self.robots[robot].sent_goals

    def event(
        self, robot: str, kind: EventKind, scenario: int, time_ns: int, goal: Vec | None
    ) -> None:
        msg = conversions.event_string(kind, scenario, time_ns, goal)
        self.robots[robot].events_pub.publish(msg)

    def lidar(self, robot: str, ranges: ArrayLike, time_ns: int) -> None:
        r = self.robots[robot]
        spec = self._wiring.lidar
        if r.lidar_pub is None or spec is None:
            return
        stamp = conversions.time_from_ns(time_ns)
        msg = conversions.lidar_scan(ranges, spec, stamp, frame_id(robot, LIDAR_LINK))
        r.lidar_pub.publish(msg)
        r.lidar_msg = (r.lidar_pub, msg)

    def observation(
        self, robot: str, ranges: ArrayLike, pose: Vec, twist: Vec, time_ns: int
    ) -> None:
        r = self.robots[robot]
        stamp = conversions.time_from_ns(time_ns)
        frame = frame_id(robot, BASE_LINK)
        scan = conversions.laser_scan_from_ranges(ranges, r.profile, stamp, frame)
        odom = conversions.odometry_from_pose(pose, twist, stamp, robot)
        r.scan_pub.publish(scan)
        r.odom_pub.publish(odom)
        self._moved(robot, pose, stamp)
        lidar = [r.lidar_msg] if r.lidar_msg is not None else []
        r.last, r.lidar_msg = [*lidar, (r.scan_pub, scan), (r.odom_pub, odom)], None

    def odometry(self, robot: str, pose: Vec, twist: Vec, time_ns: int) -> None:
        stamp = conversions.time_from_ns(time_ns)
        msg = conversions.odometry_from_pose(pose, twist, stamp, robot)
        self.robots[robot].odom_pub.publish(msg)
        self._moved(robot, pose, stamp)

    def _moved(self, robot: str, pose: Vec, stamp: Any) -> None:
        """``odom -> <ns>/base_link`` on ``/tf`` (where tf2_msgs imports)."""
        if self.tf_pub is None or TFMessage is None:
            return
        link = FrameLink(ODOM_FRAME, frame_id(robot, BASE_LINK), Transform2D(*pose))
        self.tf_pub.publish(TFMessage(transforms=conversions.transforms([link], stamp)))

    def resend(self, robots: Sequence[str]) -> None:
        """Publish the last observation of ``robots`` again (same stamp)."""
        for name in robots:
            for pub, msg in self.robots[name].last:
                pub.publish(msg)

    def info(self, text: str) -> None:
        self._log.info(text)

    def warning(self, text: str) -> None:
        self._log.warning(text)

    def error(self, text: str) -> None:
        self._log.error(text)
