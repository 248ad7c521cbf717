"""NEAT direct encoding: node genes, connection genes and the (immutable) genome.

Node id layout (fixed for every genome of a run, so genomes align without a lookup table):

* inputs ``0 .. n_inputs - 1`` (kind ``"input"``, identity),
* the bias node ``n_inputs`` (kind ``"bias"``, identity, value 1.0),
* outputs ``n_inputs + 1 .. n_inputs + n_outputs``,
* hidden nodes above that, ids handed out by the run's
  :class:`~mentor_core.evolution.innovation.InnovationTracker`.

Connection genes carry ``(innovation, in_node, out_node, weight, enabled, recurrent)``. The
forward genes (``recurrent`` False) make a feed-forward network, so no set of them (enabled or
disabled) may contain a cycle: a disabled gene can be re-enabled by crossover, so it must
never close one either. A recurrent gene reads its source's value of the previous decision (a
one-step delay, as NEAT's recurrent links), so it may point anywhere, backwards or to its own
node, and never takes part in a cycle; it may not start at the bias (whose value never
changes). The paper's planners are feed-forward; recurrent genes only appear when
``MutationConfig.recurrent_rate`` is above 0.
"""

from __future__ import annotations

import heapq
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, replace
from typing import Literal, get_args

import numpy as np

from mentor_core.errors import MentorError
from mentor_core.evolution.innovation import InnovationTracker

NodeKind = Literal["input", "bias", "output", "hidden"]
NODE_KINDS: frozenset[str] = frozenset(get_args(NodeKind))
INPUT_ACTIVATION = "identity"


class InvalidGenomeError(MentorError, ValueError):
    """A genome breaks the encoding's rules (ids, references, kinds, cycles)."""


@dataclass(frozen=True, slots=True)
class NodeGene:
    """One neuron: its id, kind and activation function name."""

    id: int
    kind: NodeKind
    activation: str


@dataclass(frozen=True, slots=True)
class ConnectionGene:
    """One weighted edge ``in_node -> out_node`` with its historical marking; ``recurrent``:
    the edge carries ``in_node``'s value of the previous decision (module docstring)."""

    innovation: int
    in_node: int
    out_node: int
    weight: float
    enabled: bool = True
    recurrent: bool = False


@dataclass(frozen=True)
class Genome:
    """A NEAT genome. ``nodes`` sorted by id, ``connections`` sorted by innovation.

    ``n_inputs`` excludes the bias node. ``hidden_activation`` is the activation new hidden
    nodes get when a mutation splits an edge (kept on the genome so offspring inherit it).
    """

    n_inputs: int
    n_outputs: int
    nodes: tuple[NodeGene, ...]
    connections: tuple[ConnectionGene, ...]
    hidden_activation: str = "sigmoid"

    @property
    def bias_id(self) -> int:
        """Id of the bias node."""
        return self.n_inputs

    @property
    def input_ids(self) -> range:
        """Ids of the input nodes (bias excluded)."""
        return range(self.n_inputs)

    @property
    def output_ids(self) -> range:
        """Ids of the output nodes."""
        return range(self.n_inputs + 1, self.n_inputs + 1 + self.n_outputs)

    @property
    def first_hidden_id(self) -> int:
        """Smallest id a hidden node may have."""
        return self.n_inputs + 1 + self.n_outputs

    @property
    def hidden_nodes(self) -> tuple[NodeGene, ...]:
        """The hidden node genes, sorted by id."""
        return tuple(n for n in self.nodes if n.kind == "hidden")

    @property
    def node_ids(self) -> frozenset[int]:
        """Ids of all nodes."""
        return frozenset(n.id for n in self.nodes)

    @property
    def is_recurrent(self) -> bool:
        """Whether an enabled recurrent gene gives the network a memory of past decisions."""
        return any(c.recurrent and c.enabled for c in self.connections)

    @property
    def enabled_connections(self) -> tuple[ConnectionGene, ...]:
        """The expressed connection genes, sorted by innovation."""
        return tuple(c for c in self.connections if c.enabled)

    def with_connections(
        self, connections: Iterable[ConnectionGene], nodes: Iterable[NodeGene] | None = None
    ) -> Genome:
        """A copy with these connections (and nodes if given), re-sorted."""
        new_nodes = self.nodes if nodes is None else nodes
        return replace(
            self,
            nodes=tuple(sorted(new_nodes, key=lambda n: n.id)),
            connections=tuple(sorted(connections, key=lambda c: c.innovation)),
        )


