"""A robot played by a script, as a real one talks to the planner node: a TurtleBot3 Burger
by default (:class:`mentor_core.StreamedRobot`: lidar at 5 Hz on ``base_scan``, odometry at
30 Hz from ``odom`` to ``base_footprint``, the base's limits), publishing ``/clock`` so that a
run goes faster than real time, and taking ``cmd_vel`` (``Twist`` or ``TwistStamped``).

:func:`drive_goals` sends it goals one by one on ``/goal_pose``, as RViz's tool does, and
reads each goal's end off the planner's ``goal_status``: the closed-loop check of the
TurtleBot3 preset (``tests/test_scripted_robot.py``,
``benchmarks/tools/scripted_robot_goals.py``).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import rclpy
from geometry_msgs.msg import PoseStamped, Twist, TwistStamped
from nav_msgs.msg import Odometry
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import qos_profile_sensor_data
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import LaserScan
from std_msgs.msg import String

from mentor_core import FrameLink, StreamedRobot, Transform2D
from mentor_planner_node.planner import QOS_LATCHED, QOS_TF, PlannerNode
from mentor_sim_node.conversions import lidar_scan, odometry_from_pose, time_from_ns, transforms

try:  # a full install, or generated in the workspace (interfaces/README.md)
    from tf2_msgs.msg import TFMessage
except ImportError:  # pragma: no cover - depends on the installation
    TFMessage = None

_NS_PER_S = 1_000_000_000
BASE = "base_footprint"


class ScriptedRobot(Node):
    """The ROS side of ``robot`` (module docstring): :meth:`tick` drives one tick and
    publishes what fell due, stamped in sim time."""

    def __init__(self, robot: StreamedRobot, stamped: bool = False, **kwargs: Any) -> None:
        super().__init__("scripted_robot", **kwargs)
        self.robot = robot
        self._scan = self.create_publisher(LaserScan, "scan", qos_profile_sensor_data)
        self._odom = self.create_publisher(Odometry, "odom", qos_profile_sensor_data)
        self._clock = self.create_publisher(Clock, "/clock", 10)
        kind = TwistStamped if stamped else Twist
        self.create_subscription(kind, "cmd_vel", self._on_cmd, 10)
        self.commands = 0
        # its frames on TF, where tf2_msgs is: odom -> base_footprint moving, the lidar fixed
        self._tf = None
        if TFMessage is not None:
            self._tf = self.create_publisher(TFMessage, "/tf", QOS_TF)
            mount = FrameLink(BASE, "base_scan", robot.spec.lidar.mount)
            static = self.create_publisher(TFMessage, "/tf_static", QOS_LATCHED)
            static.publish(TFMessage(transforms=transforms([mount], time_from_ns(0))))

    def _on_cmd(self, msg: Twist | TwistStamped) -> None:
        twist = msg.twist if isinstance(msg, TwistStamped) else msg
        self.robot.command = (float(twist.linear.x), float(twist.angular.z))
        self.commands += 1

    def tick(self) -> bool:
        """Drive one tick; publish the clock and what fell due; True on a collision."""
        out = self.robot.step()
        stamp = time_from_ns(round(out.time * _NS_PER_S))
        self._clock.publish(Clock(clock=stamp))
        if out.odometry is not None:
            pose, velocity = out.odometry
            self._odom.publish(odometry_msg(pose, velocity, stamp))
            if self._tf is not None:
                link = FrameLink("odom", BASE, Transform2D(*pose))
                self._tf.publish(TFMessage(transforms=transforms([link], stamp)))
        if out.scan is not None:
            self._scan.publish(lidar_scan(out.scan, self.robot.spec.lidar, stamp, "base_scan"))
        return out.collided


class GoalRig:
    """A user sending goals to a robot: the planner node with ``values`` (a preset's
    parameters, the genome), ``sim`` played by a :class:`ScriptedRobot`, and a node that sends
    goals on ``/goal_pose`` (:attr:`goal_pub`) and hears ``goal_status`` (:attr:`statuses`),
    all in ``context``; ``add`` puts each node on the caller's executor."""

    def __init__(self, context: Any, values: Mapping[str, Any], sim: StreamedRobot,
                 add: Callable[[Node], Any]) -> None:  # fmt: skip
        overrides = [Parameter(name, value=value) for name, value in values.items()]
        self.planner: PlannerNode = add(PlannerNode(context=context,
                                                    parameter_overrides=overrides))
        self.robot: ScriptedRobot = add(ScriptedRobot(sim, context=context))
        sender = add(rclpy.create_node("goals", context=context))
        self.statuses: list[str] = []
        status_listener(sender, self.statuses)
        self.goal_pub = sender.create_publisher(PoseStamped, "/goal_pose", 10)


