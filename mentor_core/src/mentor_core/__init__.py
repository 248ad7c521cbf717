"""MENTOR: multi-criteria evolution of neural-network topologies for robot path planning.

A pure-Python library (never imports rclpy or ROS messages), in wings named after the paper's
and the robot stack's parts; ``docs/architecture.md`` gives the rules, lowest layer first:

* ``errors``, ``atomic`` -- the foundation every wing may use;
* ``evolution`` -- NEAT genomes and operators, NSGA-II ranking, MENTOR's selection, the loop
  (knows nothing of robots) | ``sim`` -- robots, worlds, sensors, collisions, the batched
  engine, network inputs and actions (knows nothing of evolution);
* ``objectives`` -- the paper's criteria F, G and complexity | ``files`` -- genome files,
  checkpoints, rosbag2 bags | ``navigation`` -- occupancy grids and ROS maps, global plans
  for a robot's footprint, following a path;
* ``controller`` -- the decision chain and its stages (view corridor, gain on the turn,
  rotation shim, collision guard, ...), deployments as data, the batched episodes;
* ``training`` -- problem, trainers, evaluation backends, assessment | ``runtime`` -- what the
  ROS nodes run: reference simulator, scenario plans, the planner, recording;
* ``report`` -- figures, tables and the Markdown report;
* ``cli`` -- the ``mentor-*`` commands.

The names below are the public API: the node packages and users import them from
``mentor_core`` itself (``from mentor_core import GenomePlanner``); each is loaded on first
use, so importing one wing does not import the others.
"""

from __future__ import annotations

import ast
import importlib
from pathlib import Path
from typing import TYPE_CHECKING, Any

__version__ = "0.1.0"


def _exports() -> dict[str, str]:
    """Public name -> module that defines it, read from the imports below (declared once)."""
    tree = ast.parse(Path(__file__).read_text(encoding="utf-8"))
    guard = next(
        node
        for node in tree.body
        if isinstance(node, ast.If) and ast.unparse(node.test) == "TYPE_CHECKING"
    )
    return {
        alias.asname or alias.name: node.module
        for node in guard.body
        if isinstance(node, ast.ImportFrom) and node.module
        for alias in node.names
    }


_EXPORTS = _exports()
__all__ = ["__version__", *_EXPORTS]


def __getattr__(name: str) -> Any:
    """Load a public name's module on first use (PEP 562)."""
    module = _EXPORTS.get(name)
    if module is None:
        raise AttributeError(f"module 'mentor_core' has no attribute {name!r}")
    value = getattr(importlib.import_module(module), name)
    globals()[name] = value  # later lookups skip this function
    return value


def __dir__() -> list[str]:
    return sorted(__all__)


