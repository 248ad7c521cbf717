"""A hand-built planner with a memory, for tests of the context (feedback_action, memory_units)."""

from __future__ import annotations

from mentor_core.evolution.genome import Genome, genome_from_edges
from mentor_core.sim.robots import RobotProfile


def latch(profile: RobotProfile) -> Genome:
    """For a profile with one memory unit and no feedback_action: memory output m_1 = reading
    0 (identity activation); turn output o_1 = the memory input (m_1 of the previous
    decision); step output o_2 = 0.5. So the turn at decision t reads the first sensor at
    decision t - 1 (0 at the first: a full turn to the right)."""
    memory_in = profile.n_inputs - 1
    bias = profile.n_inputs
    turn, step, memory_out = bias + 1, bias + 2, bias + 3
    return genome_from_edges(
        profile.n_inputs, profile.n_outputs,
        [(memory_in, turn, 1.0), (bias, step, 0.5), (0, memory_out, 1.0)],
        output_activation="identity",
    )  # fmt: skip
