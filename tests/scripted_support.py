"""The TurtleBot3 Burger of the closed-loop tests: the ``turtlebot3_burger`` preset's planner
node, a robot played by a script (:class:`mentor_bringup.scripted_robot.ScriptedRobot`) and
the test's goal publisher, in one graph."""

from __future__ import annotations

from typing import Any

import numpy as np
from geometry_msgs.msg import PoseStamped
from ros_support import Graph

from mentor_bringup.scripted_robot import GoalRig, drive_goals, run_for, spinner
from mentor_core.runtime.streamed_robot import StreamedRobot
from mentor_core.sim.robots import get_profile
from mentor_core.sim.world import World
from mentor_planner_node.presets import SOURCE_CONFIG, preset_values

GENOME = "planners/ugv-paper-dual-s1.json"
#: a 10 m room: a wall with a door across it and two boxes
WORLD = World(10.0, np.array([
    [4.8, 0.0, 5.2, 4.0], [4.8, 5.2, 5.2, 10.0],  # the wall, a door at y 4-5.2
    [2.0, 6.5, 3.0, 7.5], [7.0, 2.0, 8.0, 3.0],
]))  # fmt: skip
SPEEDUP = 2.0


class Burger:
    """The preset's planner, the scripted robot and the test's goal publisher, in ``graph``."""

    def __init__(self, graph: Graph, start: tuple[float, float, float], **extra: Any) -> None:
        values = {**preset_values(SOURCE_CONFIG / "turtlebot3_burger.yaml"), "genome": GENOME,
                  "use_sim_time": True, **extra}  # fmt: skip
        self.sim = StreamedRobot(WORLD, get_profile("ugv"), start, seed=3)
        rig = GoalRig(graph.context, values, self.sim, graph.add)
        self.planner, self.robot, self.statuses, self.goal = (rig.planner, rig.robot,
                                                              rig.statuses, rig.goal_pub)
        self.graph = graph
        self.spin = spinner(graph.executor)

    def drive(self, *goals: tuple[float, float], limit: float = 90.0) -> list[Any]:
        return drive_goals(self.spin, self.robot, self.goal, self.statuses, list(goals),
                           SPEEDUP, limit)  # fmt: skip

    def run(self, seconds: float) -> None:
        run_for(self.spin, self.robot, seconds, SPEEDUP)


def goal_msg(xy: tuple[float, float], frame: str = "odom") -> PoseStamped:
    """A goal at ``xy`` in ``frame``, as RViz's tool sends one."""
    msg = PoseStamped()
    msg.header.frame_id = frame
    msg.pose.position.x, msg.pose.position.y = xy
    msg.pose.orientation.w = 1.0
    return msg
