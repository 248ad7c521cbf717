"""Feed-forward phenotype of a genome, compiled once and evaluated on whole batches.

Each non-input node ``j`` computes ``y_j = f_j(sum_i w_ij y_i)`` over its enabled incoming
connections; the bias node has the constant value 1.0 (appended to the inputs internally),
inputs and bias use the identity. A node without enabled incoming connections outputs
``f_j(0)``. Nodes that cannot influence an output are not evaluated.

A recurrent connection (``ConnectionGene.recurrent``) reads its source's value of the
previous decision, ``y_i(t - 1)``, instead of ``y_i(t)``; those values are the *memory* a
caller keeps per robot (zeros before the first decision) and passes to ``activate``, which
overwrites it with this decision's values. Within a decision the network stays feed-forward.

The sum has a fixed order, so a sample's outputs never depend on the rest of its batch: the
enabled incoming connections in genome order (by innovation), ``s = w_1 y_1``, then
``s = s + w_i y_i`` for ``i = 2, 3, ...`` (each product and each sum rounded, no fused
multiply-add, no reassociation). The activations are the numpy functions of
:data:`ACTIVATIONS`, applied elementwise. :mod:`mentor_core.evolution.batch_network` evaluates many
genomes at once with the same operations in the same order, so it agrees with
:meth:`FeedForwardNetwork.activate` bit for bit (the trainer and the planner decide alike).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from mentor_core.evolution.genome import (
    ConnectionGene,
    Genome,
    InvalidGenomeError,
    topological_order,
)

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
# An activation's code (in compiled programs) is its index here.
ACTIVATION_NAMES: tuple[str, ...] = tuple(ACTIVATIONS)


@dataclass(frozen=True)
class _NodeEval:
    """One node's evaluation step: target row, source rows and weights (summation order)."""

    row: int
    sources: NDArray[np.intp]
    weights: FloatArray
    activation: Callable[[FloatArray], FloatArray]


def weighted_sum(weights: FloatArray, values: FloatArray) -> FloatArray:
    """``sum_i weights[i] * values[i]`` per column of ``values`` (k, batch), in the fixed order
    of the module docstring: ``s = w_1 v_1``, then ``s = s + w_i v_i``; zeros when ``k == 0``.

    ``np.add.accumulate`` adds row after row, never pairwise, whatever the batch width.
    """
    if weights.shape[0] == 0:
        return np.zeros(values.shape[1], dtype=np.float64)
    terms = weights[:, np.newaxis] * values
    sums: FloatArray = np.add.accumulate(terms, axis=0)[-1]
    return sums


