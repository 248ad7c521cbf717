"""Robot profiles: body, range sensors, action limits and time budget of each robot.

All profiles live in one YAML file (``mentor_core/data/robots.yaml``, format
``mentor-robots`` version 1) read by the simulator, the trainer and the planner, so the three
always agree. Units are REP-103 (m, s, rad); the file writes angles in degrees (keys ending in
``_deg``) and they are converted to radians here.

Sensor order: reading ``i`` (network input ``i``, LaserScan range ``i``) comes from
``profile.sensors[i]``. The default profiles list their sensors counter-clockwise seen from
above, as a LaserScan's angles increase:

* ``ugv``: 0 front-right, 1 front-left (front edge), 2 left-front, 3 left-rear (left edge),
  4 rear-left, 5 rear-right (rear edge), 6 right-rear, 7 right-front (right edge); the two
  sensors of an edge are 0.075 m apart and splayed +-22.5 deg about its normal, so sensor
  ``i`` faces ``-22.5 + 45 i`` deg; the front pair (0, 1) reads 45 deg beams of 5 rays, the
  others single rays.
* ``swarm``: 0 front-right (-45 deg), 1 front-centre (0 deg), 2 front-left (+45 deg).

A robot file of variants may ``extends: shipped`` (or another robot file, its path relative
to this one, ending in .yaml) and list only what differs, profile by profile and key by key;
a list (``sensors``) is replaced whole (``mentor_core.validation.read_yaml_extending``).
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Annotated, Any, Literal, get_args

import numpy as np
from numpy.typing import ArrayLike, NDArray
from pydantic import Field, model_validator

from mentor_core.errors import ConfigError, FileFormatError, is_version
from mentor_core.validation import (
    Float,
    Int,
    Str,
    config_dataclass,
    fault,
    read_yaml_extending,
    validate,
)

#: environment variable that names a robot file to use instead of the shipped one
ROBOTS_ENV = "MENTOR_ROBOTS"
PROFILES_FORMAT = "mentor-robots"
PROFILES_VERSION = 1
#: the network input encodings of ``mentor_core.sim.observation``
InputEncoding = Literal["paper", "egocentric"]
INPUT_ENCODINGS: tuple[str, ...] = get_args(InputEncoding)
#: most memory units a planner may have (a context of a few latched bits; more only slows
#: the search, each unit adding an input and an output)
MAX_MEMORY_UNITS = 8
# a mount may sit on the body edge; this absorbs the rounding of decimal coordinates
_MOUNT_TOLERANCE = 1e-9


@dataclass(frozen=True)
class SensorMount:
    """One range sensor in the body frame: position (m) and facing angle (rad, 0 = forward)."""

    x: float
    y: float
    angle: float


@dataclass(frozen=True)
class RobotProfile:
    """Everything the library needs to know about one robot (units m, s, rad).

    Attributes:
        name: profile key in the robot file (``ugv``, ``swarm``).
        length, width: body rectangle along x and y of the body frame, m.
        sensors: range sensors in reading order (see the module docstring).
        sensor_range: maximum range of every sensor, m.
        beam_width: full opening angle of a sensor's beam, rad (0: a single ray).
        beam_rays: rays that sample a beam, evenly spread over ``beam_width`` (1 for a ray);
            a reading is the nearest of its rays (see :meth:`beam_offsets`).
        beam_sensors: reading indices of the sensors that have the beam, ascending; the
            others read a single ray straight out. None: every sensor.
        heading_change_max: the heading change action lies in [-max, max], rad.
        step_min, step_max: the translation action lies in [step_min, step_max], m.
        control_period: time of one decision, s. The robot file's is the robot's; a planner
            may decide more often (:mod:`~mentor_core.sim.planner_settings`), a planner's
            setting then.
        rated_speed: pace used for the time budget, m/s.
        goal_radius: a robot within this distance of the goal has reached it, m.
        time_budget_slack, time_budget_cap: see :meth:`time_budget`.
        train_arena, test_arena: side of the square training / unseen-test arena, m.
        train_scenarios: number of training scenarios (start/goal pairs).
        input_encoding: how the goal enters the network (``mentor_core.sim.observation``):
            ``"paper"`` (map-frame signal gradient and global heading, as the paper) or
            ``"egocentric"`` (goal direction in the body frame and goal signal). Not part of
            the robot file: it belongs to a planner, and comes from the training config and
            the genome's metadata (:func:`~mentor_core.sim.planner_settings.with_planner`).
        clearance_margin: when set, a step never exceeds the free range read ahead less this
            margin, m (:func:`mentor_core.sim.observation.clearance_limit`); None: no such limit,
            as in the paper. A planner's setting, like ``input_encoding``.
        feedback_action: the network also reads its previous decision's two action outputs
            (:func:`mentor_core.sim.observation.next_context`); False in the paper. A planner's
            setting.
        memory_units: extra network outputs fed back as inputs at the next decision, a
            context memory (0 to :data:`MAX_MEMORY_UNITS`; 0 in the paper). A planner's
            setting.
        proximity_scale: when set, the network reads each range as the proximity
            ``exp(-r / proximity_scale)`` (m; :func:`mentor_core.sim.observation.range_inputs`)
            instead of ``r`` in m, as in the paper (None). A planner's setting.
    """

    name: str
    length: float
    width: float
    sensors: tuple[SensorMount, ...]
    sensor_range: float
    heading_change_max: float
    step_min: float
    step_max: float
    control_period: float
    rated_speed: float
    goal_radius: float
    time_budget_slack: float
    time_budget_cap: float
    train_arena: float
    train_scenarios: int
    test_arena: float
    beam_width: float = 0.0
    beam_rays: int = 1
    beam_sensors: tuple[int, ...] | None = None
    input_encoding: str = "paper"
    clearance_margin: float | None = None
    feedback_action: bool = False
    memory_units: int = 0
    proximity_scale: float | None = None

    @property
    def sensor_mounts(self) -> NDArray[np.float64]:
        """Mount ``(x, y)`` in the body frame (m) and facing (rad) of the sensors in reading
        order: ``(n_sensors, 3)``."""
        return np.array([(m.x, m.y, m.angle) for m in self.sensors], dtype=np.float64)

    @property
    def sensor_angles(self) -> NDArray[np.float64]:
        """Facing angles of the sensors in reading order, rad: ``(n_sensors,)``."""
        return self.sensor_mounts[:, 2]

    @property
    def n_sensors(self) -> int:
        """Number of range sensors (readings)."""
        return len(self.sensors)

    @property
    def beam_offsets(self) -> NDArray[np.float64]:
        """Directions of a beam's rays relative to its sensor's facing, rad: ``(beam_rays,)``.

        ``beam_rays`` angles evenly spaced over ``[-beam_width / 2, beam_width / 2]`` (the one
        ray of a zero-width beam faces straight out). An ultrasonic sensor reports its nearest
        echo anywhere in its cone; the nearest hit of these rays samples that cone.
        """
        if self.beam_rays == 1:
            return np.zeros(1, dtype=np.float64)
        half = 0.5 * self.beam_width
        return np.linspace(-half, half, self.beam_rays, dtype=np.float64)

    @property
    def ray_counts(self) -> NDArray[np.int64]:
        """Rays of each sensor in reading order: ``beam_rays`` for a sensor with the beam,
        else 1: ``(n_sensors,)``."""
        counts = np.ones(self.n_sensors, dtype=np.int64)
        counts[self._beam_rows()] = self.beam_rays
        return counts

    @property
    def ray_offsets(self) -> NDArray[np.float64]:
        """Directions of each sensor's rays relative to its facing, rad:
        ``(n_sensors, beam_rays)``. Row ``i`` is :meth:`beam_offsets` for a sensor with the
        beam; a sensor without it has all zeros (its one ray, repeated: the nearest of equal
        rays is that ray's reading, so only its first ray needs casting)."""
        offsets = np.zeros((self.n_sensors, self.beam_rays), dtype=np.float64)
        offsets[self._beam_rows()] = self.beam_offsets
        return offsets

    def _beam_rows(self) -> list[int] | slice:
        return slice(None) if self.beam_sensors is None else list(self.beam_sensors)

    @property
    def beamed(self) -> NDArray[np.bool_]:
        """``(n_sensors,)`` whether each sensor has the beam (several rays, the nearest read)."""
        out = np.zeros(self.n_sensors, dtype=np.bool_)
        if self.beam_rays > 1:
            out[self._beam_rows()] = True
        return out

    @property
    def distinct_rays(self) -> NDArray[np.bool_]:
        """``(n_sensors, beam_rays)`` the rays that differ: every ray of a beam, the first of a
        single-ray sensor (:meth:`ray_offsets` repeats its one ray)."""
        return np.asarray(self.beamed[:, None] | (np.arange(self.beam_rays) == 0)[None, :])

    @property
    def n_context(self) -> int:
        """Network inputs fed back from the previous decision: its two action outputs with
        ``feedback_action``, then the ``memory_units`` memory outputs."""
        return 2 * int(self.feedback_action) + self.memory_units

    @property
    def n_inputs(self) -> int:
        """Network inputs without the bias: the readings, the three goal inputs and the
        context (:attr:`n_context`)."""
        return self.n_sensors + 3 + self.n_context

    @property
    def n_outputs(self) -> int:
        """Network outputs: the heading change, the step and the memory units."""
        return 2 + self.memory_units

    def network_mismatch(self, n_inputs: int, n_outputs: int) -> str:
        """Why a network with ``n_inputs`` inputs and ``n_outputs`` outputs cannot drive this
        planner (one line), or '' when it fits :attr:`n_inputs` and :attr:`n_outputs`."""
        if (n_inputs, n_outputs) == (self.n_inputs, self.n_outputs):
            return ""
        return (f"genome has {n_inputs} inputs and {n_outputs} outputs, the {self.name!r} "
                f"profile needs {self.n_inputs} inputs and {self.n_outputs} outputs")  # fmt: skip

    @property
    def half_diagonal(self) -> float:
        """Radius of the circle around the body centre that holds the whole body, m."""
        return 0.5 * math.hypot(self.length, self.width)

    @property
    def uncapped_distance(self) -> float:
        """Longest straight start-goal distance whose time budget the cap does not cut, m.

        d* = cap * rated_speed / slack (from slack * d* / rated_speed = cap).
        """
        return self.time_budget_cap * self.rated_speed / self.time_budget_slack

    @property
    def body_polygon(self) -> tuple[tuple[float, float], ...]:
        """Body rectangle corners in the body frame, counter-clockwise from rear-right, m."""
        hl, hw = 0.5 * self.length, 0.5 * self.width
        return ((-hl, -hw), (hl, -hw), (hl, hw), (-hl, hw))

    def time_budget(self, start_xy: ArrayLike, goal_xy: ArrayLike) -> float:
        """Time budget of a scenario, s.

        T_tot = min(cap, slack * d / rated_speed), d = |goal - start| the straight distance.
        """
        return float(self.time_budgets(start_xy, goal_xy)[0])

    def time_budgets(self, starts: ArrayLike, goals: ArrayLike) -> NDArray[np.float64]:
        """:meth:`time_budget` of many scenarios: starts ``(n, >=2)``, goals ``(n, >=2)`` ->
        ``(n,)`` s."""
        s = np.atleast_2d(np.asarray(starts, dtype=np.float64))
        g = np.atleast_2d(np.asarray(goals, dtype=np.float64))
        d = np.hypot(g[:, 0] - s[:, 0], g[:, 1] - s[:, 1])
        budgets: NDArray[np.float64] = np.minimum(
            self.time_budget_cap, self.time_budget_slack * d / self.rated_speed
        )
        return budgets


def sensor_record(profile: RobotProfile) -> dict[str, Any]:
    """What a planner's readings depend on, as plain JSON values: the mounts ``[x, y, angle]``
    (m, m, rad) in reading order, the range (m) and the beam (rad, rays, and the sensors that
    have it unless all do).

    Written with a trained genome and a checkpoint, so that a planner is never run, nor a run
    resumed, with sensors other than those it was trained with.
    """
    return {
        "sensors": [[m.x, m.y, m.angle] for m in profile.sensors],
        "sensor_range": profile.sensor_range,
        "beam_width": profile.beam_width,
        "beam_rays": profile.beam_rays,
        # only when some sensors lack the beam, so that older records of every other
        # profile stay equal
        **({} if profile.beam_sensors is None else {"beam_sensors": list(profile.beam_sensors)}),
    }


def body_corners(profile: RobotProfile, poses: ArrayLike) -> NDArray[np.float64]:
    """Map-frame corners of the body at each pose: (n, 3) poses -> (n, 4, 2), m.

    corner = (x, y) + R(theta) c for each body-frame corner c of ``profile.body_polygon``.
    """
    p = np.atleast_2d(np.asarray(poses, dtype=np.float64))
    local = np.asarray(profile.body_polygon, dtype=np.float64)
    c, s = np.cos(p[:, 2])[:, None], np.sin(p[:, 2])[:, None]
    x = p[:, 0:1] + c * local[None, :, 0] - s * local[None, :, 1]
    y = p[:, 1:2] + s * local[None, :, 0] + c * local[None, :, 1]
    return np.stack([x, y], axis=-1)


def shipped_profiles_path() -> Path:
    """Path of the robot file shipped with mentor_core."""
    return Path(str(resources.files("mentor_core").joinpath("data/robots.yaml")))


def default_profiles_path() -> Path:
    """The robot file in use: the one ``$MENTOR_ROBOTS`` names, else the shipped one.

    One variable, read by the trainer (and its workers), mentor-eval, mentor-report and both
    ROS nodes alike, so that all of them simulate and plan for the same robots (e.g. the
    paper's UGV with its sensor pairs facing straight out, docs/algorithm.md "Sensors").
    """
    chosen = os.environ.get(ROBOTS_ENV, "")
    return Path(chosen) if chosen else shipped_profiles_path()


def load_profiles(path: str | Path | None = None) -> dict[str, RobotProfile]:
    """Read and validate every profile of a robot file (default: :func:`default_profiles_path`).

    Raises:
        FileFormatError: the file (or one it ``extends``) is missing, empty, not YAML, or
            of another format or version.
        ConfigError: a key is unknown or missing, or a value is of the wrong type or out of
            range (names both the key, e.g. ``robots.ugv.step_min``, and the file), or a bad
            ``extends`` (module docstring).
    """
    source = default_profiles_path() if path is None else Path(path)
    doc = read_yaml_extending(source, _named_robot_file)
    if not isinstance(doc, dict):
        raise FileFormatError(source, "expected a mapping at the top level")
    if doc.get("format") != PROFILES_FORMAT:
        raise FileFormatError(source, f"format is {doc.get('format')!r}, not {PROFILES_FORMAT!r}")
    if not is_version(doc.get("version"), PROFILES_VERSION):
        raise FileFormatError(source, f"version {doc.get('version')!r} is not supported")
    spec = validate(_RobotFile, doc, source)
    return {name: spec.robots[name].profile(name) for name in sorted(spec.robots)}


def _named_robot_file(ref: str) -> Path:
    """The robot file ``extends: shipped`` names."""
    if ref != "shipped":
        raise ValueError(f"no robot file {ref!r} (shipped, or a file's path ending in .yaml)")
    return shipped_profiles_path()


def get_profile(name: str, path: str | Path | None = None) -> RobotProfile:
    """The profile called ``name``; ConfigError naming the known ones when there is none."""
    profiles = load_profiles(path)
    if name not in profiles:
        where = default_profiles_path() if path is None else path
        known = ", ".join(sorted(profiles))
        raise ConfigError(f"unknown robot {name!r} (known: {known})", key="robot", path=where)
    return profiles[name]


_Positive = Annotated[Float, Field(gt=0.0)]


@config_dataclass
class _MountSpec:
    x: Float
    y: Float
    angle_deg: Float


@config_dataclass
class _ProfileSpec:
    """One profile of the robot file: sizes, times and limits (all positive; angles in
    degrees), its sensors and (optional) their beam: a ray sensor unless given."""

    length: _Positive
    width: _Positive
    sensor_range: _Positive
    heading_change_max_deg: _Positive
    step_min: _Positive
    step_max: _Positive
    control_period: _Positive
    rated_speed: _Positive
    time_budget_slack: _Positive
    time_budget_cap: _Positive
    goal_radius: _Positive
    train_arena: _Positive
    test_arena: _Positive
    train_scenarios: Annotated[Int, Field(ge=1)]
    sensors: Annotated[list[_MountSpec], Field(min_length=1)]
    beam_width_deg: Annotated[Float, Field(ge=0.0, lt=180.0)] = 0.0
    beam_rays: Annotated[Int, Field(ge=1)] = 1
    beam_sensors: Annotated[list[Annotated[Int, Field(ge=0)]], Field(min_length=1)] | None = None

    @model_validator(mode="after")
    def _consistent(self) -> _ProfileSpec:
        if self.step_min > self.step_max:
            raise fault("step_min", f"{self.step_min} exceeds step_max {self.step_max}")
        if (self.beam_width_deg == 0.0) != (self.beam_rays == 1):
            need = "1 ray" if self.beam_width_deg == 0.0 else "at least 2 rays"
            raise fault(
                "beam_rays", f"a beam {self.beam_width_deg} deg wide needs {need}, got "
                f"{self.beam_rays}",
            )  # fmt: skip
        n = len(self.sensors)
        if self.beam_sensors is not None:
            if self.beam_rays == 1:
                raise fault("beam_sensors", "needs a beam (beam_width_deg and beam_rays)")
            picked = self.beam_sensors
            if max(picked) >= n or len(set(picked)) != len(picked):
                raise fault(
                    "beam_sensors",
                    f"expected distinct sensor indices in [0, {n}), got {self.beam_sensors}",
                )
        for i, m in enumerate(self.sensors):
            half_l, half_w = 0.5 * self.length, 0.5 * self.width
            if abs(m.x) > half_l + _MOUNT_TOLERANCE or abs(m.y) > half_w + _MOUNT_TOLERANCE:
                raise fault(
                    f"sensors[{i}]",
                    f"sensor at ({m.x}, {m.y}) lies outside the {self.length} x {self.width} m "
                    "body",
                )
        return self

    def profile(self, name: str) -> RobotProfile:
        """The profile (angles in radians) called ``name``."""
        return RobotProfile(
            name=name,
            length=self.length,
            width=self.width,
            sensors=tuple(
                SensorMount(x=m.x, y=m.y, angle=math.radians(m.angle_deg)) for m in self.sensors
            ),
            sensor_range=self.sensor_range,
            heading_change_max=math.radians(self.heading_change_max_deg),
            step_min=self.step_min,
            step_max=self.step_max,
            control_period=self.control_period,
            rated_speed=self.rated_speed,
            goal_radius=self.goal_radius,
            time_budget_slack=self.time_budget_slack,
            time_budget_cap=self.time_budget_cap,
            train_arena=self.train_arena,
            train_scenarios=self.train_scenarios,
            test_arena=self.test_arena,
            beam_width=math.radians(self.beam_width_deg),
            beam_rays=self.beam_rays,
            beam_sensors=None if self.beam_sensors is None else tuple(sorted(self.beam_sensors)),
        )


@config_dataclass
class _RobotFile:
    format: Str
    version: Int
    robots: Annotated[dict[Str, _ProfileSpec], Field(min_length=1)]
