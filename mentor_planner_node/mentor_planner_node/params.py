"""The planner node's parameters: declared (descriptions, ranges), then checked.

All are read-only but ``goal_radius``, which may change while the node runs
(:func:`check_goal_radius`). See ``docs/ros.md`` for the table.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ament_index_python.packages import PackageNotFoundError, get_package_share_directory
from rcl_interfaces.msg import FloatingPointRange, ParameterDescriptor
from rclpy.node import Node
from rclpy.parameter import Parameter

from mentor_core import (
    MAP_FRAME,
    MIN_PERIOD,
    Deployed,
    Deployment,
    Genome,
    GoalRules,
    LidarMount,
    MentorError,
    RobotProfile,
    Transform2D,
    VelocityLimits,
    deployed_genome,
    footprint_box,
    get_profile,
    goal_rules,
    load_deployment,
    period_fault,
)

PACKAGE = "mentor_planner_node"
#: periods without an answer before the watchdog fires, when ``stale_timeout`` is 0
STALE_PERIODS = 3.0
SCAN_KINDS = ("auto", "sensors", "lidar")
#: Hz at which a planner deciding on its timer repeats its cmd_vel (bases time out at 0.5 s)
REPEAT_RATE = 10.0
#: s, Nav2's progress checker's default movement_time_allowance
MOVEMENT_TIME_S = 10.0


class PlannerSetupError(MentorError):
    """A parameter of the planner node is invalid (one line)."""


@dataclass(frozen=True)
class PlannerParameters:
    """The checked parameters (``docs/ros.md``)."""

    genome: str
    profile: RobotProfile
    deployment: Deployment
    #: the genome (None without one) and how it runs as its deployment
    loaded: Genome | None
    deployed: Deployed | None
    control_period: float
    stale_timeout: float
    sync_tolerance: float
    goal_radius: float
    decide_on_timer: bool
    scan_kind: str
    ray_width: float
    lidar_mount: LidarMount
    map_to_odom: Transform2D
    map_frame: str
    goal_pose_topic: str
    use_tf: bool
    repeat_rate: float = REPEAT_RATE
    limits: VelocityLimits = field(default_factory=VelocityLimits)
    cmd_vel_stamped: bool = False
    yaw_goal_tolerance: float = 0.0
    #: the progress checker's movement (m; 0: half the goal radius) and time (s; 0: off)
    required_movement_radius: float = 0.0
    movement_time_allowance: float = MOVEMENT_TIME_S
    time_limit: float = 0.0

    def goal_rules(self, radius: float) -> GoalRules:
        """When a goal of the goal radius ``radius`` is reached or given up."""
        return goal_rules(self.profile, radius, self.limits, self.control_period,
                          yaw_tolerance=self.yaw_goal_tolerance,
                          movement_radius=self.required_movement_radius,
                          movement_time=self.movement_time_allowance,
                          time_limit=self.time_limit)  # fmt: skip


def _descriptor(text: str, low: float | None = None, runtime: bool = False) -> Any:
    extra: dict[str, Any] = {}
    if low is not None:
        extra["floating_point_range"] = [FloatingPointRange(from_value=low, to_value=1e9)]
    return ParameterDescriptor(description=text, read_only=not runtime, **extra)


def _declarations() -> list[tuple[str, Any, Any]]:
    return [
        ("genome", "", _descriptor("genome JSON file ('' : answer zero Twists)")),
        ("profile", "ugv", _descriptor("robot profile (robots.yaml)")),
        ("deployment", "none",
         _descriptor("how the genome runs: 'none' (as trained), 'shipped' (the shipped "
                     "planners' deployment of the profile) or a deployment YAML file")),
        ("deployment_set", Parameter.Type.STRING_ARRAY,
         _descriptor("KEY=VALUE changes of the deployment, as mentor-bench --set "
                     "(['stages.turn_gain.gain=1'])")),
        (
            "stale_timeout",
            0.0,
            _descriptor(
                "wall s (steady clock) without an answered observation before a zero Twist "
                f"(0: {STALE_PERIODS:g} control periods)",
                low=0.0,
            ),
        ),
        (
            "sync_tolerance",
            0.1,
            _descriptor("s a scan's stamp may lie past the newest (or before the oldest) "
                        "odometry and take its pose; between two, the pose is interpolated",
                        low=0.0),
        ),
        (
            "goal_radius",
            0.0,
            _descriptor(
                "m, within it a goal is reached: zero Twist, goal done (0: the profile's); "
                "changes at run time",
                low=0.0,
                runtime=True,
            ),
        ),
        (
            "decide_on_timer",
            False,
            _descriptor("decide every control period with the latest data (continuous mode) "
                        "instead of answering each new observation (lockstep)"),
        ),
        (
            "repeat_rate",
            REPEAT_RATE,
            _descriptor("Hz: with decide_on_timer, send the latest cmd_vel again at this rate "
                        "between decisions, for a base that stops when cmd_vel goes quiet "
                        "(the simulator's command_timeout; 0: only at decisions)", low=0.0),
        ),
        ("scan_kind", "auto", _descriptor("auto | sensors (the simulator's) | lidar (any)")),
        ("ray_width", 0.0, _descriptor("rad, field of view of a single-ray sensor", low=0.0)),
        (
            "lidar_mount",
            [0.0, 0.0, 0.0],
            _descriptor("pose [x, y, yaw] of the scan's frame on the body, where TF is "
                        "not installed"),
        ),
        (
            "map_to_odom",
            [0.0, 0.0, 0.0],
            _descriptor("pose [x, y, yaw] of the odometry frame in map, where TF is not "
                        "installed"),
        ),
        ("map_frame", MAP_FRAME, _descriptor("the map's frame (goals without a frame)")),
        ("goal_pose_topic", "/goal_pose", _descriptor("goals of RViz/Foxglove ('' : none)")),
        ("use_tf", True, _descriptor("take frames from /tf where tf2_ros is installed")),
        ("max_vel_x", 0.0, _descriptor("m/s, the robot's top speed: both speeds scaled "
                                       "together to it, the arc kept (0: none)", low=0.0)),
        ("max_vel_theta", 0.0, _descriptor("rad/s, the robot's top turn rate, as max_vel_x "
                                           "(0: none)", low=0.0)),
        ("acc_lim_x", 0.0, _descriptor("m/s^2, largest change of the speed per second "
                                       "(0: none)", low=0.0)),
        ("acc_lim_theta", 0.0, _descriptor("rad/s^2, largest change of the turn rate per "
                                           "second (0: none)", low=0.0)),
        ("footprint", "", _descriptor("the robot's outline in its base frame, as Nav2's: "
                                      "'[[x, y], [x, y], ...]' m; the box holding it is kept "
                                      "clear ('' : robot_radius, or the profile's body)")),
        ("robot_radius", 0.0, _descriptor("m, a round robot's radius where footprint is '' "
                                          "(0: the profile's body)", low=0.0)),
        ("yaw_goal_tolerance", 0.0, _descriptor("rad: a goal's heading is turned to, in place, "
                                                "within this (0: headings ignored)", low=0.0)),
        ("required_movement_radius", 0.0,
         _descriptor("m the robot must move within movement_time_allowance, or the goal is "
                     "aborted (Nav2's progress checker; 0: half the goal radius)", low=0.0)),
        ("movement_time_allowance", MOVEMENT_TIME_S,
         _descriptor("s allowed to move required_movement_radius (0: no progress check)",
                     low=0.0)),
        ("time_limit", 0.0, _descriptor("s a goal may take before it is aborted (0: from its "
                                        "distance at the rated speed, docs/ros.md)", low=0.0)),
        ("cmd_vel_stamped", False, _descriptor("publish geometry_msgs/TwistStamped on cmd_vel "
                                               "(Jazzy's diff_drive_controller) instead of "
                                               "Twist")),
    ]


def resolve_genome(genome: str) -> str:
    """``genome`` as given where that file exists (or it is ''), else the shipped planner of
    that name installed with the package (``ugv-paper-dual-s1`` or
    ``planners/ugv-paper-dual-s1.json`` from any working directory), else as given (its
    loading then names the missing file)."""
    if not genome or Path(genome).exists():
        return genome
    try:
        share = Path(get_package_share_directory(PACKAGE))
    except (PackageNotFoundError, OSError):  # not installed with colcon: paths as given
        return genome
    name = Path(genome).name
    installed = share / "planners" / (name if name.endswith(".json") else name + ".json")
    return str(installed) if installed.is_file() else genome


def _transform(values: Mapping[str, Any], key: str) -> Transform2D:
    try:
        return Transform2D.of([float(v) for v in values[key]])
    except (TypeError, ValueError) as err:
        raise PlannerSetupError(f"{key}: {err}") from None


def check_parameters(values: Mapping[str, Any]) -> PlannerParameters:
    """The parameters ``values`` (name -> value, all) checked, the genome loaded as its
    deployment runs it (which sets the control period: the profile's without a genome).
    PlannerSetupError, a ConfigError for an unknown profile or a bad deployment, a
    FileFormatError for a bad genome."""
    profile = get_profile(str(values["profile"]))
    settings = [str(v) for v in values.get("deployment_set") or []]
    deployment = load_deployment(str(values["deployment"]), profile.name, settings,
                                 "deployment_set")[0]
    genome = resolve_genome(str(values["genome"]))
    try:
        box = footprint_box(str(values["footprint"]), float(values["robot_radius"]))
    except ValueError as err:
        raise PlannerSetupError(str(err)) from None
    loaded: Genome | None = None
    deployed: Deployed | None = None
    if genome:
        loaded, deployed = deployed_genome(genome, profile.name, deployment, box)
    period = profile.control_period if deployed is None else deployed.profile.control_period
    stale = float(values["stale_timeout"]) or STALE_PERIODS * period
    if stale <= period:
        raise PlannerSetupError(
            f"stale_timeout: {stale} s must exceed the control period {period} s"
        )
    repeat = float(values["repeat_rate"])
    if not (repeat >= 0.0 and repeat < float("inf")):
        raise PlannerSetupError(f"repeat_rate: {repeat} is not a rate >= 0 Hz")
    for name, seconds in (("repeat_rate", 1.0 / repeat if repeat else MIN_PERIOD),
                          ("control period", period)):
        fault = period_fault(name, seconds)
        if fault:
            raise PlannerSetupError(fault)
    try:
        limits = VelocityLimits(**{k: float(values[k]) for k in
                                   ("max_vel_x", "max_vel_theta", "acc_lim_x", "acc_lim_theta")})
    except ValueError as err:
        raise PlannerSetupError(str(err)) from None
    kind = str(values["scan_kind"])
    if kind not in SCAN_KINDS:
        raise PlannerSetupError(f"scan_kind: {kind!r} is not one of {', '.join(SCAN_KINDS)}")
    return PlannerParameters(
        genome=genome,
        profile=profile,
        deployment=deployment,
        loaded=loaded,
        deployed=deployed,
        control_period=period,
        stale_timeout=stale,
        sync_tolerance=float(values["sync_tolerance"]),
        goal_radius=float(values["goal_radius"]) or profile.goal_radius,
        decide_on_timer=bool(values["decide_on_timer"]),
        scan_kind=kind,
        ray_width=float(values["ray_width"]),
        lidar_mount=LidarMount(_transform(values, "lidar_mount")),
        map_to_odom=_transform(values, "map_to_odom"),
        map_frame=str(values["map_frame"]) or MAP_FRAME,
        goal_pose_topic=str(values["goal_pose_topic"]),
        use_tf=bool(values["use_tf"]),
        repeat_rate=repeat,
        limits=limits,
        cmd_vel_stamped=bool(values["cmd_vel_stamped"]),
        yaw_goal_tolerance=float(values["yaw_goal_tolerance"]),
        required_movement_radius=float(values["required_movement_radius"]),
        movement_time_allowance=float(values["movement_time_allowance"]),
        time_limit=float(values["time_limit"]),
    )


def declare_parameters(node: Node) -> PlannerParameters:
    """Declare the node's parameters and check them."""
    declared = node.declare_parameters("", _declarations())
    return check_parameters({p.name: p.value for p in declared})


def check_goal_radius(value: Any, profile: RobotProfile) -> tuple[float, str]:
    """A run-time goal radius (0: the profile's) and why it is refused ('' : fine)."""
    radius = float(value)
    if radius < 0.0:
        return radius, "goal_radius must be >= 0 m"
    return (radius or profile.goal_radius), ""
