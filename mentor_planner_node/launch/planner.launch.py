"""Launch one MENTOR planner on a real robot (ROS 2 Jazzy with ``launch`` installed).

    ros2 launch mentor_planner_node planner.launch.py genome:=best_genome.json scan:=/scan
    ros2 launch mentor_planner_node planner.launch.py genome:=g.json collision_guard:=true

The planner reads the robot's lidar (``scan``), odometry (``odom``) and goals (``/goal_pose``,
RViz's "2D Goal Pose"), takes frames from TF (the lidar's mount, ``map -> odom``) and decides
every control period (``decide_on_timer``), publishing ``cmd_vel``.
"""

from __future__ import annotations

from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node
from launch_ros.parameter_descriptions import ParameterValue

ARGUMENTS = {
    "genome": "best_genome.json",
    "profile": "ugv",
    "scan": "/scan",
    "odom": "/odom",
    "cmd_vel": "/cmd_vel",
    "use_sim_time": "false",
    "collision_guard": "false",
}


def generate_launch_description() -> LaunchDescription:
    """The planner node with its topics remapped to the robot's."""
    config = {name: LaunchConfiguration(name) for name in ARGUMENTS}
    planner = Node(
        package="mentor_planner_node",
        executable="planner",
        name="mentor_planner",
        output="screen",
        parameters=[{
            "genome": config["genome"],
            "profile": config["profile"],
            "use_sim_time": ParameterValue(config["use_sim_time"], value_type=bool),
            "collision_guard": ParameterValue(config["collision_guard"], value_type=bool),
            "decide_on_timer": True,
            "scan_kind": "lidar",
        }],
        remappings=[
            ("scan", config["scan"]),
            ("odom", config["odom"]),
            ("cmd_vel", config["cmd_vel"]),
        ],
    )
    return LaunchDescription(
        [DeclareLaunchArgument(name, default_value=default) for name, default in
         ARGUMENTS.items()]
        + [planner]
    )
