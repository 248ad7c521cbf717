"""A pure pursuit in the network's place: what the network adds to a deployment.

Not a planner of the paper: a control for the question "which part carries the result"
(issue 55). The policy reads the goal a network is shown (the scenario's goal, or the carrot
of its deployment's plan on the scan map) from the network's inputs and drives at it::

    o_1 = 1/2 + clip(beta, -h, h) / (2 h),   o_2 = 1 if |beta| <= h else 0,

``beta`` the goal's bearing (:func:`~mentor_core.controller.rotation_shim.goal_bearing`), so
that :func:`~mentor_core.sim.observation.actions_from_outputs` turns onto the goal by at most
``h`` and steps its longest step (held to the clearance rule) once the goal lies within a
turn, the smallest step while it does not: a pure pursuit of the carrot, as Nav2's pure
pursuit follows a plan, in the planner's own action space, with no learning and no reading
of obstacles but the clearance rule (the deployment's stages, its guard and its plan, still
act). Its memory outputs are 0.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from mentor_core.controller.rotation_shim import goal_bearing
from mentor_core.sim.episode import Policy
from mentor_core.sim.robots import RobotProfile
from mentor_core.sim.world import Scenario

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]


def pursuit_outputs(inputs: FloatArray, profile: RobotProfile) -> FloatArray:
    """The outputs ``(m, profile.n_outputs)`` of the pure pursuit on network inputs
    ``(m, profile.n_inputs)`` (module docstring)."""
    x = np.atleast_2d(np.asarray(inputs, dtype=np.float64))
    beta = goal_bearing(x, profile)
    h = profile.heading_change_max
    out = np.zeros((x.shape[0], profile.n_outputs), dtype=np.float64)
    out[:, 0] = 0.5 + np.clip(beta, -h, h) / (2.0 * h)
    out[:, 1] = np.where(np.abs(beta) <= h, 1.0, 0.0)
    return out


def pursuit_policy(scenarios: Sequence[Scenario], profile: RobotProfile) -> Policy:
    """The pure pursuit's policy for robots on ``scenarios`` (it keeps no state)."""

    def policy(inputs: FloatArray, robots: IntArray) -> FloatArray:
        return pursuit_outputs(inputs, profile)

    return policy
