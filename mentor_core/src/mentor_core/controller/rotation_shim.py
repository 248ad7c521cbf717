"""A rotation shim in front of the network: turn onto a new goal first, then drive.

Not in the paper; off by default (the stage ``rotation_shim`` of a deployment, or trained with:
the trainer config's ``rotation_shim_deg``, the genome's metadata's ``rotation_shim``). A robot
starts facing anywhere, and with a heading change of at most ``h`` a decision an evolved
planner turns towards its goal over several decisions while it drives: an arc away from the
goal and back, which costs path length. Nav2 puts a ``RotationShimController`` in front of its
controllers
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

import math
from typing import Annotated, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from pydantic import Field

from mentor_core.controller.stage import Stage, StageRun
from mentor_core.sim.robots import RobotProfile
from mentor_core.validation import Float, config_dataclass

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
    outputs: ArrayLike, inputs: ArrayLike, aligned: ArrayLike, profile: RobotProfile,
    threshold: float,
) -> tuple[FloatArray, BoolArray]:  # fmt: skip
    """The outputs (n, ``profile.n_outputs``) the actions are taken from, and whether each
    robot has now been aligned with its goal (module docstring): ``aligned`` (n,) says which
    had been before this decision; ``threshold`` in rad."""
    out = np.array(outputs, dtype=np.float64, ndmin=2)
    was = np.asarray(aligned, dtype=np.bool_).reshape(-1)
    beta = goal_bearing(inputs, profile)
    now = was | (np.abs(beta) <= threshold)
    hold = ~now
    limit = profile.heading_change_max
    out[hold, 0] = 0.5 + np.clip(beta[hold], -limit, limit) / (2.0 * limit)
    out[hold, 1] = 0.0
    return out, now


@config_dataclass
class RotationShim(Stage):
    """The stage ``rotation_shim`` (module docstring)."""

    name = "rotation_shim"
    threshold_deg: Annotated[Float, Field(gt=0.0, le=180.0)] = 45.0
    """Degrees: the network drives once the goal's bearing has been within this angle (Nav2's
    default 45)."""

    @property
    def threshold(self) -> float:
        """The threshold, rad."""
        return math.radians(self.threshold_deg)

    def start(self, n: int, profile: RobotProfile, arena: float | None) -> StageRun:
        return _ShimRun(n, profile, self.threshold)

    def record(self) -> dict[str, Any]:
        return {"rotation_shim": self.threshold}


class _ShimRun(StageRun):
    def __init__(self, n: int, profile: RobotProfile, threshold: float) -> None:
        self.profile = profile
        self.threshold = threshold
        self.aligned = np.zeros(n, dtype=np.bool_)  # turned onto the goal yet

    def reset(self, robots: NDArray[np.int64] | None = None) -> None:
        self.aligned[slice(None) if robots is None else robots] = False

    def outputs(
        self, robots: NDArray[np.int64], outputs: FloatArray, inputs: FloatArray
    ) -> FloatArray:
        out, self.aligned[robots] = rotation_shim(
            outputs, inputs, self.aligned[robots], self.profile, self.threshold
        )
        return out
