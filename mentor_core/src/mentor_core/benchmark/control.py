"""What the hand-written planners share: reading the network inputs back, acting through the
network's outputs, and odometry.

The baselines and the oracle are policies of the same kind as an evolved network
(``mentor_core.sim.episode.Policy``): they get the same inputs (range readings and goal
inputs, ``mentor_core.sim.observation.network_inputs``) once per control period and answer
outputs in ``[0, 1]`` that the engine turns into actions with the same function
(``actions_from_outputs``: the heading limit, the step range and the clearance rule). So they
have the same sensors, action limits and control period as the evolved planners. They have no
memory: a profile with a context (``feedback_action``, ``memory_units``) gives them extra
inputs after the goal inputs, which they do not read, and they answer zero memory outputs.

Odometry: a robot knows the actions it took, and the engine moves it along exactly that arc
(``mentor_core.sim.kinematics.unicycle_arc``) unless the decision ends the episode (goal or
collision). So a pose integrated from the start with the actions that ``actions_from_outputs``
makes of the policy's own outputs is the true pose, up to rounding; it is what wheel odometry
gives a real robot, without drift.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from mentor_core.sim.kinematics import unicycle_arc, wrap_angle
from mentor_core.sim.observation import (
    CLEARANCE_CONE,
    actions_from_outputs,
    ranges_from_inputs,
)
from mentor_core.sim.robots import RobotProfile

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]


def outputs_for(dtheta: ArrayLike, ds: ArrayLike, profile: RobotProfile) -> FloatArray:
    """Network outputs ``(m, profile.n_outputs)`` that ``actions_from_outputs`` maps onto
    ``(dtheta, ds)`` (rad, m), each clipped into the profile's range first:
    ``o_1 = (dtheta / h + 1) / 2``, ``o_2 = (ds - step_min) / (step_max - step_min)``, and
    zero memory outputs."""
    h = profile.heading_change_max
    span = profile.step_max - profile.step_min
    o1 = 0.5 * (np.clip(np.asarray(dtheta, dtype=np.float64) / h, -1.0, 1.0) + 1.0)
    ds_ = np.asarray(ds, dtype=np.float64)
    o2 = np.clip((ds_ - profile.step_min) / span, 0.0, 1.0) if span > 0 else np.zeros_like(ds_)
    actions = np.stack([np.broadcast_to(o1, np.shape(o2)), o2], axis=-1).reshape(-1, 2)
    if not profile.memory_units:
        return actions
    return np.concatenate([actions, np.zeros((len(actions), profile.memory_units))], axis=1)


def readings(inputs: ArrayLike, profile: RobotProfile) -> FloatArray:
    """The clipped range readings ``(m, k)`` (m) in network inputs ``(m, n_inputs)``."""
    return ranges_from_inputs(inputs, profile)


def goal_polar(inputs: ArrayLike, profile: RobotProfile) -> tuple[FloatArray, FloatArray]:
    """``(bearing (m,), distance (m,))`` of the goal from the body (rad, m), read back from
    the goal inputs of either encoding (``mentor_core.sim.observation``): egocentric
    ``beta = atan2(sin, cos)``, ``d = R / S``; paper ``beta = atan2(dY, dX) - theta``,
    ``d = R / sqrt(|(dX, dY)|)``. Within the goal radius ``d`` reads as ``R``."""
    x = np.asarray(inputs, dtype=np.float64)
    k = profile.n_sensors
    radius = profile.goal_radius
    if profile.input_encoding == "egocentric":
        bearing = np.arctan2(x[:, k + 1], x[:, k])
        distance = radius / np.maximum(x[:, k + 2], 1e-12)
    else:
        bearing = wrap_angle(np.arctan2(x[:, k + 1], x[:, k]) - x[:, k + 2])
        distance = radius / np.sqrt(np.maximum(np.hypot(x[:, k], x[:, k + 1]), 1e-24))
    return np.asarray(bearing, dtype=np.float64), np.asarray(distance, dtype=np.float64)


def free_along(ranges: ArrayLike, direction: ArrayLike, profile: RobotProfile) -> FloatArray:
    """How far each robot saw free space along body-frame directions (m): the smallest
    ``U_i cos(a_i - phi)`` over the sensors facing within 45 deg of ``phi``, as the clearance
    rule reads it (``observation.clearance_limit``); NaN where no sensor faces that way (the
    Swarm-Robot sees nothing behind it). ``direction`` ``(m,)`` gives ``(m,)``, ``(m, d)``
    gives ``(m, d)``."""
    u = np.asarray(ranges, dtype=np.float64)
    phi = np.asarray(direction, dtype=np.float64)
    off = wrap_angle(profile.sensor_angles - phi[..., None])  # (m, [d,] k)
    ahead = np.abs(off) <= CLEARANCE_CONE + 1e-9
    readings_ = u if phi.ndim == 1 else u[:, None, :]
    along = np.where(ahead, readings_ * np.cos(off), np.inf).min(axis=-1)
    return np.where(ahead.any(axis=-1), along, np.nan)


def hit_points(ranges: ArrayLike, profile: RobotProfile) -> FloatArray:
    """Body-frame points ``(m, k, 2)`` (m) where each sensor's reading ends, along its
    facing (a beam's nearest echo is taken on its axis); NaN where it saw nothing in range."""
    u = np.asarray(ranges, dtype=np.float64)
    mounts = profile.sensor_mounts
    reach = np.where(u < profile.sensor_range, u, np.nan)
    x = mounts[None, :, 0] + reach * np.cos(mounts[None, :, 2])
    y = mounts[None, :, 1] + reach * np.sin(mounts[None, :, 2])
    return np.stack([x, y], axis=-1)


def free_corridor(
    ranges: ArrayLike, direction: ArrayLike, profile: RobotProfile,
    points: FloatArray | None = None,
) -> FloatArray:
    """How far (m) each robot can drive along a body-frame ``direction`` before the
    corridor its body sweeps (half width: the circumscribed radius) meets a seen point: the
    least ``along`` of the hit points ahead of the centre whose distance across the
    direction is below that radius; the free range along the direction (:func:`free_along`)
    when it is nearer; 0 for a direction no sensor faces. Shapes as :func:`free_along`.

    ``points``: the body-frame points ``(m, p, 2)`` to check (NaN rows are ignored); by
    default those of ``ranges`` (:func:`hit_points`). The readings a sensor takes at its
    facing say nothing of what lies between two rays, so a box's corner beside the path can
    be missed by :func:`free_along` alone (it counts only sensors facing within 45 deg) and
    clipped by the body's side.
    """
    pts = hit_points(ranges, profile) if points is None else points
    phi = np.asarray(direction, dtype=np.float64)
    c, s = np.cos(phi)[..., None], np.sin(phi)[..., None]  # (m, [d,] 1)
    x, y = (pts[..., 0], pts[..., 1]) if phi.ndim == 1 else (pts[:, None, :, 0],
                                                             pts[:, None, :, 1])
    along = x * c + y * s
    across = -x * s + y * c
    inside = (np.abs(across) < profile.half_diagonal) & (along > 0.0)
    corridor = np.where(inside, along, np.inf).min(axis=-1)
    ahead = np.nan_to_num(free_along(ranges, direction, profile), nan=0.0)
    return np.asarray(np.minimum(ahead, corridor), dtype=np.float64)


def sees_all_round(profile: RobotProfile) -> bool:
    """Whether every direction lies within 45 deg of a sensor's facing (the UGV's eight
    sensors; not the Swarm-Robot's three at the front)."""
    directions = np.linspace(-np.pi, np.pi, 360, endpoint=False)
    off = wrap_angle(profile.sensor_angles[None, :] - directions[:, None])
    return bool((np.abs(off) <= CLEARANCE_CONE + 1e-9).any(axis=1).all())


class PointMemory:
    """The hit points of each robot's last ``depth`` decisions, kept in its odometry frame
    (a histogram grid's short memory, as VFH keeps one): what a robot saw ahead a moment ago
    is still there when it has passed beside it and no sensor faces it any more. A robot
    that sees all round (:func:`sees_all_round`) keeps only the current decision's: it sees
    what is beside it anyway."""

    def __init__(self, n: int, profile: RobotProfile, depth: int) -> None:
        self.depth = 1 if sees_all_round(profile) else depth
        self.points = np.full((n, self.depth, profile.n_sensors, 2), np.nan)

    def add_and_get(self, robots: IntArray, poses: FloatArray, body_points: FloatArray
                    ) -> FloatArray:
        """Store ``body_points`` ``(m, k, 2)`` seen at ``poses`` (odometry frame) and return
        every remembered point in each robot's body frame now, ``(m, depth k, 2)``."""
        c, s = np.cos(poses[:, 2])[:, None], np.sin(poses[:, 2])[:, None]
        x, y = body_points[..., 0], body_points[..., 1]
        world = np.stack([poses[:, 0:1] + c * x - s * y, poses[:, 1:2] + s * x + c * y], -1)
        mem = self.points[robots]
        mem = np.concatenate([mem[:, 1:], world[:, None]], axis=1)
        self.points[robots] = mem
        flat = mem.reshape(len(robots), -1, 2)
        dx, dy = flat[..., 0] - poses[:, 0:1], flat[..., 1] - poses[:, 1:2]
        return np.stack([c * dx + s * dy, -s * dx + c * dy], axis=-1)


class Odometry:
    """Poses ``(n, 3)`` of ``n`` robots integrated from their starts with their own actions
    (module docstring); ``starts`` in any frame (the map frame for the oracle)."""

    def __init__(self, starts: ArrayLike) -> None:
        self.poses = np.array(starts, dtype=np.float64).reshape(-1, 3)

    def advance(
        self, robots: IntArray, outputs: ArrayLike, inputs: ArrayLike, profile: RobotProfile
    ) -> None:
        """Move ``robots`` by the actions the engine makes of ``outputs`` given ``inputs``."""
        dtheta, ds = actions_from_outputs(outputs, profile, readings(inputs, profile))
        self.poses[robots] = unicycle_arc(self.poses[robots], dtheta, ds)