def odometry_msg(pose: Sequence[float], velocity: Sequence[float], stamp: Any) -> Odometry:
    """Odometry as a TurtleBot3 publishes it: ``odom`` -> ``base_footprint``."""
    msg = odometry_from_pose(pose, velocity, stamp, "")
    msg.child_frame_id = BASE
    return msg


@dataclass(frozen=True)
class GoalRun:
    """How one goal ended: ``status`` as ``goal_status`` said it ('' : no end within the
    time), sim s taken, collisions on the way, m driven, m left to the goal."""

    status: str
    seconds: float
    collisions: int
    driven: float
    left: float


def drive_goals(
    spin: Callable[[float], None], robot: ScriptedRobot, goal_pub: Any, statuses: list[str],
    goals: Sequence[tuple[float, float]], speedup: float = 4.0, limit: float = 120.0,
    frame: str = "odom",
) -> list[GoalRun]:  # fmt: skip
    """Send ``goals`` one by one on ``goal_pub`` (``/goal_pose``) and tick ``robot`` until
    ``statuses`` (``goal_status``, appended by the caller's subscription) says the goal
    ended or ``limit`` sim s pass; ``spin(wall_s)`` runs the executor between ticks, the
    sim going ``speedup`` times faster than the wall."""
    runs = []
    sim = robot.robot
    for goal in goals:
        msg = PoseStamped()
        msg.header.frame_id = frame
        msg.pose.position.x, msg.pose.position.y = goal
        start, collisions, driven = sim.time, sim.collisions, sim.distance
        seen = len(statuses)
        ended = ""
        while not ended and sim.time - start < limit:
            if not any(s.startswith("accepted") or _final(s) for s in statuses[seen:]):
                goal_pub.publish(msg)  # until the planner has it (its subscriptions match)
            run_for(spin, robot, sim.spec.tick, speedup)
            ended = next((s for s in statuses[seen:] if _final(s)), "")
        x, y, _ = sim.pose
        runs.append(GoalRun(ended, sim.time - start, sim.collisions - collisions,
                            sim.distance - driven, ((x - goal[0]) ** 2 + (y - goal[1]) ** 2)
                            ** 0.5))  # fmt: skip
        run_for(spin, robot, 10 * sim.spec.tick, speedup)  # the last zero Twist arrives
    return runs


#: spin_once calls without waiting that take what is ready before a tick's wait: a tick
#: brings several messages (clock, odometry, TF, a scan), and one call handles one of them
DRAIN = 20


def spinner(executor: Any) -> Callable[[float], None]:
    """``spin(seconds)``: handle what is ready on ``executor``, then wait for more until
    ``seconds`` of wall time have passed (so the graph never falls behind the ticks)."""

    def spin(seconds: float) -> None:
        deadline = time.monotonic() + seconds
        for _ in range(DRAIN):
            executor.spin_once(timeout_sec=0.0)
        while (left := deadline - time.monotonic()) > 0.0:
            executor.spin_once(timeout_sec=left)

    return spin


def run_for(spin: Callable[[float], None], robot: ScriptedRobot, seconds: float,
            speedup: float = 2.0) -> None:  # fmt: skip
    """Tick ``robot`` for ``seconds`` of sim time, ``speedup`` times faster than the wall."""
    sim = robot.robot
    end = sim.time + seconds
    while sim.time < end:
        began = time.monotonic()
        robot.tick()
        spin(max(0.0, sim.spec.tick / speedup - (time.monotonic() - began)))


def _final(status: str) -> bool:
    return status == "reached" or status.split(":")[0] in ("aborted", "goal refused",
                                                            "canceled")  # fmt: skip


def status_listener(node: Node, statuses: list[str], topic: str = "goal_status") -> Any:
    """A subscription appending each ``goal_status`` to ``statuses``."""
    return node.create_subscription(String, topic, lambda m: statuses.append(m.data),
                                    QOS_LATCHED)  # fmt: skip
