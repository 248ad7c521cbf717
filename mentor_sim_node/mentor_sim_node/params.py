"""The simulator node's parameters: declared (descriptions, ranges), then checked.

:func:`declare_parameters` declares them on the node and returns them checked
(:func:`check_parameters`, which needs no node) as :class:`SimParameters`; then it declares
every robot's mount layout (``<ns>.profile``, ``<ns>.sensor_x``, ...), for tools that need
the sensor geometry a LaserScan cannot carry. All are read-only but :data:`RUNTIME`
(``real_time_factor``, ``goal_radius``), which :func:`check_runtime` checks when they are set
on the running node. See ``docs/ros.md`` for the table.
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from dataclasses import dataclass, replace
from typing import Any

from rcl_interfaces.msg import FloatingPointRange, IntegerRange, ParameterDescriptor
from rclpy.node import Node

from mentor_core import (
    MIN_PERIOD,
    ContinuousConfig,
    LidarSpec,
    MentorError,
    RobotProfile,
    SessionConfig,
    Transform2D,
    Wiring,
    get_profile,
    period_fault,
)

#: parameters that may change while the node runs
RUNTIME = ("real_time_factor", "goal_radius")


class SimSetupError(MentorError):
    """A parameter of the simulator node is invalid (one line)."""


@dataclass(frozen=True)
class SimParameters:
    """The checked parameters: the scenario source and the session settings."""

    world: str
    scenario_bag: str
    seed: int
    session: SessionConfig
    goal_pose_topic: str
    map_yaml: str = ""
    map_resolution: float = 0.05


def _descriptor(text: str, runtime: bool = False, **extra: Any) -> ParameterDescriptor:
    return ParameterDescriptor(description=text, read_only=not runtime, **extra)


def _at_least(low: float) -> list[FloatingPointRange]:
    return [FloatingPointRange(from_value=low, to_value=1e9, step=0.0)]


def _count() -> list[IntegerRange]:
    return [IntegerRange(from_value=0, to_value=1_000_000, step=1)]


def _declarations() -> list[tuple[str, Any, ParameterDescriptor]]:
    return [
        ("robots", ["robot_0"], _descriptor("robot namespaces, one robot each")),
        (
            "profiles",
            ["ugv"],
            _descriptor("robot profile per robot (one entry: the same for all)"),
        ),
        ("world", "", _descriptor("world file (YAML) with scenarios")),
        ("scenario_bag", "", _descriptor("scenario bag (instead of a world file)")),
        ("seed", 0, _descriptor("seed of the training scenarios used without a file")),
        (
            "first_scenario",
            0,
            _descriptor("offset of the first scenario handed out", integer_range=_count()),
        ),
        (
            "episodes",
            0,
            _descriptor("episodes to run, then stop (0: no limit)", integer_range=_count()),
        ),
        (
            "auto_advance",
            True,
            _descriptor("start the next scenario when an episode ends (else: ~/reset)"),
        ),
        (
            "time_limit",
            0.0,
            _descriptor(
                "episode time limit, s (0: the profile's time budget T_tot)",
                floating_point_range=_at_least(0.0),
            ),
        ),
        (
            "control_period",
            0.0,
            _descriptor(
                "s per decision (0: the profiles'); set it to the planners' when their "
                "genomes decide more often (metadata control_period)",
                floating_point_range=_at_least(0.0),
            ),
        ),
        (
            "real_time_factor",
            0.0,
            _descriptor(
                "sim seconds per wall second (0: as fast as the planners answer); "
                "changes at run time between positive values",
                runtime=True,
                floating_point_range=_at_least(0.0),
            ),
        ),
        (
            "answer_timeout",
            0.0,
            _descriptor(
                "wall s to wait for a cmd_vel before the robot holds still (0: wait)",
                floating_point_range=_at_least(0.0),
            ),
        ),
        (
            "resend_period",
            0.1,
            _descriptor(
                "wall s after which an unanswered observation is published again",
                floating_point_range=_at_least(0.001),
            ),
        ),
        ("record", "", _descriptor("episode bag to write everything into ('' : none)")),
        (
            "record_metadata",
            "{}",
            _descriptor("JSON object added to the recording's metadata (e.g. genomes)"),
        ),
        *_frame_and_goal_declarations(),
        *_lidar_declarations(),
        *_continuous_declarations(),
    ]


def _frame_and_goal_declarations() -> list[tuple[str, Any, ParameterDescriptor]]:
    return [
        (
            "map_to_odom",
            [0.0, 0.0, 0.0],
            _descriptor("pose [x, y, yaw] (m, m, rad) of the odom frame in map"),
        ),
        (
            "goal_radius",
            0.0,
            _descriptor(
                "m, a robot within it has reached its goal (0: each profile's); run time",
                runtime=True,
                floating_point_range=_at_least(0.0),
            ),
        ),
        (
            "wait_for_goals",
            False,
            _descriptor("robots wait at their starts for a goal on a goal topic"),
        ),
        (
            "goal_pose_topic",
            "/goal_pose",
            _descriptor("goals for every robot (RViz/Foxglove goal tools; '' : none)"),
        ),
    ]


def _lidar_declarations() -> list[tuple[str, Any, ParameterDescriptor]]:
    return [
        (
            "lidar_rays",
            0,
            _descriptor("rays of a simulated 2-D lidar on <ns>/lidar/scan (0: none)",
                        integer_range=_count()),
        ),
        ("lidar_fov", 6.283185307179586, _descriptor("lidar field of view, rad (<= 2 pi)")),
        (
            "lidar_mount",
            [0.0, 0.0, 0.0],
            _descriptor("pose [x, y, yaw] (m, m, rad) of the lidar in the body frame"),
        ),
        ("lidar_range_min", 0.0, _descriptor("m, nearer returns read -inf (REP-117)")),
        ("lidar_range_max", 0.0, _descriptor("m, farther read +inf (0: the sensor range)")),
        ("lidar_noise", 0.0, _descriptor("standard deviation of the range noise, m")),
        ("lidar_seed", 0, _descriptor("seed of the lidar noise")),
    ]


def _continuous_declarations() -> list[tuple[str, Any, ParameterDescriptor]]:
    return [
        (
            "continuous",
            False,
            _descriptor("physics at a fixed step with held cmd_vel (as Gazebo), not lockstep"),
        ),
        ("physics_step", 0.05, _descriptor("continuous: s of sim time per physics step")),
        ("scan_rate", 10.0, _descriptor("continuous: scans per s of sim time")),
        ("odom_rate", 20.0, _descriptor("continuous: odometry messages per s of sim time")),
        (
            "command_timeout",
            0.5,
            _descriptor("continuous: sim s a cmd_vel holds before the robot stops (0: ever)"),
        ),
    ]


def _map_declarations() -> list[tuple[str, Any, ParameterDescriptor]]:
    """The world from a ROS map, and the map the node publishes (``/map``)."""
    return [
        (
            "map_yaml",
            "",
            _descriptor("ROS map (map_server YAML + PGM) as the world; pairs sampled with seed"),
        ),
        (
            "map_resolution",
            0.05,
            _descriptor(
                "cell side of /map, m (a world made of a ROS map: the map's own)",
                floating_point_range=[FloatingPointRange(from_value=0.001, to_value=10.0)],
            ),
        ),
    ]


def _is_relative_name(name: str) -> bool:
    return bool(name) and not name.startswith("/") and all(
        part and part[0].isalpha() and part.replace("_", "").isalnum()
        for part in name.split("/")
    )


def check_parameters(values: Mapping[str, Any], node_name: str) -> SimParameters:
    """The parameters ``values`` (name -> value, all of them) checked; ``node_name`` goes
    into the recording's metadata. SimSetupError (MentorError for an unknown profile)."""
    names = [str(n) for n in values["robots"]]
    profiles = [str(p) for p in values["profiles"]]
    if not names or len(set(names)) != len(names):
        raise SimSetupError(f"robots: need distinct robot names, got {names}")
    for n in names:
        if not _is_relative_name(n):
            raise SimSetupError(f"robots: {n!r} is not a relative ROS name like 'robot_0'")
    if len(profiles) == 1:
        profiles = profiles * len(names)
    if len(profiles) != len(names):
        raise SimSetupError(
            f"profiles: {len(profiles)} given for {len(names)} robots (give 1 or one each)"
        )
    robots = tuple((n, get_profile(p)) for n, p in zip(names, profiles, strict=True))
    period = float(values["control_period"])
    for name, seconds in (("control_period", period or MIN_PERIOD),
                          ("resend_period", float(values["resend_period"]))):
        fault = period_fault(name, seconds)
        if fault:
            raise SimSetupError(fault)
    if period > 0.0:  # the planners' period: a Twist then stands for period seconds
        robots = tuple((n, replace(p, control_period=period)) for n, p in robots)
    periods = {profile.control_period for _, profile in robots}
    if len(periods) != 1:
        raise SimSetupError(f"profiles: robots decide at different periods {sorted(periods)}")
    record = str(values["record"])
    if record and len({profile.name for _, profile in robots}) != 1:
        raise SimSetupError("record: an episode bag holds robots of one profile only")
    try:
        note = json.loads(str(values["record_metadata"]))
    except json.JSONDecodeError as err:
        raise SimSetupError(f"record_metadata: not JSON ({err.msg})") from None
    if not isinstance(note, dict):
        raise SimSetupError("record_metadata: not a JSON object")
    limit = float(values["time_limit"])
    rtf = float(values["real_time_factor"])
    radius = float(values["goal_radius"])
    session = SessionConfig(
        robots=robots,
        first_scenario=int(values["first_scenario"]),
        time_limit=limit if limit > 0.0 else None,
        episodes=int(values["episodes"]),
        auto_advance=bool(values["auto_advance"]),
        real_time_factor=rtf,
        answer_timeout=float(values["answer_timeout"]),
        resend_period=float(values["resend_period"]),
        record=record,
        record_metadata={**note, "node": node_name, "real_time_factor": rtf},
        wiring=_wiring(values, robots),
        wait_for_goals=bool(values["wait_for_goals"]),
        continuous=_continuous(values),
        goal_radius=radius if radius > 0.0 else None,
    )
    return SimParameters(
        str(values["world"]), str(values["scenario_bag"]), int(values["seed"]), session,
        str(values["goal_pose_topic"]),
        map_yaml=str(values.get("map_yaml", "")),
        map_resolution=float(values.get("map_resolution", 0.05)),
    )


