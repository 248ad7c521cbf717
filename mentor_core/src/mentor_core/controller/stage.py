"""The stage protocol: what a layer of the controller may change in a decision.

A decision (:class:`~mentor_core.controller.pipeline.DecisionChain`) runs, for the robots that
decide now::

    readings -> [stage.readings] -> network inputs -> network -> [stage.outputs]
             -> actions -> [stage.actions] -> the engine (or cmd_vel)

so a stage may change what the network sees of the readings (a view corridor), the network's
outputs before they become actions (a gain on the turn, a rotation shim) and the actions
before they are driven (a collision guard). The goal the network sees comes from the plan
(:mod:`~mentor_core.controller.deployment`: a carrot on a path), as Nav2's planner server
feeds its controller server.

A :class:`Stage` is a frozen, validated config (a :func:`~mentor_core.validation.config_dataclass`)
whose :meth:`Stage.start` makes the stateful :class:`StageRun` of ``n`` robots for one batch of
episodes (or one planner node: a batch of one). A run's hooks take the indices ``robots`` of
the robots deciding, in ascending order, and arrays of their rows; the base class's hooks pass
everything through, so a stage overrides only what it changes. Nav2's controller plugins and
MPPI's critics are the model: one interface, plugins listed in a parameter file and looped
over in order.
"""

from __future__ import annotations

from typing import Any, ClassVar

import numpy as np
from numpy.typing import NDArray

from mentor_core.sim.robots import RobotProfile

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]


class StageRun:
    """One batch's state of a stage (module docstring); every hook passes its input through."""

    def reset(self, robots: IntArray | None = None) -> None:
        """Forget what robots ``robots`` (None: all) remembered: a new goal or episode."""

    def readings(
        self, robots: IntArray, readings: FloatArray, poses: FloatArray, goals: FloatArray
    ) -> FloatArray:
        """The readings ``(m, k)`` the networks see: ``readings`` clipped to the sensor range,
        the robots at ``poses`` ``(m, 3)`` steering to ``goals`` ``(m, 2)`` (map frame)."""
        return readings

    def outputs(self, robots: IntArray, outputs: FloatArray, inputs: FloatArray) -> FloatArray:
        """The outputs ``(m, n_outputs)`` the actions are taken from, given the network's
        ``outputs`` on ``inputs`` ``(m, n_inputs)``; a stage that changes them returns a copy."""
        return outputs

    def actions(
        self, robots: IntArray, poses: FloatArray, dtheta: FloatArray, ds: FloatArray,
        readings: FloatArray,
    ) -> tuple[FloatArray, FloatArray]:  # fmt: skip
        """The actions ``(dtheta, ds)`` ``(m,)`` (rad, m) driven instead of the chain's so far;
        ``readings`` ``(m, k)`` the raw ones the decision was made on."""
        return dtheta, ds


class Stage:
    """A layer's settings, and the maker of its runs (module docstring).

    Subclasses are config dataclasses (:func:`~mentor_core.validation.config_dataclass`); their
    fields are the settings a deployment file gives under the stage's name.
    """

    #: the name a deployment file lists the stage under
    name: ClassVar[str] = ""

    def start(self, n: int, profile: RobotProfile, arena: float | None) -> StageRun:
        """The run of ``n`` robots of ``profile`` (the planner's) in a square arena of side
        ``arena`` m (None: no arena known, as on a real robot)."""
        raise NotImplementedError

    def record(self) -> dict[str, Any]:
        """The stage's settings as plain values, as ``bench.json`` lists a planner's."""
        return {}


__all__ = ["Stage", "StageRun"]
