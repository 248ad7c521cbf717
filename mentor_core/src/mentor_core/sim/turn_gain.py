"""A gain on the network's turn at deployment: the same decisions, turned less.

Not in the paper; off by default (the planner setting ``RobotProfile.turn_gain``, 1). An
evolved planner's turn output mostly sits at its limits, so on a straight way it drives arcs
of nearly ``+h`` and ``-h`` in turn: the chords line up, but each arc is longer than its chord
(by 2.6 % at ``h`` = 45 deg) and the heading swings about the way. A proportional
controller's answer is a lower gain; here the turn output is scaled about its middle,

    o_1' = 1/2 + g (clip(o_1, 0, 1) - 1/2),

so that :func:`~mentor_core.sim.observation.actions_from_outputs` turns by ``g`` times the
network's turn, at most ``g h``. It is applied to the network's outputs only: a rotation shim
in front of it (:mod:`mentor_core.sim.rotation_shim`) still turns by up to ``h``, and the
collision guard behind it (:mod:`mentor_core.sim.collision_guard`) still chooses among turns
of up to ``h``. A planner that reads its previous action reads the turn it took. The step
and the memory outputs pass unchanged.

Chosen on the benchmark's validation split for the shipped Swarm-Robot planners (0.75;
experiment E054, "A gain on the turn"); the UGV's planners gained nothing from it.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from mentor_core.sim.robots import RobotProfile

FloatArray = NDArray[np.float64]


def turn_gain(outputs: ArrayLike, profile: RobotProfile) -> FloatArray:
    """The network's outputs ``(n, profile.n_outputs)`` with the turn output scaled by
    ``profile.turn_gain`` about its middle (module docstring): a new array, or ``outputs``
    themselves at gain 1 (training's case: no copy)."""
    gain = profile.turn_gain
    if gain == 1.0:
        return np.asarray(outputs, dtype=np.float64)
    out = np.array(outputs, dtype=np.float64, ndmin=2)
    out[:, 0] = 0.5 + gain * (np.clip(out[:, 0], 0.0, 1.0) - 0.5)
    return out
