"""Launch one MENTOR planner on a robot (ROS 2 Jazzy with ``launch`` installed).

    ros2 launch mentor_planner_node planner.launch.py robot:=turtlebot3_burger \
        genome:=ugv-paper-dual-s1
    ros2 launch mentor_planner_node planner.launch.py robot:=turtlebot3_waffle \
        genome:=ugv-paper-dual-s1 namespace:=tb3_0 goal_radius:=0.4 rviz:=true
    ros2 launch mentor_planner_node planner.launch.py genome:=best_genome.json \
        lidar_mount:="[0.1, 0.0, 0.0]" max_vel_x:=0.5      # any lidar robot (robot:=generic)
    ros2 launch mentor_planner_node planner.launch.py robot:=mentor_sim namespace:=robot_0 \
        genome:=ugv-paper-dual-s1                          # beside this project's simulator

``robot`` picks a preset, a parameter file installed with the package
(``share/mentor_planner_node/config/<robot>.yaml``: ``generic``, ``turtlebot3_burger``,
``turtlebot3_waffle``, ``mentor_sim``); every other argument left empty keeps the preset's
value (``docs/ros.md`` has the table). ``genome`` is a file or the name of a shipped planner
(``ugv-paper-dual-s1``), installed with the package. ``namespace`` puts the node and its
relative topics (``scan``, ``odom``, ``cmd_vel``, ``goal``, ``goal_status``, ...) under it;
``scan``, ``odom`` and ``cmd_vel`` remap them to the robot's; ``params_file`` adds a file of
your own on top; ``rviz`` starts RViz2 in the namespace.
"""

from __future__ import annotations

import os

from ament_index_python.packages import get_package_share_directory
from launch import LaunchContext, LaunchDescription
from launch.actions import DeclareLaunchArgument, OpaqueFunction
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node

from mentor_core import launch_flag
from mentor_planner_node.presets import PARAMETERS, launch_parameters, preset_file

ARGUMENTS = {
    "robot": "generic",
    "namespace": "",
    "scan": "scan",
    "odom": "odom",
    "cmd_vel": "cmd_vel",
    "params_file": "",
    "rviz": "false",
    **{name: "" for name in PARAMETERS},
}


def _nodes(context: LaunchContext) -> list[Node]:
    value = {name: LaunchConfiguration(name).perform(context) for name in ARGUMENTS}
    share = get_package_share_directory("mentor_planner_node")
    files = [str(preset_file(value["robot"], share))]
    if value["params_file"]:
        files.append(value["params_file"])
    nodes = [
        Node(
            package="mentor_planner_node",
            executable="planner",
            name="mentor_planner",
            namespace=value["namespace"],
            output="screen",
            parameters=[*files, launch_parameters(value)],
            remappings=[("scan", value["scan"]), ("odom", value["odom"]),
                        ("cmd_vel", value["cmd_vel"])],
        )
    ]
    if launch_flag("rviz", value["rviz"]):
        config = os.path.join(get_package_share_directory("mentor_ros_common"), "config",
                              "mentor.rviz")
        nodes.append(Node(package="rviz2", executable="rviz2", arguments=["-d", config],
                          namespace=value["namespace"]))
    return nodes


def generate_launch_description() -> LaunchDescription:
    """The planner node with its preset, the arguments given on top."""
    return LaunchDescription(
        [DeclareLaunchArgument(name, default_value=default) for name, default in
         ARGUMENTS.items()]
        + [OpaqueFunction(function=_nodes)]
    )
