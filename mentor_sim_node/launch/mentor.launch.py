"""Launch the MENTOR simulator and one planner per robot (ROS 2 Jazzy with ``launch`` installed).

    ros2 launch mentor_sim_node mentor.launch.py genome:=bags/regression/ugv_reference_genome.json
    ros2 launch mentor_sim_node mentor.launch.py robots:=ugv_0,ugv_1 lidar_rays:=360 rviz:=true
    ros2 launch mentor_sim_node mentor.launch.py profiles:=ugv,swarm continuous:=true \
        genomes:=ugv=planners/ugv-paper-dual-s1.json,swarm=planners/swarm-paper-dual-s1.json \
        deployment:=shipped

Arguments: ``robots`` (comma-separated namespaces), ``profile`` (of every robot), ``genome``
(of every robot); or ``profiles`` (comma-separated, one robot each, named ``<profile>_<i>``)
with ``genomes`` (comma-separated ``PROFILE=FILE``; a profile not named plans with its
regression reference genome); ``deployment`` (how every planner runs: ``none``, ``shipped`` as
``mentor-bench --deployment shipped`` runs the shipped planners, or a deployment file),
``world`` (a world file; '' : the training world), ``lidar_rays`` (> 0: the
planners read the simulated lidar instead of the per-sensor scan), ``continuous`` (the
simulator runs like Gazebo, the planners decide on their own timers), ``real_time_factor``,
``wait_for_goals`` (robots wait for goals from RViz's "2D Goal Pose" tool), ``rviz`` (start
RViz2 with this package's config). The pip-only install has no ``launch``: use the ``demo``
executable there.
"""

from __future__ import annotations

import os

from ament_index_python.packages import get_package_share_directory
from launch import LaunchContext, LaunchDescription
from launch.actions import DeclareLaunchArgument, OpaqueFunction
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node

from mentor_core import (
    RobotPlanner,
    launch_count,
    launch_flag,
    launch_number,
    parse_genomes,
    robot_planners,
    simulator_period,
)

ARGUMENTS = {
    "robots": "robot_0",
    "profile": "ugv",
    "genome": "bags/regression/ugv_reference_genome.json",
    "profiles": "",
    "genomes": "",
    "deployment": "none",
    "world": "",
    "lidar_rays": "0",
    "continuous": "false",
    "real_time_factor": "0.0",
    "wait_for_goals": "false",
    "rviz": "false",
}


def _items(text: str) -> list[str]:
    return [item.strip() for item in text.split(",") if item.strip()]


def _planners(value: dict[str, str], continuous: bool) -> list[RobotPlanner]:
    """The robots and their planners: of ``profiles``, else ``robots`` all of ``profile``."""
    deployment = value["deployment"] or "none"
    if value["profiles"]:
        return robot_planners(_items(value["profiles"]), parse_genomes(_items(value["genomes"])),
                              deployment=deployment, continuous=continuous)
    names = _items(value["robots"])
    genome = {value["profile"]: value["genome"]} if value["genome"] else {}
    return robot_planners([value["profile"]] * len(names), genome, names=names,
                          deployment=deployment, continuous=continuous)


def _nodes(context: LaunchContext) -> list[Node]:
    value = {name: LaunchConfiguration(name).perform(context) for name in ARGUMENTS}
    rays = launch_count("lidar_rays", value["lidar_rays"])
    continuous = launch_flag("continuous", value["continuous"])
    rate = launch_number("real_time_factor", value["real_time_factor"])
    rate = rate or (1.0 if continuous else 0.0)
    planners = _planners(value, continuous)
    nodes = [
        Node(
            package="mentor_sim_node",
            executable="sim",
            name="mentor_sim",
            output="screen",
            parameters=[{
                "robots": [p.namespace for p in planners],
                "profiles": [p.profile for p in planners],
                "world": value["world"],
                "lidar_rays": rays,
                "continuous": continuous,
                "real_time_factor": rate,
                "wait_for_goals": launch_flag("wait_for_goals", value["wait_for_goals"]),
                # the period the genomes decide at (their metadata); continuous: the shortest
                "control_period": simulator_period(planners, continuous, "continuous:=true"),
            }],
        )
    ]
    for planner in planners:
        nodes.append(
            Node(
                package="mentor_planner_node",
                executable="planner",
                name="mentor_planner",
                namespace=planner.namespace,
                output="screen",
                parameters=[{**planner.parameters, "use_sim_time": True}],
                remappings=[("scan", "lidar/scan")] if rays > 0 else [],
            )
        )
    if launch_flag("rviz", value["rviz"]):
        config = os.path.join(get_package_share_directory("mentor_ros_common"), "config",
                              "mentor.rviz")
        # its robot topics are relative: it shows the first robot, in whose namespace it runs
        nodes.append(Node(package="rviz2", executable="rviz2", arguments=["-d", config],
                          namespace=planners[0].namespace,
                          parameters=[{"use_sim_time": True}]))
    return nodes


def generate_launch_description() -> LaunchDescription:
    """The launch description: the arguments, then the nodes they ask for."""
    return LaunchDescription(
        [DeclareLaunchArgument(name, default_value=default) for name, default in
         ARGUMENTS.items()]
        + [OpaqueFunction(function=_nodes)]
    )