def minimal_genome(
    n_inputs: int,
    n_outputs: int,
    tracker: InnovationTracker,
    rng: np.random.Generator,
    *,
    weight_sigma: float = 1.0,
    hidden_activation: str = "sigmoid",
    output_activation: str = "sigmoid",
) -> Genome:
    """Inputs and bias fully connected to the outputs, no hidden node.

    Weights are drawn from N(0, ``weight_sigma``) in the order outputs x (inputs, bias);
    innovation numbers come from ``tracker`` so every minimal genome of a run shares them.
    """
    if n_inputs < 0 or n_outputs < 1:
        raise InvalidGenomeError(
            f"need n_inputs >= 0 and n_outputs >= 1, got {n_inputs}, {n_outputs}"
        )
    if not weight_sigma > 0:
        raise InvalidGenomeError(f"weight_sigma must be > 0, got {weight_sigma}")
    first_hidden = n_inputs + 1 + n_outputs
    if tracker.next_node_id < first_hidden:
        # the tracker would hand out ids of inputs/outputs as hidden nodes
        raise InvalidGenomeError(
            f"tracker.next_node_id {tracker.next_node_id} < first hidden id {first_hidden}"
        )
    nodes = _fixed_nodes(n_inputs, n_outputs, output_activation)
    pairs = [(i, o) for o in range(n_inputs + 1, first_hidden) for i in range(n_inputs + 1)]
    weights = rng.normal(0.0, weight_sigma, size=len(pairs))
    connections = [
        ConnectionGene(tracker.connection(i, o), i, o, float(w))
        for (i, o), w in zip(pairs, weights, strict=True)
    ]
    connections.sort(key=lambda c: c.innovation)
    return Genome(n_inputs, n_outputs, tuple(nodes), tuple(connections), hidden_activation)


def genome_from_edges(
    n_inputs: int,
    n_outputs: int,
    edges: Iterable[tuple[int, int, float] | tuple[int, int, float, bool]],
    *,
    hidden_activation: str = "sigmoid",
    output_activation: str = "sigmoid",
    recurrent: Iterable[tuple[int, int, float]] = (),
) -> Genome:
    """A validated genome from ``(in, out, weight[, enabled])`` edges, innovation = position;
    the ``recurrent`` edges ``(in, out, weight)`` follow them.

    Hidden nodes are the referenced ids at or above the first hidden id. Meant for tests,
    examples and hand-built networks; evolved genomes get innovations from a tracker.
    """
    connections = []
    for k, edge in enumerate(edges):
        enabled = bool(edge[3]) if len(edge) == 4 else True
        connections.append(ConnectionGene(k, int(edge[0]), int(edge[1]), float(edge[2]), enabled))
    for a, b, w in recurrent:
        k = len(connections)
        connections.append(ConnectionGene(k, int(a), int(b), float(w), recurrent=True))
    first_hidden = n_inputs + 1 + n_outputs
    nodes = _fixed_nodes(n_inputs, n_outputs, output_activation)
    hidden = {e for c in connections for e in (c.in_node, c.out_node) if e >= first_hidden}
    nodes += [NodeGene(h, "hidden", hidden_activation) for h in sorted(hidden)]
    genome = Genome(n_inputs, n_outputs, tuple(nodes), tuple(connections), hidden_activation)
    validate_genome(genome)
    return genome


def _fixed_nodes(n_inputs: int, n_outputs: int, output_activation: str) -> list[NodeGene]:
    """Input, bias and output node genes of the fixed id layout."""
    nodes = [NodeGene(i, "input", INPUT_ACTIVATION) for i in range(n_inputs)]
    nodes.append(NodeGene(n_inputs, "bias", INPUT_ACTIVATION))
    first_hidden = n_inputs + 1 + n_outputs
    nodes += [NodeGene(o, "output", output_activation) for o in range(n_inputs + 1, first_hidden)]
    return nodes


def adjacency(connections: Iterable[ConnectionGene]) -> dict[int, set[int]]:
    """Successor sets ``{in_node: {out_node, ...}}`` of all forward genes, enabled or not
    (recurrent genes are delayed and close no cycle)."""
    succ: dict[int, set[int]] = {}
    for c in connections:
        if not c.recurrent:
            succ.setdefault(c.in_node, set()).add(c.out_node)
    return succ


def has_path(succ: Mapping[int, Iterable[int]], start: int, target: int) -> bool:
    """Whether ``target`` is reachable from ``start`` along ``succ`` (``start == target``: yes)."""
    if start == target:
        return True
    seen = {start}
    stack = [start]
    while stack:
        for nxt in succ.get(stack.pop(), ()):
            if nxt == target:
                return True
            if nxt not in seen:
                seen.add(nxt)
                stack.append(nxt)
    return False


def creates_cycle(connections: Iterable[ConnectionGene], in_node: int, out_node: int) -> bool:
    """Whether adding the forward edge ``in_node -> out_node`` to ``connections`` would close a
    directed cycle of forward genes.

    Disabled genes count too, since crossover may re-enable them.
    """
    return has_path(adjacency(connections), out_node, in_node)


