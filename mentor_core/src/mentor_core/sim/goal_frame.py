"""Turns relative to the goal: the turn output names a heading relative to the goal's bearing.

Not in the paper; off by default (the trainer config's ``turn_frame: goal``; an experiment).
With the paper's actions the turn output ``o_1`` is a heading change in the body frame, so a
planner that turns away from a wall it faces sees the goal move to its other side and, if it
weighs the goal's bearing, turns back: the dithering at walls of experiment E023.
Here ``o_1`` names a heading ``phi = pi (2 o_1 - 1)`` relative to the goal's bearing ``beta``
(the egocentric goal inputs), and the robot turns towards it as far as the heading-change
limit allows: ``dtheta = clip(wrap(beta + phi), -h, h)``. ``o_1 = 0.5`` heads for the goal; a
planner that keeps a wall on one side keeps ``phi``, whatever its own heading.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from mentor_core.sim.kinematics import wrap_angle
from mentor_core.sim.robots import RobotProfile

FloatArray = NDArray[np.float64]


def goal_frame_turns(outputs: FloatArray, inputs: FloatArray, profile: RobotProfile) -> FloatArray:
    """``outputs`` (n, >= 2) with ``o_1`` turned from a heading relative to the goal into the
    body-frame turn output of the paper's mapping (a copy); ``inputs`` (n, >= k + 3) hold the
    egocentric goal inputs ``cos beta, sin beta`` after the ``k`` readings."""
    if profile.input_encoding != "egocentric":
        raise ValueError("turns relative to the goal need the egocentric goal inputs")
    k = profile.n_sensors
    out = np.array(outputs, dtype=np.float64, copy=True)
    beta = np.arctan2(inputs[:, k + 1], inputs[:, k])
    phi = np.pi * (2.0 * np.clip(out[:, 0], 0.0, 1.0) - 1.0)
    h = profile.heading_change_max
    dtheta = np.clip(wrap_angle(beta + phi), -h, h)
    out[:, 0] = 0.5 * (dtheta / h + 1.0)
    return out
