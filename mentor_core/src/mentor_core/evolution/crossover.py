"""NEAT crossover: align two parents' connection genes by innovation number.

Paper, section II "Crossover and Mutation" (after Stanley & Miikkulainen 2002): matching genes
go to the child from either parent at random; disjoint and excess genes come only from the
parent with the better rank, or from either parent at random when both have the same rank.
A matching gene disabled in either parent is disabled in the child with probability 0.75.
The child never contains a cycle: genes are taken in innovation order and a forward gene that
would close a cycle with those already taken is skipped (recurrent genes are delayed and close
none).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from mentor_core.evolution.genome import (
    ConnectionGene,
    Genome,
    InvalidGenomeError,
    NodeGene,
    has_path,
)

DISABLED_INHERIT_PROB = 0.75  # NEAT: p(child gene disabled | disabled in either parent)


def crossover(a: Genome, b: Genome, a_better: bool | None, rng: np.random.Generator) -> Genome:
    """Child of parents ``a`` and ``b``.

    ``a_better``: True if ``a`` ranks better, False if ``b`` does, None at equal rank (each
    disjoint/excess gene of either parent is then inherited with probability 0.5).
    """
    if (a.n_inputs, a.n_outputs) != (b.n_inputs, b.n_outputs):
        raise InvalidGenomeError(
            f"parents differ in shape: {a.n_inputs}x{a.n_outputs} vs {b.n_inputs}x{b.n_outputs}"
        )
    genes_a = {c.innovation: c for c in a.connections}
    genes_b = {c.innovation: c for c in b.connections}
    innovations = sorted(genes_a.keys() | genes_b.keys())
    # one uniform draw per gene per decision, in innovation order: reproducible from rng
    pick_a = rng.random(len(innovations)) < 0.5
    disable = rng.random(len(innovations)) < DISABLED_INHERIT_PROB
    keep_lone = rng.random(len(innovations)) < 0.5
    succ: dict[int, set[int]] = {}
    delayed: set[tuple[int, int]] = set()
    child: list[ConnectionGene] = []
    for k, innovation in enumerate(innovations):
        gene = _inherit(
            genes_a.get(innovation),
            genes_b.get(innovation),
            a_better,
            bool(pick_a[k]),
            bool(disable[k]),
            bool(keep_lone[k]),
        )
        if gene is None:
            continue
        if gene.recurrent:
            if (gene.in_node, gene.out_node) not in delayed:
                delayed.add((gene.in_node, gene.out_node))
                child.append(gene)
            continue
        if gene.out_node in succ.get(gene.in_node, ()):
            continue
        if has_path(succ, gene.out_node, gene.in_node):
            continue  # would close a cycle with the genes already inherited
        succ.setdefault(gene.in_node, set()).add(gene.out_node)
        child.append(gene)
    better, other = (b, a) if a_better is False else (a, b)
    return better.with_connections(child, _child_nodes(better, other, child))


def _inherit(
    ga: ConnectionGene | None,
    gb: ConnectionGene | None,
    a_better: bool | None,
    pick_a: bool,
    disable: bool,
    keep_lone: bool,
) -> ConnectionGene | None:
    """The child's copy of one aligned gene position, or None if it is not inherited."""
    if ga is not None and gb is not None:
        gene = ga if pick_a else gb
        if not (ga.enabled and gb.enabled):
            enabled = not disable
            if gene.enabled != enabled:
                gene = replace(gene, enabled=enabled)
        return gene
    if a_better is None:
        lone = ga if ga is not None else gb
        return lone if keep_lone else None
    return ga if a_better else gb


def _child_nodes(better: Genome, other: Genome, child: list[ConnectionGene]) -> list[NodeGene]:
    """Fixed nodes plus every node the child's genes refer to, each copied from a parent."""
    source = {n.id: n for n in other.nodes}
    source.update({n.id: n for n in better.nodes})  # the better parent's copy wins
    wanted = {n.id for n in better.nodes if n.kind != "hidden"}
    for c in child:
        wanted.update((c.in_node, c.out_node))
    return [source[i] for i in sorted(wanted)]