def _transform(values: Mapping[str, Any], key: str) -> Transform2D:
    try:
        return Transform2D.of([float(v) for v in values[key]])
    except (TypeError, ValueError) as err:
        raise SimSetupError(f"{key}: {err}") from None


def _wiring(
    values: Mapping[str, Any], robots: tuple[tuple[str, RobotProfile], ...]
) -> Wiring:
    map_to_odom = _transform(values, "map_to_odom")
    rays = int(values["lidar_rays"])
    if rays == 0:
        return Wiring(map_to_odom=map_to_odom)
    reach = float(values["lidar_range_max"]) or max(p.sensor_range for _, p in robots)
    try:
        spec = LidarSpec(
            rays,
            fov=float(values["lidar_fov"]),
            mount=_transform(values, "lidar_mount"),
            range_min=float(values["lidar_range_min"]),
            range_max=reach,
            noise=float(values["lidar_noise"]),
        )
    except ValueError as err:
        raise SimSetupError(str(err)) from None
    return Wiring(lidar=spec, seed=int(values["lidar_seed"]), map_to_odom=map_to_odom)


def _continuous(values: Mapping[str, Any]) -> ContinuousConfig | None:
    if not values["continuous"]:
        return None
    rates = {key: float(values[key]) for key in ("scan_rate", "odom_rate")}
    for key, rate in rates.items():
        if not rate > 0.0:
            raise SimSetupError(f"{key}: must be positive, got {rate}")
    periods = {"physics_step": float(values["physics_step"]),
               **{key: 1.0 / rate for key, rate in rates.items()}}
    for key, seconds in periods.items():
        fault = period_fault(key, seconds)
        if fault:
            raise SimSetupError(fault)
    try:
        return ContinuousConfig(
            physics_step=float(values["physics_step"]),
            scan_period=1.0 / rates["scan_rate"],
            odom_period=1.0 / rates["odom_rate"],
            command_timeout=float(values["command_timeout"]),
        )
    except ValueError as err:
        raise SimSetupError(str(err)) from None


