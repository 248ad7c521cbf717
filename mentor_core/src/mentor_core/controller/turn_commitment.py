"""A Bug-like turn commitment: keep turning to one side while the way ahead is blocked.

Not in the paper; off by default (the trainer config's ``turn_commitment``, which trains
with the stage ``turn_commitment``). The UGV planners'
collisions end in alternating +-45 deg turns at the smallest step while a wall blocks the way
ahead (experiment E023, "Better planners"): facing a wall with the goal behind it, a
turn either way puts the goal on the other side. While the clearance limit holds the chosen
turn's step at ``step_min`` (``observation.clearance_limit``), a turn output on the other side
of 0.5 (straight on) than the robot's previous decision's is mirrored about 0.5 to that side,
with the same magnitude; elsewhere the network decides alone.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from mentor_core.controller.stage import Stage, StageRun
from mentor_core.sim.observation import clearance_limit, ranges_from_inputs
from mentor_core.sim.robots import RobotProfile
from mentor_core.validation import config_dataclass

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]


@config_dataclass
class TurnCommitment(Stage):
    """The stage ``turn_commitment`` (module docstring); no settings."""

    name = "turn_commitment"

    def start(self, n: int, profile: RobotProfile, arena: float | None) -> StageRun:
        return _CommitmentRun(profile, n)


class _CommitmentRun(StageRun):
    """The rule for ``n_robots`` robots, each remembering its previous turn output (0.5, no
    turn, before its first decision)."""

    def __init__(self, profile: RobotProfile, n_robots: int) -> None:
        self.profile = profile
        self.previous: FloatArray = np.full(n_robots, 0.5)

    def reset(self, robots: IntArray | None = None) -> None:
        self.previous[slice(None) if robots is None else robots] = 0.5

    def outputs(self, robots: IntArray, outputs: FloatArray, inputs: FloatArray) -> FloatArray:
        """The network ``outputs`` (n, >= 2) of ``robots`` on ``inputs`` (n, >= k sensors),
        turns committed (a copy)."""
        p = self.profile
        out = np.array(outputs, dtype=np.float64, copy=True)
        turn = np.clip(out[:, 0], 0.0, 1.0)
        dtheta = p.heading_change_max * (2.0 * turn - 1.0)
        blocked = clearance_limit(ranges_from_inputs(inputs, p), dtheta, p) <= p.step_min
        flip = blocked & ((turn - 0.5) * (self.previous[robots] - 0.5) < 0.0)
        out[flip, 0] = 1.0 - turn[flip]
        self.previous[robots] = out[:, 0]
        return out
