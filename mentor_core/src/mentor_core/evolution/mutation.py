"""MENTOR mutation: per-edge weight and add-node mutations, per-node add-edge mutation.

Paper, section II "Crossover and Mutation": a fixed probability of mutating *each edge* makes
the expected amount of variation proportional to the network's size; add-edge, which the paper
applies "to different pairs of nodes", is one trial per non-input node here (see below).
One call applies, in this order:

1. weight mutation: every connection gene (enabled or not) with probability ``weight_rate``;
   of those, a fraction ``weight_replace_rate`` draws a fresh weight from
   N(0, ``weight_init_sigma``), the rest add N(0, ``weight_perturb_sigma``); the result is
   clamped to ``[-weight_max, weight_max]``;
2. add node: every enabled connection of the parent with probability ``node_rate`` is split:
   it is disabled, ``in -> new`` gets weight 1.0 and ``new -> out`` the old weight, so the
   network computes nearly the same function; the new node has the genome's
   ``hidden_activation``;
3. add edge: every non-input node ``b`` (hidden or output, in id order) draws, with
   probability ``edge_rate``, one new incoming edge ``a -> b`` from a source picked uniformly
   among the candidates: ``a != b``, no gene ``a -> b`` yet (enabled or not) and no path
   ``b -> a`` (no cycle, counting the edges added before it), weight N(0, ``weight_init_sigma``);
4. add recurrent edge (only when ``recurrent_rate > 0``; the paper's planners are
   feed-forward): every non-input node ``b`` draws, with probability ``recurrent_rate``, one
   new recurrent in-edge ``a -> b`` (``a``'s value of the previous decision) from a source
   picked uniformly among every node but the bias, ``b`` itself included, that has no
   recurrent gene ``a -> b`` yet; weight N(0, ``weight_init_sigma``).

Add-node splits recurrent edges too: ``in -> new`` keeps the delay, ``new -> out`` is forward.

The paper applies add-edge "to different pairs of nodes" with Table I's rate (0.03 UGV, 0.5
Swarm-Robot). Read as one coin per node pair, the number of new edges grows with the square of
the node count and the Swarm-Robot's 0.5 explodes (mutation alone, no selection: 24 -> 201 ->
2,071 -> 14,146 connections in four generations). One trial per node keeps the paper's stated
aim, variation proportional to the network's size, for all three operators.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Annotated

import numpy as np
from pydantic import Field

from mentor_core.evolution.genome import (
    ConnectionGene,
    Genome,
    NodeGene,
    adjacency,
    minimal_genome,
    topological_order,
)
from mentor_core.evolution.innovation import InnovationTracker
from mentor_core.validation import Float, Int, config_dataclass

#: a probability
Rate = Annotated[Float, Field(ge=0.0, le=1.0)]
#: a positive finite number
Positive = Annotated[Float, Field(gt=0.0)]


@config_dataclass
class MutationConfig:
    """Mutation probabilities and weight parameters (defaults: the paper's UGV case).

    ``max_hidden`` (None: no limit) stops add-node once a genome has that many hidden nodes.
    ``recurrent_rate`` (0: the paper's feed-forward planners) is the per-node probability of
    a new recurrent in-edge (module docstring, step 4).
    The paper's per-edge add-node rate makes the expected growth proportional to the size, so
    sizes grow geometrically along a lineage when nothing selects against them (stage 2 and
    XOR have no complexity pressure): an evaluation cost that doubles every few generations.
    """

    weight_rate: Rate = 0.25
    weight_perturb_sigma: Positive = 0.5
    weight_replace_rate: Rate = 0.1
    weight_init_sigma: Positive = 1.0
    weight_max: Positive = 8.0
    node_rate: Rate = 0.05
    edge_rate: Rate = 0.03
    max_hidden: Annotated[Int, Field(ge=0)] | None = None
    recurrent_rate: Rate = 0.0


def mutate(
    genome: Genome, cfg: MutationConfig, tracker: InnovationTracker, rng: np.random.Generator
) -> Genome:
    """A mutated copy of ``genome`` (weights, add-node, add-edge, add recurrent edge; see the
    module doc)."""
    connections = mutate_weights(genome.connections, cfg, rng)
    connections, nodes = _add_nodes(genome, connections, cfg, tracker, rng)
    connections = _add_edges(connections, nodes, cfg, tracker, rng)
    if cfg.recurrent_rate > 0:  # no draw otherwise: feed-forward runs keep their random stream
        connections = _add_edges(connections, nodes, cfg, tracker, rng, recurrent=True)
    return genome.with_connections(connections, nodes)


def mutated_genomes(
    n: int, n_inputs: int, cfg: MutationConfig, rounds: int, rng: np.random.Generator
) -> list[Genome]:
    """``n`` minimal genomes (2 outputs), each put through ``rounds`` of :func:`mutate` with one
    tracker: random networks with hidden nodes and extra edges, for benchmarks and tests."""
    tracker = InnovationTracker(next_node_id=n_inputs + 3)  # inputs, bias, 2 outputs
    genomes = []
    for _ in range(n):
        g = minimal_genome(n_inputs, 2, tracker, rng)
        for _ in range(rounds):
            g = mutate(g, cfg, tracker, rng)
        genomes.append(g)
    return genomes


def mutate_weights(
    connections: tuple[ConnectionGene, ...], cfg: MutationConfig, rng: np.random.Generator
) -> list[ConnectionGene]:
    """Per-edge weight mutation: perturb (or, rarely, replace) each weight w.p. ``weight_rate``."""
    n = len(connections)
    hit = rng.random(n) < cfg.weight_rate
    renew = rng.random(n) < cfg.weight_replace_rate
    fresh = rng.normal(0.0, cfg.weight_init_sigma, size=n)
    noise = rng.normal(0.0, cfg.weight_perturb_sigma, size=n)
    old = np.array([c.weight for c in connections], dtype=np.float64)
    new = np.clip(np.where(renew, fresh, old + noise), -cfg.weight_max, cfg.weight_max)
    return [
        replace(c, weight=float(w)) if h else c
        for c, h, w in zip(connections, hit, new, strict=True)
    ]


def _add_nodes(
    genome: Genome,
    connections: list[ConnectionGene],
    cfg: MutationConfig,
    tracker: InnovationTracker,
    rng: np.random.Generator,
) -> tuple[list[ConnectionGene], list[NodeGene]]:
    """Split each enabled edge with probability ``node_rate`` (up to ``max_hidden`` nodes)."""
    split = rng.random(len(connections)) < cfg.node_rate
    nodes = list(genome.nodes)
    taken = {n.id for n in nodes}
    cap = cfg.max_hidden
    room = len(connections) if cap is None else cap - len(genome.hidden_nodes)
    out: list[ConnectionGene] = []
    for c, do_split in zip(connections, split, strict=True):
        if not (do_split and c.enabled) or room <= 0:
            out.append(c)
            continue
        room -= 1
        node = tracker.split(c.innovation, taken)
        taken.add(node)
        nodes.append(NodeGene(node, "hidden", genome.hidden_activation))
        out.append(replace(c, enabled=False))
        delayed = c.recurrent  # the new node's in-edge keeps a recurrent edge's delay
        out.append(
            ConnectionGene(
                tracker.connection(c.in_node, node, delayed), c.in_node, node, 1.0,
                recurrent=delayed,
            )
        )  # fmt: skip
        out.append(
            ConnectionGene(tracker.connection(node, c.out_node), node, c.out_node, c.weight)
        )
    return out, nodes


def _add_edges(
    connections: list[ConnectionGene],
    nodes: list[NodeGene],
    cfg: MutationConfig,
    tracker: InnovationTracker,
    rng: np.random.Generator,
    recurrent: bool = False,
) -> list[ConnectionGene]:
    """Give each non-input node, with probability ``edge_rate``, one new acyclic in-edge;
    ``recurrent``: with probability ``recurrent_rate``, one new recurrent in-edge from any
    node but the bias (itself included)."""
    ordered = sorted(nodes, key=lambda n: n.id)
    ids = [n.id for n in ordered if not (recurrent and n.kind == "bias")]
    targets = [n.id for n in ordered if n.kind in ("output", "hidden")]
    rate = cfg.recurrent_rate if recurrent else cfg.edge_rate
    hits = [b for b, u in zip(targets, rng.random(len(targets)), strict=True) if u < rate]
    succ = adjacency(connections)  # forward genes
    delayed = {(c.in_node, c.out_node) for c in connections if c.recurrent}
    out = list(connections)
    for b in hits:
        if recurrent:
            sources = [a for a in ids if (a, b) not in delayed]
        else:
            below = descendants(ids, succ)[b]  # a -> b closes a cycle iff a is reachable from b
            sources = [a for a in ids if a != b and b not in succ.get(a, ()) and a not in below]
        if not sources:
            continue
        a = sources[int(rng.integers(len(sources)))]
        w = float(np.clip(rng.normal(0.0, cfg.weight_init_sigma), -cfg.weight_max, cfg.weight_max))
        if recurrent:
            delayed.add((a, b))
        else:
            succ.setdefault(a, set()).add(b)
        out.append(
            ConnectionGene(tracker.connection(a, b, recurrent), a, b, w, recurrent=recurrent)
        )
    return out


def descendants(ids: list[int], succ: dict[int, set[int]]) -> dict[int, frozenset[int]]:
    """For every node, the set of nodes reachable from it (itself excluded); acyclic ``succ``."""
    order = topological_order(ids, ((a, b) for a, bs in succ.items() for b in bs))
    below: dict[int, frozenset[int]] = {}
    for node in reversed(order):
        reach: set[int] = set()
        for nxt in succ.get(node, ()):
            reach.add(nxt)
            reach |= below[nxt]
        below[node] = frozenset(reach)
    return below
