"""A rotation shim in front of the network: turn onto a new goal first, then drive.

Not in the paper; off by default (the planner setting ``RobotProfile.rotation_shim``, from
the trainer config's ``rotation_shim_deg`` and the genome's metadata). A robot starts facing
anywhere, and with a heading change of at most ``h`` a decision an evolved planner turns
towards its goal over several decisions while it drives: an arc away from the goal and back,
which costs path length. Nav2 puts a ``RotationShimController`` in front of its controllers
for the same reason: at the start of a new path, while the heading is more than a threshold
off the way (its default 45 deg), the robot rotates in place towards it, then the controller
takes over.

Here, until the goal's bearing ``beta`` (from the network's goal inputs) has first been
within the threshold since the goal was set, the outputs are replaced by the turn onto the
bearing and the smallest step::

    o_1 = 1/2 + clip(beta, -h, h) / (2 h),   o_2 = 0,

so that :func:`~mentor_core.sim.observation.actions_from_outputs` turns by ``clip(beta, -h,
h)`` and steps ``step_min``; from then on the network's outputs pass unchanged, also when the
bearing later swings wide (going round an obstacle). A planner steered to a carrot
(``input_goals``) turns onto the carrot. The memory outputs pass unchanged.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from mentor_core.sim.robots import RobotProfile

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]


def goal_bearing(inputs: ArrayLike, profile: RobotProfile) -> FloatArray:
    """The goal's bearing in the body frame (n,), rad in [-pi, pi], from network inputs
    (n, ``profile.n_inputs``) of either encoding (``mentor_core.sim.observation``)."""
    x = np.atleast_2d(np.asarray(inputs, dtype=np.float64))
    k = profile.n_sensors
    if profile.input_encoding == "egocentric":
        return np.asarray(np.arctan2(x[:, k + 1], x[:, k]), dtype=np.float64)
    # the paper's: the map-frame gradient towards the goal and the heading
    angle = np.arctan2(x[:, k + 1], x[:, k]) - x[:, k + 2]
    return np.asarray(np.arctan2(np.sin(angle), np.cos(angle)), dtype=np.float64)


def rotation_shim(
    outputs: ArrayLike, inputs: ArrayLike, aligned: ArrayLike, profile: RobotProfile
) -> tuple[FloatArray, BoolArray]:
    """The outputs (n, ``profile.n_outputs``) the actions are taken from, and whether each
    robot has now been aligned with its goal (module docstring): ``aligned`` (n,) says which
    had been before this decision. ``profile.rotation_shim`` is the threshold (rad); a profile
    without one returns the outputs unchanged."""
    out = np.array(outputs, dtype=np.float64, ndmin=2)
    was = np.asarray(aligned, dtype=np.bool_).reshape(-1)
    threshold = profile.rotation_shim
    if threshold is None:
        return out, was.copy()
    beta = goal_bearing(inputs, profile)
    now = was | (np.abs(beta) <= threshold)
    hold = ~now
    limit = profile.heading_change_max
    out[hold, 0] = 0.5 + np.clip(beta[hold], -limit, limit) / (2.0 * limit)
    out[hold, 1] = 0.0
    return out, now
