"""Complexity criterion: estimated FLOPs of one forward pass, relative to the minimal network.

Paper, section III-E: the approximate number of floating-point operations a topology needs to
map the input vector to the output, counting both connectivity and the nonlinearity of the
activations, scaled by that of the simplest topology (inputs wired to outputs, no hidden
node).

Cost model (FLOPs per forward pass of one input vector):

* each enabled connection: 2 (one multiply, one add into the node's sum);
* each non-input node (hidden and output): the cost of its activation,
  ``ACTIVATION_FLOPS`` = sigmoid 4 (scale, exp, add, divide), tanh 6, relu 1, identity 0;
  the sum itself is already paid by the connections;
* inputs and the bias node: 0.

The whole genome is counted (every enabled gene, every hidden node), i.e. the architecture's
cost, even where a node cannot influence an output.
"""

from __future__ import annotations

from collections.abc import Mapping
from types import MappingProxyType

from mentor_core.evolution.genome import Genome, InvalidGenomeError

FLOPS_PER_CONNECTION = 2
ACTIVATION_FLOPS: Mapping[str, int] = MappingProxyType(
    {"sigmoid": 4, "tanh": 6, "relu": 1, "identity": 0}
)


def _activation_cost(name: str) -> int:
    cost = ACTIVATION_FLOPS.get(name)
    if cost is None:
        raise InvalidGenomeError(f"no FLOP cost for activation {name!r}")
    return cost


def flops(genome: Genome) -> int:
    """Estimated FLOPs of one forward pass: ``2 * n_enabled + sum(activation costs)``."""
    nodes = sum(
        _activation_cost(n.activation) for n in genome.nodes if n.kind in ("hidden", "output")
    )
    return FLOPS_PER_CONNECTION * len(genome.enabled_connections) + nodes


def minimal_flops(genome: Genome) -> int:
    """FLOPs of the minimal network with ``genome``'s inputs and outputs (and output
    activations): ``(n_inputs + 1) * n_outputs`` connections, no hidden node.
    """
    outputs = sum(_activation_cost(n.activation) for n in genome.nodes if n.kind == "output")
    return FLOPS_PER_CONNECTION * (genome.n_inputs + 1) * genome.n_outputs + outputs


def flops_ratio(genome: Genome) -> float:
    """``flops(genome) / minimal_flops(genome)``; 1.0 for a minimal genome, > 1 as it grows."""
    return flops(genome) / minimal_flops(genome)
