"""Feed-forward phenotype of a genome, compiled once and evaluated on whole batches.

Each non-input node ``j`` computes ``y_j = f_j(sum_i w_ij y_i)`` over its enabled incoming
connections; the bias node has the constant value 1.0 (appended to the inputs internally),
inputs and bias use the identity. A node without enabled incoming connections outputs
``f_j(0)``. Nodes that cannot influence an output are not evaluated.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from types import MappingProxyType

import numpy as np
from numpy.typing import NDArray

from mentor_core.genome import Genome, InvalidGenomeError, topological_order

FloatArray = NDArray[np.float64]

NEAT_SIGMOID_SLOPE = 4.9  # Stanley & Miikkulainen 2002: steep sigmoid, near-linear at 0


def _sigmoid(x: FloatArray) -> FloatArray:
    """NEAT sigmoid ``1 / (1 + exp(-4.9 x))``, written so exp never overflows."""
    z = NEAT_SIGMOID_SLOPE * x
    e = np.exp(-np.abs(z))
    return np.where(z >= 0.0, 1.0 / (1.0 + e), e / (1.0 + e))


def _tanh(x: FloatArray) -> FloatArray:
    return np.tanh(x)


def _relu(x: FloatArray) -> FloatArray:
    return np.maximum(x, 0.0)


def _identity(x: FloatArray) -> FloatArray:
    return x


ACTIVATIONS: Mapping[str, Callable[[FloatArray], FloatArray]] = MappingProxyType(
    {"sigmoid": _sigmoid, "tanh": _tanh, "relu": _relu, "identity": _identity}
)


@dataclass(frozen=True)
class _NodeEval:
    """One node's evaluation step: target row, source rows and weights."""

    row: int
    sources: NDArray[np.intp]
    weights: FloatArray
    activation: Callable[[FloatArray], FloatArray]


class FeedForwardNetwork:
    """A compiled genome: ``activate`` maps ``(batch, n_inputs)`` to ``(batch, n_outputs)``."""

    def __init__(
        self,
        n_inputs: int,
        n_outputs: int,
        n_rows: int,
        steps: tuple[_NodeEval, ...],
        output_rows: NDArray[np.intp],
    ) -> None:
        self.n_inputs = n_inputs
        self.n_outputs = n_outputs
        self._n_rows = n_rows
        self._steps = steps
        self._output_rows = output_rows

    @classmethod
    def from_genome(cls, genome: Genome) -> FeedForwardNetwork:
        """Compile ``genome``: topological order over enabled connections, per-node arrays.

        Raises InvalidGenomeError for an unknown activation, a dangling reference or a cycle.
        """
        row_of = {n.id: k for k, n in enumerate(genome.nodes)}
        enabled = genome.enabled_connections
        for c in enabled:
            if c.in_node not in row_of or c.out_node not in row_of:
                raise InvalidGenomeError(f"connection {c.innovation} refers to a missing node")
        order = topological_order(row_of, ((c.in_node, c.out_node) for c in enabled))
        needed = _needed_for_outputs(genome)
        incoming: dict[int, list[tuple[int, float]]] = {}
        for c in enabled:
            incoming.setdefault(c.out_node, []).append((row_of[c.in_node], c.weight))
        first_computed = genome.n_inputs + 1  # inputs and bias are given, not computed
        steps = []
        for node_id in order:
            if node_id < first_computed or node_id not in needed:
                continue
            gene = genome.nodes[row_of[node_id]]
            if gene.activation not in ACTIVATIONS:
                raise InvalidGenomeError(f"node {node_id}: unknown activation {gene.activation!r}")
            links = incoming.get(node_id, [])
            steps.append(
                _NodeEval(
                    row=row_of[node_id],
                    sources=np.array([r for r, _ in links], dtype=np.intp),
                    weights=np.array([w for _, w in links], dtype=np.float64),
                    activation=ACTIVATIONS[gene.activation],
                )
            )
        outputs = np.array([row_of[o] for o in genome.output_ids], dtype=np.intp)
        return cls(genome.n_inputs, genome.n_outputs, len(genome.nodes), tuple(steps), outputs)

    def activate(self, inputs: NDArray[np.floating] | FloatArray) -> FloatArray:
        """Outputs ``(batch, n_outputs)`` for inputs ``(batch, n_inputs)``; 1-D in, 1-D out.

        The bias value 1.0 is appended internally; the whole batch is evaluated at once, one
        dot product per node.
        """
        x = np.asarray(inputs, dtype=np.float64)
        single = x.ndim == 1
        batch = x[np.newaxis, :] if single else x
        if batch.ndim != 2 or batch.shape[1] != self.n_inputs:
            raise ValueError(f"inputs must have shape (batch, {self.n_inputs}), got {x.shape}")
        # rows are nodes so each gather of source rows reads contiguous memory
        values = np.zeros((self._n_rows, batch.shape[0]), dtype=np.float64)
        values[: self.n_inputs] = batch.T
        values[self.n_inputs] = 1.0
        for step in self._steps:
            values[step.row] = step.activation(step.weights @ values[step.sources])
        out = values[self._output_rows].T.copy()
        return out[0] if single else out


def _needed_for_outputs(genome: Genome) -> set[int]:
    """Ids of the nodes from which an output is reachable over enabled connections."""
    pred: dict[int, list[int]] = {}
    for c in genome.enabled_connections:
        pred.setdefault(c.out_node, []).append(c.in_node)
    needed = set(genome.output_ids)
    stack = list(needed)
    while stack:
        for src in pred.get(stack.pop(), ()):
            if src not in needed:
                needed.add(src)
                stack.append(src)
    return needed
