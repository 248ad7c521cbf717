"""Launch one MENTOR planner on a real robot (ROS 2 Jazzy with ``launch`` installed).

    ros2 launch mentor_planner_node planner.launch.py genome:=best_genome.json scan:=/scan
    ros2 launch mentor_planner_node planner.launch.py genome:=planners/ugv-paper-dual-s1.json \
        deployment:=shipped   # as the shipped planners run
    ros2 launch mentor_planner_node planner.launch.py genome:=planners/swarm-paper-dual-s1.json \
        profile:=swarm deployment:=shipped scan_map_size:=20.0 scan_map_origin:="[-10.0, -10.0]"
    ros2 launch mentor_planner_node planner.launch.py genome:=g.json deployment:=my.yaml

The planner reads the robot's lidar (``scan``), odometry (``odom``) and goals (``/goal_pose``,
RViz's "2D Goal Pose"), takes frames from TF (the lidar's mount, ``map -> odom``) and decides
every control period (``decide_on_timer``), publishing ``cmd_vel`` (again at ``repeat_rate``
between decisions, for bases that stop on a quiet ``cmd_vel``). It runs as ``deployment``
(``none``: as trained, ``shipped``: as ``mentor-bench --deployment shipped`` scores the shipped
planners, or a deployment file; ``docs/deployment.md``); a deployment with a scan map plans on
a map of its own scans, a square of ``scan_map_size`` m from ``scan_map_origin`` in the
odometry frame (``docs/ros.md``, "Global plans").
"""

from __future__ import annotations

from launch import LaunchContext, LaunchDescription
from launch.actions import DeclareLaunchArgument, OpaqueFunction
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
    "deployment": "none",
    "scan_map_size": "20.0",
    "scan_map_origin": "[-10.0, -10.0]",
    "scan_map_keep": "true",
    "repeat_rate": "10.0",
}


def _nodes(context: LaunchContext) -> list[Node]:
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
            "deployment": config["deployment"],
            "scan_map_size": ParameterValue(config["scan_map_size"], value_type=float),
            # no value_type: the string is read as YAML, a list of floats
            "scan_map_origin": ParameterValue(config["scan_map_origin"]),
            "scan_map_keep": ParameterValue(config["scan_map_keep"], value_type=bool),
            "decide_on_timer": True,
            # the base stops on a quiet cmd_vel (diff_drive_controller: 0.5 s), a planner
            # decides every 0.5-1 s: its command goes out again at this rate in between
            "repeat_rate": ParameterValue(config["repeat_rate"], value_type=float),
            "scan_kind": "lidar",
        }],
        remappings=[
            ("scan", config["scan"]),
            ("odom", config["odom"]),
            ("cmd_vel", config["cmd_vel"]),
        ],
    )
    return [planner]


def generate_launch_description() -> LaunchDescription:
    """The planner node with its topics remapped to the robot's."""
    return LaunchDescription(
        [DeclareLaunchArgument(name, default_value=default) for name, default in
         ARGUMENTS.items()]
        + [OpaqueFunction(function=_nodes)]
    )