class FeedForwardNetwork:
    """A compiled genome: ``activate`` maps ``(batch, n_inputs)`` to ``(batch, n_outputs)``."""

    def __init__(
        self,
        n_inputs: int,
        n_outputs: int,
        n_rows: int,
        steps: tuple[_NodeEval, ...],
        output_rows: NDArray[np.intp],
        recurrent: bool = False,
    ) -> None:
        self.n_inputs = n_inputs
        self.n_outputs = n_outputs
        self._n_rows = n_rows
        self._steps = steps
        self._output_rows = output_rows
        self.recurrent = recurrent

    @property
    def memory_width(self) -> int:
        """Values per robot of the memory a recurrent network keeps (0: feed-forward)."""
        return self._n_rows if self.recurrent else 0

    def new_memory(self, batch: int = 1) -> FloatArray:
        """A blank memory ``(batch, memory_width)`` for ``batch`` robots: zeros, as before a
        first decision."""
        return np.zeros((batch, self.memory_width), dtype=np.float64)

    @classmethod
    def from_genome(cls, genome: Genome) -> FeedForwardNetwork:
        """Compile ``genome``: topological order over enabled connections, per-node arrays.

        Raises InvalidGenomeError for an unknown activation, a dangling reference or a cycle.
        """
        planned, outputs = plan_nodes(genome)
        steps = tuple(
            _NodeEval(
                row=p.row,
                sources=np.array(p.sources, dtype=np.intp),
                weights=np.array(p.weights, dtype=np.float64),
                activation=ACTIVATIONS[ACTIVATION_NAMES[p.code]],
            )
            for p in planned
        )
        output_rows = np.array(outputs, dtype=np.intp)
        n_rows = len(genome.nodes)
        recurrent = any(int(p.sources.max(initial=-1)) >= n_rows for p in steps)
        return cls(genome.n_inputs, genome.n_outputs, n_rows, steps, output_rows, recurrent)

    def episode_policy(
        self, n_robots: int
    ) -> Callable[[FloatArray, NDArray[np.int64]], FloatArray]:
        """``policy(inputs, robots)`` for ``n_robots`` robots of one episode batch (the
        simulator's policy signature): robot ``robots[r]`` decides on ``inputs[r]``, with its
        own memory (blank at the first call) when the network is recurrent."""
        memory = self.new_memory(n_robots)

        def policy(inputs: FloatArray, robots: NDArray[np.int64]) -> FloatArray:
            if not self.recurrent:
                return self.activate(inputs)
            mine = memory[robots]
            out = self.activate(inputs, mine)
            memory[robots] = mine
            return out

        return policy

    def activate(
        self, inputs: NDArray[np.floating] | FloatArray, memory: FloatArray | None = None
    ) -> FloatArray:
        """Outputs ``(batch, n_outputs)`` for inputs ``(batch, n_inputs)``; 1-D in, 1-D out.

        The bias value 1.0 is appended internally; the whole batch is evaluated at once, node
        by node, each weighted sum in the fixed order of the module docstring (so every row's
        outputs are those it gets alone, bit for bit). A recurrent network needs ``memory``
        (:meth:`new_memory`, one row per input row), which it reads and then overwrites with
        this decision's values; a feed-forward one ignores it.

        Raises ValueError for inputs or a memory of the wrong shape, or a recurrent network
        without a memory.
        """
        x = np.asarray(inputs, dtype=np.float64)
        single = x.ndim == 1
        batch = x[np.newaxis, :] if single else x
        if batch.ndim != 2 or batch.shape[1] != self.n_inputs:
            raise ValueError(f"inputs must have shape (batch, {self.n_inputs}), got {x.shape}")
        n = self._n_rows
        # rows are nodes so each gather of source rows reads contiguous memory; a recurrent
        # network's rows n.. hold the previous decision's values (source row n + i: y_i(t-1))
        values = np.zeros((2 * n if self.recurrent else n, batch.shape[0]), dtype=np.float64)
        if self.recurrent:
            if memory is None or memory.shape != (batch.shape[0], n):
                got = None if memory is None else memory.shape
                raise ValueError(f"a recurrent network needs a memory of shape "
                                 f"({batch.shape[0]}, {n}), got {got}")  # fmt: skip
            values[n:] = memory.T
        values[: self.n_inputs] = batch.T
        values[self.n_inputs] = 1.0
        for step in self._steps:
            values[step.row] = step.activation(weighted_sum(step.weights, values[step.sources]))
        if memory is not None and self.recurrent:
            memory[:] = values[:n].T
        out = values[self._output_rows].T.copy()
        return out[0] if single else out


class PlannedNode(NamedTuple):
    """A computed node as plain lists: its row (index in ``genome.nodes``), the rows and
    weights of its enabled incoming connections in genome order, its activation code. The
    source of a recurrent connection is ``len(genome.nodes) + row`` (the previous value)."""

    row: int
    sources: list[int]
    weights: list[float]
    code: int


def plan_nodes(genome: Genome) -> tuple[list[PlannedNode], list[int]]:
    """The computed nodes that reach an output (now or, through a recurrent connection, at a
    later decision), in topological order of the forward connections (ties by id), and the
    output rows; rows index ``genome.nodes`` (inputs ``0..n_inputs-1``, then the bias).

    Raises InvalidGenomeError for an unknown activation, a dangling reference or a cycle among
    the enabled forward connections.
    """
    row_of = {n.id: k for k, n in enumerate(genome.nodes)}
    incoming: dict[int, list[ConnectionGene]] = {}
    edges = []
    for c in genome.connections:
        if not c.enabled:
            continue
        if c.in_node not in row_of or c.out_node not in row_of:
            raise InvalidGenomeError(f"connection {c.innovation} refers to a missing node")
        incoming.setdefault(c.out_node, []).append(c)
        if not c.recurrent:
            edges.append((c.in_node, c.out_node))
    order = topological_order(row_of, edges)
    # nodes from which an output is reachable: sweeps against the topological order, again
    # while a recurrent connection reaches back to a node not yet needed
    needed = set(genome.output_ids)
    size = -1
    while size != len(needed):
        size = len(needed)
        for node_id in reversed(order):
            if node_id in needed:
                needed.update(c.in_node for c in incoming.get(node_id, ()))
    n_rows = len(genome.nodes)
    first_computed = genome.n_inputs + 1  # inputs and bias are given, not computed
    planned = []
    for node_id in order:
        if node_id < first_computed or node_id not in needed:
            continue
        activation = genome.nodes[row_of[node_id]].activation
        if activation not in ACTIVATIONS:
            raise InvalidGenomeError(f"node {node_id}: unknown activation {activation!r}")
        links = incoming.get(node_id, [])
        planned.append(
            PlannedNode(
                row_of[node_id],
                [row_of[c.in_node] + (n_rows if c.recurrent else 0) for c in links],
                [c.weight for c in links],
                ACTIVATION_NAMES.index(activation),
            )
        )
    return planned, [row_of[o] for o in genome.output_ids]
