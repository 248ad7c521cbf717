"""The decision chain: one decision of many robots, from readings to actions, through the
stages of a deployment.

The one chain every planner decides with: the batched episodes of training and of the
benchmark (:func:`~mentor_core.controller.episodes.run_episodes`), ``mentor-eval``, and the
planner node (:class:`~mentor_core.runtime.planner.GenomePlanner`, a batch of one), so that
"the node equals the benchmark" holds by construction. For the robots deciding now::

    seen = stage.readings(clip(readings))          each stage in order
    inputs = network_inputs(seen, poses, goals, context)
    outputs = stage.outputs(policy(inputs))        each stage in order
    dtheta, ds = actions_from_outputs(outputs, readings)
    dtheta, ds = stage.actions(dtheta, ds)         each stage in order
    context = next_context(outputs)

The context (a planner with ``feedback_action`` or ``memory_units``) is the chain's: what each
robot's network output at its previous decision (:mod:`mentor_core.sim.observation`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from mentor_core.controller.stage import Stage
from mentor_core.sim import observation
from mentor_core.sim.episode import Policy
from mentor_core.sim.robots import RobotProfile

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]


@dataclass(frozen=True)
class Decision:
    """What the robots ``(m,)`` decided: actions ``dtheta``, ``ds`` (rad, m) and the outputs
    ``(m, n_outputs)`` they were taken from."""

    dtheta: FloatArray
    ds: FloatArray
    outputs: FloatArray


class DecisionChain:
    """The decisions of ``n`` robots of ``profile`` (a planner's) through ``stages`` (module
    docstring), in a square arena of side ``arena`` m (None: none known)."""

    def __init__(
        self, profile: RobotProfile, stages: Sequence[Stage], n: int,
        arena: float | None = None,
    ) -> None:  # fmt: skip
        self.profile = profile
        self.stages = tuple(stages)
        self.runs = [stage.start(n, profile, arena) for stage in self.stages]
        self.context = observation.initial_context(n, profile)

    def reset(self, robots: IntArray | None = None) -> None:
        """Start robots ``robots`` (None: all) blank: a new goal or episode."""
        chosen = slice(None) if robots is None else robots
        self.context[chosen] = observation.initial_context(1, self.profile)
        for run in self.runs:
            run.reset(robots)

    def decide(
        self, robots: IntArray, readings: FloatArray, poses: FloatArray, goals: FloatArray,
        policy: Policy,
    ) -> Decision:  # fmt: skip
        """The decisions of robots ``robots`` ``(m,)`` (ascending) at ``poses`` ``(m, 3)``
        reading ``readings`` ``(m, k)`` (m, +inf nothing seen) and steering to ``goals``
        ``(m, 2)``; the network answers through ``policy``. ValueError for NaN or malformed
        readings, poses or goals, before any state changes."""
        profile = self.profile
        seen = observation.clip_ranges(readings, profile)
        poses, goals = observation.checked_poses(poses, goals, seen.shape[0])
        for run in self.runs:
            seen = run.readings(robots, seen, poses, goals)
        past = self.context[robots] if profile.n_context else None  # the paper's: no context
        inputs = observation.network_inputs(seen, poses, goals, profile, past)
        outputs = np.asarray(policy(inputs, robots), dtype=np.float64)
        outputs = outputs.reshape(robots.size, profile.n_outputs)
        for run in self.runs:
            outputs = run.outputs(robots, outputs, inputs)
        dtheta, ds = observation.actions_from_outputs(outputs, profile, readings)
        for run in self.runs:
            dtheta, ds = run.actions(robots, poses, dtheta, ds, readings)
        if profile.n_context:
            self.context[robots] = observation.next_context(outputs, profile)
        return Decision(dtheta, ds, outputs)


__all__ = ["Decision", "DecisionChain"]