def topological_order(node_ids: Iterable[int], edges: Iterable[tuple[int, int]]) -> list[int]:
    """Node ids in a topological order of ``edges`` (ties by id); InvalidGenomeError on a cycle."""
    ids = sorted(set(node_ids))
    indegree = dict.fromkeys(ids, 0)
    succ: dict[int, list[int]] = {i: [] for i in ids}
    for a, b in edges:
        succ[a].append(b)
        indegree[b] += 1
    ready = [i for i in ids if indegree[i] == 0]  # sorted: a valid heap
    order: list[int] = []
    while ready:
        node = heapq.heappop(ready)  # the smallest id first, for a deterministic order
        order.append(node)
        for nxt in succ[node]:
            indegree[nxt] -= 1
            if indegree[nxt] == 0:
                heapq.heappush(ready, nxt)
    if len(order) != len(ids):
        raise InvalidGenomeError("connections contain a cycle")
    return order


def validate_genome(genome: Genome) -> None:
    """Raise :class:`InvalidGenomeError` naming the first rule ``genome`` breaks."""
    if genome.n_inputs < 0 or genome.n_outputs < 1:
        raise InvalidGenomeError(
            f"n_inputs {genome.n_inputs} must be >= 0 and n_outputs {genome.n_outputs} >= 1"
        )
    _check_nodes(genome)
    _check_connections(genome, genome.nodes)
    forward = ((c.in_node, c.out_node) for c in genome.connections if not c.recurrent)
    topological_order(genome.node_ids, forward)


def _check_nodes(genome: Genome) -> None:
    ids = [n.id for n in genome.nodes]
    if len(set(ids)) != len(ids):
        raise InvalidGenomeError(f"duplicate node ids in {ids}")
    if ids != sorted(ids):
        raise InvalidGenomeError("nodes are not sorted by id")
    kinds = {n.id: n.kind for n in genome.nodes}
    expected = {i: "input" for i in genome.input_ids}
    expected[genome.bias_id] = "bias"
    expected.update({o: "output" for o in genome.output_ids})
    for node_id, kind in sorted(expected.items()):
        if kinds.get(node_id) != kind:
            raise InvalidGenomeError(
                f"node {node_id} must be of kind {kind!r}, found {kinds.get(node_id)!r}"
            )
    for n in genome.nodes:
        if n.kind not in NODE_KINDS:
            raise InvalidGenomeError(f"node {n.id} has unknown kind {n.kind!r}")
        if n.id not in expected and (n.kind != "hidden" or n.id < genome.first_hidden_id):
            raise InvalidGenomeError(f"node {n.id} of kind {n.kind!r} is outside the id layout")
        if not isinstance(n.activation, str) or not n.activation:
            raise InvalidGenomeError(f"node {n.id} has no activation name")
        if n.kind in ("input", "bias") and n.activation != INPUT_ACTIVATION:
            raise InvalidGenomeError(f"{n.kind} node {n.id} must use {INPUT_ACTIVATION!r}")


def _check_connections(genome: Genome, nodes: Sequence[NodeGene]) -> None:
    kinds = {n.id: n.kind for n in nodes}
    innovations = [c.innovation for c in genome.connections]
    if len(set(innovations)) != len(innovations):
        raise InvalidGenomeError("duplicate connection innovation numbers")
    if innovations != sorted(innovations):
        raise InvalidGenomeError("connections are not sorted by innovation")
    pairs: set[tuple[int, int, bool]] = set()
    for c in genome.connections:
        if not isinstance(c.recurrent, bool):
            raise InvalidGenomeError(f"connection {c.innovation}: recurrent must be a bool")
        for end in (c.in_node, c.out_node):
            if end not in kinds:
                raise InvalidGenomeError(f"connection {c.innovation} refers to missing node {end}")
        if kinds[c.out_node] in ("input", "bias"):
            raise InvalidGenomeError(
                f"connection {c.innovation} ends in {kinds[c.out_node]} node {c.out_node}"
            )
        if c.recurrent and kinds[c.in_node] == "bias":
            raise InvalidGenomeError(f"recurrent connection {c.innovation} starts at the bias")
        if (c.in_node, c.out_node, c.recurrent) in pairs:
            kind = "recurrent " if c.recurrent else ""
            raise InvalidGenomeError(f"two {kind}connections {c.in_node} -> {c.out_node}")
        pairs.add((c.in_node, c.out_node, c.recurrent))
        if not np.isfinite(c.weight):
            raise InvalidGenomeError(f"connection {c.innovation} has weight {c.weight}")
