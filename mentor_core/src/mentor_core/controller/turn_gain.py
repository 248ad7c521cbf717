"""A gain on the network's turn at deployment: the same decisions, turned less.

Not in the paper; off by default (the stage ``turn_gain`` of a deployment; never trained with). An
evolved planner's turn output mostly sits at its limits, so on a straight way it drives arcs
of nearly ``+h`` and ``-h`` in turn: the chords line up, but each arc is longer than its chord
(by 2.6 % at ``h`` = 45 deg) and the heading swings about the way. A proportional
controller's answer is a lower gain; here the turn output is scaled about its middle,

    o_1' = 1/2 + g (clip(o_1, 0, 1) - 1/2),

so that :func:`~mentor_core.sim.observation.actions_from_outputs` turns by ``g`` times the
network's turn, at most ``g h``. Listed before a rotation shim
(:mod:`~mentor_core.controller.rotation_shim`), it scales the network's outputs only: the shim
still turns by up to ``h``, and the collision guard behind them
(:mod:`~mentor_core.controller.collision_guard`) still chooses among turns of up to ``h``. A
planner that reads its previous action reads the turn it took. The step and the memory outputs
pass unchanged.

Chosen on the benchmark's validation split for the shipped Swarm-Robot planners (0.75;
experiment E054, "A gain on the turn"); the UGV's planners gained nothing from it.
"""

from __future__ import annotations

from typing import Annotated, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from pydantic import Field

from mentor_core.controller.stage import Stage, StageRun
from mentor_core.sim.robots import RobotProfile
from mentor_core.validation import Float, config_dataclass

FloatArray = NDArray[np.float64]


def turn_gain(outputs: ArrayLike, gain: float) -> FloatArray:
    """The network's outputs ``(n, n_outputs)`` with the turn output scaled by ``gain`` about
    its middle (module docstring): a new array, or ``outputs`` themselves at gain 1."""
    if gain == 1.0:
        return np.asarray(outputs, dtype=np.float64)
    out = np.array(outputs, dtype=np.float64, ndmin=2)
    out[:, 0] = 0.5 + gain * (np.clip(out[:, 0], 0.0, 1.0) - 0.5)
    return out


@config_dataclass
class TurnGain(Stage):
    """The stage ``turn_gain`` (module docstring)."""

    name = "turn_gain"
    gain: Annotated[Float, Field(gt=0.0, le=1.0)] = 1.0
    """The gain g on the network's turn, in (0, 1]."""

    def start(self, n: int, profile: RobotProfile, arena: float | None) -> StageRun:
        return _GainRun(self.gain)

    def record(self) -> dict[str, Any]:
        return {} if self.gain == 1.0 else {"turn_gain": self.gain}


class _GainRun(StageRun):
    def __init__(self, gain: float) -> None:
        self.gain = gain

    def outputs(
        self, robots: NDArray[np.int64], outputs: FloatArray, inputs: FloatArray
    ) -> FloatArray:
        return turn_gain(outputs, self.gain)