def check_runtime(name: str, value: Any, current: SessionConfig) -> str:
    """Why a run-time change of parameter ``name`` to ``value`` is refused ('' : fine)."""
    if name not in RUNTIME:
        return f"{name} is read-only"
    number = float(value)
    if name == "goal_radius":
        return "" if number >= 0.0 else "goal_radius must be >= 0 m"
    if current.continuous is None and (number == 0.0) != (current.real_time_factor == 0.0):
        return "real_time_factor cannot switch between lockstep (0) and real time at run time"
    return "" if number >= 0.0 else "real_time_factor must be >= 0"


def declare_parameters(node: Node, node_name: str) -> SimParameters:
    """Declare the node's parameters, check them, declare each robot's mount layout."""
    declared = node.declare_parameters("", _declarations() + _map_declarations())
    checked = check_parameters({p.name: p.value for p in declared}, node_name)
    for name, profile in checked.session.robots:
        _declare_layout(node, name, profile)
    return checked


def _declare_layout(node: Node, name: str, profile: RobotProfile) -> None:
    key = name.replace("/", ".")
    node.declare_parameters(
        "",
        [
            (f"{key}.profile", profile.name, _descriptor("robot profile")),
            (
                f"{key}.sensor_x",
                [m.x for m in profile.sensors],
                _descriptor("sensor mount x in the body frame, m (scan order)"),
            ),
            (
                f"{key}.sensor_y",
                [m.y for m in profile.sensors],
                _descriptor("sensor mount y in the body frame, m (scan order)"),
            ),
            (
                f"{key}.sensor_angle",
                [m.angle for m in profile.sensors],
                _descriptor("sensor facing angle in the body frame, rad (scan order)"),
            ),
            (f"{key}.sensor_range", profile.sensor_range, _descriptor("range, m")),
        ],
    )