# The public API, by wing: every name a user or a node package imports from ``mentor_core``.
# Type checkers read these imports; at run time each is loaded on first use (``__getattr__``).
if TYPE_CHECKING:
    # controller
    from mentor_core.controller.deployment import Deployed as Deployed
    from mentor_core.controller.deployment import Deployment as Deployment
    from mentor_core.controller.deployment import load_deployment as load_deployment
    from mentor_core.controller.episodes import run_episodes as run_episodes
    from mentor_core.controller.pipeline import DecisionChain as DecisionChain
    from mentor_core.controller.stage import Stage as Stage
    from mentor_core.controller.stage import StageRun as StageRun

    # foundation
    from mentor_core.errors import (
        ConfigError as ConfigError,
    )
    from mentor_core.errors import (
        FileFormatError as FileFormatError,
    )
    from mentor_core.errors import (
        MentorError as MentorError,
    )
    from mentor_core.evolution.config import EvolutionConfig as EvolutionConfig

    # evolution
    from mentor_core.evolution.genome import Genome as Genome
    from mentor_core.evolution.innovation import InnovationTracker as InnovationTracker
    from mentor_core.evolution.loop import Evolution as Evolution
    from mentor_core.evolution.network import FeedForwardNetwork as FeedForwardNetwork
    from mentor_core.evolution.ranking import (
        crowding_distance as crowding_distance,
    )
    from mentor_core.evolution.ranking import (
        non_dominated_ranks as non_dominated_ranks,
    )
    from mentor_core.evolution.ranking import (
        scalar_fitness as scalar_fitness,
    )
    from mentor_core.files.bags import (
        ARENA_LINE_WIDTH as ARENA_LINE_WIDTH,
    )
    from mentor_core.files.bags import (
        BAG_VERSION as BAG_VERSION,
    )
    from mentor_core.files.bags import (
        EVENT_FORMAT as EVENT_FORMAT,
    )
    from mentor_core.files.bags import (
        EVENT_KINDS as EVENT_KINDS,
    )
    from mentor_core.files.bags import (
        EventKind as EventKind,
    )
    from mentor_core.files.bags import (
        arena_outline as arena_outline,
    )
    from mentor_core.files.bags import (
        box_markers as box_markers,
    )
    from mentor_core.files.bags import (
        read_episode_bag as read_episode_bag,
    )
    from mentor_core.files.bags import (
        read_scenario_bag as read_scenario_bag,
    )
    from mentor_core.files.bags import (
        scan_geometry as scan_geometry,
    )
    from mentor_core.files.bags import (
        write_episode_bag as write_episode_bag,
    )
    from mentor_core.files.bags import (
        write_scenario_bag as write_scenario_bag,
    )
    from mentor_core.files.genome_file import (
        load_genome as load_genome,
    )
    from mentor_core.files.genome_file import (
        load_genome_and_metadata as load_genome_and_metadata,
    )

    # files
    from mentor_core.files.genome_file import (
        save_genome as save_genome,
    )
    from mentor_core.navigation.grid import MAX_CELLS as MAX_CELLS

    # navigation
    from mentor_core.navigation.grid import (
        OccupancyGrid as OccupancyGrid,
    )
    from mentor_core.navigation.grid import (
        world_grid as world_grid,
    )
    from mentor_core.navigation.grid_planner import GridPlanner as GridPlanner
    from mentor_core.navigation.guide import (
        GuideConfig as GuideConfig,
    )
    from mentor_core.navigation.guide import (
        PathGuide as PathGuide,
    )
    from mentor_core.navigation.guide import (
        guide_config as guide_config,
    )
    from mentor_core.navigation.map_file import load_map as load_map
    from mentor_core.navigation.map_file import save_map as save_map
    from mentor_core.navigation.map_world import load_world_file as load_world_file
    from mentor_core.navigation.plan_worker import PlanResult as PlanResult
    from mentor_core.navigation.plan_worker import ThreadPlans as ThreadPlans
    from mentor_core.navigation.scan_map import scan_guide_config as scan_guide_config
    from mentor_core.navigation.scan_map import warm_up_scan_map as warm_up_scan_map
    from mentor_core.objectives.complexity import flops_ratio as flops_ratio
    from mentor_core.objectives.experience import experience_gain as experience_gain

    # objectives
    from mentor_core.objectives.performance import performance as performance

    # report
    from mentor_core.report.markdown import write_report as write_report
    from mentor_core.runtime.decision_gate import (
        DecisionGate as DecisionGate,
    )
    from mentor_core.runtime.footprint import footprint_box as footprint_box
    from mentor_core.runtime.goal_intake import (
        Bounds as Bounds,
    )
    from mentor_core.runtime.goal_intake import (
        bounds_fault as bounds_fault,
    )
    from mentor_core.runtime.goal_intake import (
        bounds_in as bounds_in,
    )
    from mentor_core.runtime.goal_intake import (
        same_goal as same_goal,
    )
    from mentor_core.runtime.goal_tracker import GoalRules as GoalRules
    from mentor_core.runtime.goal_tracker import GoalStep as GoalStep
    from mentor_core.runtime.goal_tracker import GoalTracker as GoalTracker
    from mentor_core.runtime.goal_tracker import goal_rules as goal_rules
    from mentor_core.runtime.guided_planner import (
        GuidedPlanner as GuidedPlanner,
    )
    from mentor_core.runtime.guided_planner import (
        ScanGuidedPlanner as ScanGuidedPlanner,
    )
    from mentor_core.runtime.guided_planner import (
        wire_grid as wire_grid,
    )
    from mentor_core.runtime.lockstep import (
        CommandBarrier as CommandBarrier,
    )
    from mentor_core.runtime.lockstep import (
        LatestCommands as LatestCommands,
    )

    # runtime
    from mentor_core.runtime.planner import (
        GenomePlanner as GenomePlanner,
    )
    from mentor_core.runtime.planner import (
        deployed_genome as deployed_genome,
    )
    from mentor_core.runtime.planner import (
        genome_control_period as genome_control_period,
    )
    from mentor_core.runtime.planner_frames import PlannerFrames as PlannerFrames
    from mentor_core.runtime.recording import EpisodeRecorder as EpisodeRecorder
    from mentor_core.runtime.robot_graph import (
        RobotPlanner as RobotPlanner,
    )
    from mentor_core.runtime.robot_graph import (
        parse_genomes as parse_genomes,
    )
    from mentor_core.runtime.robot_graph import (
        planner_period as planner_period,
    )
    from mentor_core.runtime.robot_graph import (
        robot_planners as robot_planners,
    )
    from mentor_core.runtime.robot_graph import (
        simulator_period as simulator_period,
    )
    from mentor_core.runtime.ros_arguments import (
        MIN_PERIOD as MIN_PERIOD,
    )
    from mentor_core.runtime.ros_arguments import (
        launch_count as launch_count,
    )
    from mentor_core.runtime.ros_arguments import (
        launch_flag as launch_flag,
    )
    from mentor_core.runtime.ros_arguments import (
        launch_number as launch_number,
    )
    from mentor_core.runtime.ros_arguments import (
        launch_numbers as launch_numbers,
    )
    from mentor_core.runtime.ros_arguments import (
        parameter_fault as parameter_fault,
    )
    from mentor_core.runtime.ros_arguments import (
        period_fault as period_fault,
    )
    from mentor_core.runtime.scenario_plan import (
        ScenarioPlan as ScenarioPlan,
    )
    from mentor_core.runtime.scenario_plan import (
        load_scenario_source as load_scenario_source,
    )
    from mentor_core.runtime.scenario_plan import (
        source_map as source_map,
    )
    from mentor_core.runtime.session_config import ContinuousConfig as ContinuousConfig
    from mentor_core.runtime.sim_session import (
        Outcome as Outcome,
    )
    from mentor_core.runtime.sim_session import (
        SessionConfig as SessionConfig,
    )
    from mentor_core.runtime.sim_session import (
        SessionPort as SessionPort,
    )
    from mentor_core.runtime.sim_session import (
        SimSession as SimSession,
    )
    from mentor_core.runtime.simulator import (
        Event as Event,
    )
    from mentor_core.runtime.simulator import (
        ReferenceSimulator as ReferenceSimulator,
    )
    from mentor_core.runtime.streamed_robot import StreamedRobot as StreamedRobot
    from mentor_core.runtime.streamed_robot import StreamSpec as StreamSpec
    from mentor_core.runtime.tf_buffer import TfBuffer as TfBuffer
    from mentor_core.runtime.velocity_limits import (
        VelocityLimits as VelocityLimits,
    )
    from mentor_core.runtime.velocity_limits import (
        limited_velocity as limited_velocity,
    )
    from mentor_core.runtime.wiring import Wiring as Wiring
    from mentor_core.sim.frames import (
        MAP_FRAME as MAP_FRAME,
    )
    from mentor_core.sim.frames import (
        ODOM_FRAME as ODOM_FRAME,
    )
    from mentor_core.sim.frames import (
        quaternion_to_yaw as quaternion_to_yaw,
    )
    from mentor_core.sim.frames import (
        yaw_to_quaternion as yaw_to_quaternion,
    )
    from mentor_core.sim.lidar import LidarSpec as LidarSpec
    from mentor_core.sim.observation import (
        action_from_twist as action_from_twist,
    )
    from mentor_core.sim.observation import (
        network_inputs as network_inputs,
    )
    from mentor_core.sim.observation import (
        twist_from_action as twist_from_action,
    )
    from mentor_core.sim.robot_description import (
        BASE_LINK as BASE_LINK,
    )
    from mentor_core.sim.robot_description import (
        LIDAR_LINK as LIDAR_LINK,
    )
    from mentor_core.sim.robot_description import (
        FrameLink as FrameLink,
    )
    from mentor_core.sim.robot_description import (
        frame_id as frame_id,
    )
    from mentor_core.sim.robot_description import (
        robot_links as robot_links,
    )
    from mentor_core.sim.robot_description import (
        robot_urdf as robot_urdf,
    )

    # sim
    from mentor_core.sim.robots import (
        RobotProfile as RobotProfile,
    )
    from mentor_core.sim.robots import (
        get_profile as get_profile,
    )
    from mentor_core.sim.robots import (
        load_profiles as load_profiles,
    )
    from mentor_core.sim.scan_adapter import (
        LaserScanData as LaserScanData,
    )
    from mentor_core.sim.scan_adapter import (
        LidarMount as LidarMount,
    )
    from mentor_core.sim.scan_adapter import (
        MountedScan as MountedScan,
    )
    from mentor_core.sim.scan_adapter import (
        ScanReadings as ScanReadings,
    )
    from mentor_core.sim.scan_adapter import (
        readings_fault as readings_fault,
    )
    from mentor_core.sim.scan_adapter import (
        readings_from_scan as readings_from_scan,
    )
    from mentor_core.sim.transforms import (
        FrameTree as FrameTree,
    )
    from mentor_core.sim.transforms import (
        Transform2D as Transform2D,
    )
    from mentor_core.sim.transforms import (
        planar_transform as planar_transform,
    )
    from mentor_core.sim.world import (
        Scenario as Scenario,
    )
    from mentor_core.sim.world import (
        World as World,
    )
    from mentor_core.sim.world import (
        load_world as load_world,
    )
    from mentor_core.sim.world import (
        save_world as save_world,
    )
    from mentor_core.training.assessment import assess as assess

    # training
    from mentor_core.training.config import (
        TrainerConfig as TrainerConfig,
    )
    from mentor_core.training.config import (
        load_config_file as load_config_file,
    )
    from mentor_core.training.problem import NavigationProblem as NavigationProblem
    from mentor_core.training.trainer import train as train
    from mentor_core.validation import config_dataclass as config_dataclass
