"""A whole population's phenotypes as one flat program, evaluated for many robots at once.

The trainer steps every robot of every genome together; per decision each active robot's
network maps its inputs to outputs. :class:`BatchNetwork` compiles all genomes of a
generation once (:meth:`BatchNetwork.from_genomes`) and :meth:`BatchNetwork.activate`
evaluates any set of robots, each with its owner genome, in a few calls per decision,
whatever the mix of genomes.

The program (CSR arrays, one entry per computed node that reaches an output):

* per genome its nodes sorted by *level* (inputs and bias are level 0; a node is one level
  above its highest source), ties in topological order; ``level_ptr[g, l]`` is the first
  node of genome ``g`` at level ``l + 1``;
* per node its activation code (index in
  :data:`mentor_core.evolution.network.ACTIVATION_NAMES`) and its enabled incoming connections
  (source row, weight) in genome order;
* a robot of genome ``g`` owns ``n_rows[g]`` consecutive values: its inputs, the bias 1.0,
  then the node values in program order (source rows are relative to that block); a genome
  with recurrent connections has twice ``block[g]`` values, the second half the previous
  decision's values of the first (a recurrent source row is ``block[g]`` + the row), copied
  in from the caller's memory before the decision and back out after it.

Per decision and level, the weighted sums of all robots' nodes of that level are computed in
the fixed order of :mod:`mentor_core.evolution.network` (``s = w_1 v_1``, then
``s = s + w_i v_i``), by a numba kernel (``backend="numba"``) or by vectorised numpy
(``"numpy"``, the fallback; both round identically, no fused multiply-add), grouped by
activation code; then each group gets its activation and is written to the robots' value
slots. The transcendental functions always come from numpy: numpy's ``exp``/``tanh`` (SIMD)
and libm's (what numba calls) differ in the last bit on a few percent of inputs, so the kernel
must not compute them. The numpy backend applies :data:`mentor_core.evolution.network.ACTIVATIONS`
as they are; the numba backend applies tanh and relu the same way and splits the sigmoid
``1 / (1 + exp(-4.9 s))`` of :func:`mentor_core.evolution.network._sigmoid` around numpy's
``exp``: the kernel computes ``-|4.9 s|``, numpy its ``exp`` ``e``, the kernel ``1 / (1 + e)``
(``4.9 s >= 0``) or ``e / (1 + e)``, the very operations of ``_sigmoid``. So one robot's
outputs are bit-identical to ``FeedForwardNetwork.activate`` of its genome on its inputs (the
planner's path), whatever else is in the batch and whichever backend (the tests check all
three).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from mentor_core.evolution.genome import Genome
from mentor_core.evolution.network import (
    ACTIVATION_NAMES,
    ACTIVATIONS,
    NEAT_SIGMOID_SLOPE,
    plan_nodes,
)

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
Backend = Literal["auto", "numba", "numpy"]

N_CODES = len(ACTIVATION_NAMES)
_IDENTITY = ACTIVATION_NAMES.index("identity")
_SIGMOID = ACTIVATION_NAMES.index("sigmoid")


def _fill_loop(x: FloatArray, offsets: IntArray, values: FloatArray) -> None:
    """Each robot's block starts with its inputs, then the bias 1.0 (compiled by numba)."""
    n_in = x.shape[1]
    for r in range(x.shape[0]):
        base = offsets[r]
        for i in range(n_in):
            values[base + i] = x[r, i]
        values[base + n_in] = 1.0


def _level_sums_loop(
    level: int, owners: IntArray, offsets: IntArray, values: FloatArray, level_ptr: IntArray,
    node_code: IntArray, edge_ptr: IntArray, edge_src: IntArray, edge_w: FloatArray,
    n_fixed: int, cursor: IntArray, pre: FloatArray, aux: FloatArray, dest: IntArray,
) -> None:
    """Weighted sums of every robot's nodes at ``level + 1`` (compiled by numba).

    Writes each sum to ``pre[k]`` and its value slot to ``dest[k]``, ``k`` taken from
    ``cursor[code]`` (advanced), so the sums come out grouped by activation code. For a
    sigmoid node it also writes ``aux[k] = -|4.9 s|``, the argument of the sigmoid's exp.
    """
    for r in range(owners.shape[0]):
        g = owners[r]
        base = offsets[r]
        first = level_ptr[g, 0]
        for j in range(level_ptr[g, level], level_ptr[g, level + 1]):
            lo = edge_ptr[j]
            hi = edge_ptr[j + 1]
            acc = 0.0
            if hi > lo:
                acc = edge_w[lo] * values[base + edge_src[lo]]
                for e in range(lo + 1, hi):
                    acc = acc + edge_w[e] * values[base + edge_src[e]]
            c = node_code[j]
            k = cursor[c]
            cursor[c] = k + 1
            pre[k] = acc
            dest[k] = base + n_fixed + (j - first)
            if c == _SIGMOID:
                aux[k] = -abs(NEAT_SIGMOID_SLOPE * acc)


def _scatter_loop(
    lo: int, hi: int, sigmoid: bool, pre: FloatArray, aux: FloatArray, dest: IntArray,
    values: FloatArray,
) -> None:
    """``values[dest[k]] = y_k`` for ``lo <= k < hi`` (compiled by numba): ``y = pre`` (an
    activation numpy already applied, or identity) or, for ``sigmoid``, the rest of
    :func:`mentor_core.evolution.network._sigmoid` given ``aux = exp(-|z|)``: ``1 / (1 + e)`` for
    ``z = 4.9 s >= 0``, else ``e / (1 + e)``."""
    if sigmoid:
        for k in range(lo, hi):
            e = aux[k]
            top = 1.0 if NEAT_SIGMOID_SLOPE * pre[k] >= 0.0 else e  # a select, not a branch
            values[dest[k]] = top / (1.0 + e)
    else:
        for k in range(lo, hi):
            values[dest[k]] = pre[k]


def _gather_loop(
    values: FloatArray, offsets: IntArray, owners: IntArray, output_rows: IntArray,
    out: FloatArray,
) -> None:
    """``out[r, o] = values[offsets[r] + output_rows[owners[r], o]]`` (compiled by numba)."""
    for r in range(owners.shape[0]):
        base = offsets[r]
        g = owners[r]
        for o in range(out.shape[1]):
            out[r, o] = values[base + output_rows[g, o]]


_fill_numba: Callable[..., None] | None
_level_sums_numba: Callable[..., None] | None
_scatter_numba: Callable[..., None] | None
_gather_numba: Callable[..., None] | None
try:
    from numba import njit

    # No fastmath: every product and sum must round exactly like the numpy backend's.
    _fill_numba = njit(cache=True)(_fill_loop)
    _level_sums_numba = njit(cache=True)(_level_sums_loop)
    _scatter_numba = njit(cache=True)(_scatter_loop)
    _gather_numba = njit(cache=True)(_gather_loop)
except ImportError:  # pragma: no cover - numba is in the lock file; numpy stays the fallback
    _fill_numba = _level_sums_numba = _scatter_numba = _gather_numba = None

HAVE_NUMBA = _level_sums_numba is not None


def _use_numba(backend: Backend) -> bool:
    if backend not in ("auto", "numba", "numpy"):
        raise ValueError(f"unknown backend {backend!r}")
    if backend == "numba" and not HAVE_NUMBA:
        raise ValueError("backend 'numba' requested but numba is not importable")
    return backend != "numpy" and HAVE_NUMBA


@dataclass(frozen=True)
class BatchNetwork:
    """The compiled program of a list of genomes (module docstring); build with
    :meth:`from_genomes`, evaluate with :meth:`activate`.

    Attributes:
        n_inputs, n_outputs: shared by all genomes (bias excluded from ``n_inputs``).
        n_levels: the deepest genome's number of levels above the inputs.
        n_rows: (G,) values per robot of each genome: inputs, bias, computed nodes (and
            their previous values, for a recurrent genome).
        block: (G,) inputs, bias and computed nodes of each genome (``n_rows`` without the
            previous values).
        level_ptr: (G, n_levels + 1) first node of each genome at each level; row ``g`` ends
            with the end of genome ``g``'s nodes.
        node_code: (N,) activation code of each node.
        edge_ptr: (N + 1,) each node's incoming connections ``edge_ptr[j]:edge_ptr[j + 1]``.
        edge_src: (E,) source row of each connection, within the robot's block.
        edge_w: (E,) its weight.
        output_rows: (G, n_outputs) rows of each genome's outputs, within the block.
        code_counts: (G, n_levels, N_CODES) nodes per genome, level and activation code.
    """

    n_inputs: int
    n_outputs: int
    n_levels: int
    n_rows: IntArray
    block: IntArray
    level_ptr: IntArray
    node_code: IntArray
    edge_ptr: IntArray
    edge_src: IntArray
    edge_w: FloatArray
    output_rows: IntArray
    code_counts: IntArray

    @property
    def n_genomes(self) -> int:
        """Number of genomes G."""
        return int(self.n_rows.shape[0])

    @property
    def memory_width(self) -> int:
        """Values per robot of the memory recurrent genomes keep (0: all feed-forward)."""
        delayed = self.n_rows != self.block
        return int(self.block[delayed].max(initial=0))

    def new_memory(self, n_slots: int) -> FloatArray:
        """A blank memory for ``n_slots`` robots, ``(n_slots, memory_width)`` zeros: as before
        a first decision (:meth:`activate`)."""
        return np.zeros((n_slots, self.memory_width), dtype=np.float64)

    @classmethod
    def from_genomes(cls, genomes: Sequence[Genome]) -> BatchNetwork:
        """Compile ``genomes`` (at least one, all with the same numbers of inputs and outputs).

        Raises InvalidGenomeError as :meth:`FeedForwardNetwork.from_genome` does, ValueError
        for an empty list or mismatched input/output counts.
        """
        if not genomes:
            raise ValueError("a BatchNetwork needs at least one genome")
        n_in, n_out = genomes[0].n_inputs, genomes[0].n_outputs
        if any(g.n_inputs != n_in or g.n_outputs != n_out for g in genomes):
            raise ValueError("all genomes of a BatchNetwork need the same inputs and outputs")
        n_fixed = n_in + 1
        per_genome = [_genome_program(g, n_fixed) for g in genomes]
        n_levels = max(len(p.level_sizes) for p in per_genome)
        n_gen = len(genomes)
        level_ptr = np.zeros((n_gen, n_levels + 1), dtype=np.int64)
        first = 0
        for g, p in enumerate(per_genome):
            sizes = np.zeros(n_levels, dtype=np.int64)
            sizes[: len(p.level_sizes)] = p.level_sizes
            level_ptr[g] = first + np.concatenate([[0], np.cumsum(sizes)])
            first += len(p.codes)
        # nodes per (genome, level, code): one bincount over every node's flat cell
        cell = [(g * n_levels + level - 1) * N_CODES + code
                for g, p in enumerate(per_genome)
                for level, code in zip(p.levels, p.codes, strict=True)]
        code_counts = np.bincount(
            np.array(cell, dtype=np.intp), minlength=n_gen * n_levels * N_CODES
        ).astype(np.int64).reshape(n_gen, n_levels, N_CODES)
        degrees = [d for p in per_genome for d in p.degrees]
        return cls(
            n_inputs=n_in,
            n_outputs=n_out,
            n_levels=n_levels,
            n_rows=np.array(
                [(2 if p.recurrent else 1) * (n_fixed + len(p.codes)) for p in per_genome],
                dtype=np.int64,
            ),
            block=np.array([n_fixed + len(p.codes) for p in per_genome], dtype=np.int64),
            level_ptr=level_ptr,
            node_code=np.array([c for p in per_genome for c in p.codes], dtype=np.int64),
            edge_ptr=np.concatenate([[0], np.cumsum(degrees, dtype=np.int64)]),
            edge_src=np.array([s for p in per_genome for s in p.sources], dtype=np.int64),
            edge_w=np.array([w for p in per_genome for w in p.weights], dtype=np.float64),
            output_rows=np.array([p.output_rows for p in per_genome], dtype=np.int64),
            code_counts=code_counts,
        )

    def activate(
        self, inputs: ArrayLike, owners: ArrayLike, *, backend: Backend = "auto",
        memory: FloatArray | None = None, slots: ArrayLike | None = None,
    ) -> FloatArray:
        """Outputs ``(m, n_outputs)`` of ``m`` robots: row ``r`` is genome ``owners[r]``'s
        network on ``inputs[r]`` (``(m, n_inputs)``), bit-identical to
        ``FeedForwardNetwork.activate`` of that genome on that row.

        ``backend``: ``"numba"``, ``"numpy"`` or ``"auto"`` (numba when importable); both give
        the same bits. With recurrent genomes, ``memory`` (:meth:`new_memory`) holds every
        robot's previous values, robot ``r`` in row ``slots[r]``: read, then overwritten with
        this decision's values (rows of feed-forward genomes' robots are left alone).

        Raises ValueError for mismatched shapes, owners out of range, or recurrent genomes
        without ``memory`` and ``slots``.
        """
        x = np.ascontiguousarray(inputs, dtype=np.float64)
        own = np.ascontiguousarray(owners, dtype=np.int64).reshape(-1)
        if x.ndim != 2 or x.shape[1] != self.n_inputs or x.shape[0] != own.shape[0]:
            raise ValueError(
                f"inputs must have shape ({own.shape[0]}, {self.n_inputs}), got {x.shape}"
            )
        m = own.shape[0]
        if m == 0:
            return np.zeros((0, self.n_outputs), dtype=np.float64)
        if own.min() < 0 or own.max() >= self.n_genomes:
            raise ValueError(f"owners must lie in [0, {self.n_genomes})")
        numba = _use_numba(backend)
        widths = self.n_rows[own]
        ends = np.cumsum(widths)
        offsets = ends - widths
        values = np.empty(int(ends[-1]), dtype=np.float64)
        # nodes per (level, code) over these robots, then each group's slice of pre/dest
        multiplicity = np.bincount(own, minlength=self.n_genomes)
        counts = (multiplicity @ self.code_counts.reshape(self.n_genomes, -1)).reshape(-1)
        bounds = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
        carried = self._carried(own, offsets, memory, slots)
        if carried is not None:  # the previous values go to each block's second half
            at, row, col, half = carried
            values[at + half] = memory[row, col]  # type: ignore[index]
        run = self._run_numba if numba else self._run_numpy
        out = run(x, own, offsets, values, bounds)
        if carried is not None:
            memory[row, col] = values[at]  # type: ignore[index]
        return out

    def _carried(
        self, owners: IntArray, offsets: IntArray, memory: FloatArray | None,
        slots: ArrayLike | None,
    ) -> tuple[IntArray, IntArray, IntArray, IntArray] | None:
        """For the robots of recurrent genomes: each block value's index in ``values`` (first
        half), its memory row and column, and the offset of its previous value; None when
        none of these robots has a recurrent genome."""
        delayed = np.flatnonzero(self.n_rows[owners] != self.block[owners])
        if delayed.size == 0:
            return None
        if memory is None or slots is None:
            raise ValueError("recurrent genomes need memory= (new_memory) and slots=")
        where = np.ascontiguousarray(slots, dtype=np.int64).reshape(-1)
        if where.shape[0] != owners.shape[0]:
            raise ValueError(f"slots must have shape ({owners.shape[0]},), got {where.shape}")
        width = self.memory_width
        if memory.ndim != 2 or memory.shape[1] != width:
            raise ValueError(f"memory must have shape (n, {width}), got {memory.shape}")
        if where[delayed].min() < 0 or where[delayed].max() >= memory.shape[0]:
            raise ValueError(f"slots must lie in [0, {memory.shape[0]})")
        sizes = self.block[owners[delayed]]
        robot = np.repeat(delayed, sizes)
        col = np.arange(robot.shape[0]) - np.repeat(np.cumsum(sizes) - sizes, sizes)
        half = np.repeat(sizes, sizes)
        return offsets[robot] + col, where[robot], col, half

    def _run_numba(
        self, x: FloatArray, owners: IntArray, offsets: IntArray, values: FloatArray,
        bounds: IntArray,
    ) -> FloatArray:
        """:meth:`activate` with the numba kernels; numpy only for exp, tanh and relu."""
        assert _fill_numba is not None and _level_sums_numba is not None
        assert _scatter_numba is not None and _gather_numba is not None
        n_entries = int(bounds[-1])
        pre = np.empty(n_entries, dtype=np.float64)
        aux = np.empty(n_entries, dtype=np.float64)
        dest = np.empty(n_entries, dtype=np.int64)
        _fill_numba(x, offsets, values)
        for level in range(self.n_levels):
            group = bounds[level * N_CODES : (level + 1) * N_CODES + 1]
            if group[-1] == group[0]:
                continue
            _level_sums_numba(
                level, owners, offsets, values, self.level_ptr, self.node_code, self.edge_ptr,
                self.edge_src, self.edge_w, self.n_inputs + 1, group[:-1].copy(), pre, aux,
                dest,
            )
            for code in range(N_CODES):
                lo, hi = int(group[code]), int(group[code + 1])
                if hi == lo:
                    continue
                if code == _SIGMOID:
                    np.exp(aux[lo:hi], out=aux[lo:hi])
                elif code != _IDENTITY:
                    pre[lo:hi] = ACTIVATIONS[ACTIVATION_NAMES[code]](pre[lo:hi])
                _scatter_numba(lo, hi, code == _SIGMOID, pre, aux, dest, values)
        out = np.empty((owners.shape[0], self.n_outputs), dtype=np.float64)
        _gather_numba(values, offsets, owners, self.output_rows, out)
        return out

    def _run_numpy(
        self, x: FloatArray, owners: IntArray, offsets: IntArray, values: FloatArray,
        bounds: IntArray,
    ) -> FloatArray:
        """:meth:`activate` in numpy: the activations of :data:`ACTIVATIONS` as they are."""
        n_entries = int(bounds[-1])
        pre = np.empty(n_entries, dtype=np.float64)
        dest = np.empty(n_entries, dtype=np.int64)
        if self.n_inputs:
            values[offsets[:, np.newaxis] + np.arange(self.n_inputs)] = x
        values[offsets + self.n_inputs] = 1.0
        for level in range(self.n_levels):
            group = bounds[level * N_CODES : (level + 1) * N_CODES + 1]
            if group[-1] == group[0]:
                continue
            self._level_sums_numpy(level, owners, offsets, values, group, pre, dest)
            for code in range(N_CODES):
                lo, hi = int(group[code]), int(group[code + 1])
                if hi > lo:
                    values[dest[lo:hi]] = ACTIVATIONS[ACTIVATION_NAMES[code]](pre[lo:hi])
        out: FloatArray = values[offsets[:, np.newaxis] + self.output_rows[owners]]
        return out

    def _level_sums_numpy(
        self, level: int, owners: IntArray, offsets: IntArray, values: FloatArray,
        group: IntArray, pre: FloatArray, dest: IntArray,
    ) -> None:
        """Vectorised twin of the numba kernel: same products and sums in the same order.

        Each (robot, node) pair of the level is one entry; entries sorted by in-degree
        (descending) let edge position ``p`` update a prefix ``acc[:n_p]`` of them.
        """
        first = self.level_ptr[owners, level]
        count = self.level_ptr[owners, level + 1] - first
        total = int(count.sum())
        robot = np.repeat(np.arange(owners.shape[0]), count)
        starts = np.cumsum(count) - count
        node = first[robot] + (np.arange(total) - starts[robot])
        base = offsets[robot]
        slot = base + (self.n_inputs + 1) + (node - self.level_ptr[owners[robot], 0])
        e_lo = self.edge_ptr[node]
        degree = self.edge_ptr[node + 1] - e_lo
        order = np.argsort(-degree, kind="stable")
        e_lo, base, degree, node, slot = (a[order] for a in (e_lo, base, degree, node, slot))
        acc = np.zeros(total, dtype=np.float64)
        # entries with degree > p form the prefix of length n_with[p]
        n_with = np.searchsorted(-degree, -np.arange(int(degree.max(initial=0))), side="left")
        for p, n_p in enumerate(n_with):
            e = e_lo[:n_p] + p
            term = self.edge_w[e] * values[base[:n_p] + self.edge_src[e]]
            if p == 0:
                acc[:n_p] = term
            else:
                acc[:n_p] += term
        by_code = np.argsort(self.node_code[node], kind="stable")
        lo, hi = int(group[0]), int(group[-1])
        pre[lo:hi] = acc[by_code]
        dest[lo:hi] = slot[by_code]


@dataclass(frozen=True)
class _GenomeProgram:
    """One genome's part of the program: nodes in (level, topological) order."""

    levels: list[int]
    level_sizes: list[int]
    codes: list[int]
    degrees: list[int]
    sources: list[int]
    weights: list[float]
    output_rows: list[int]
    recurrent: bool


def _genome_program(genome: Genome, n_fixed: int) -> _GenomeProgram:
    """Levels, codes and CSR lists of ``genome``'s computed nodes
    (:func:`mentor_core.evolution.network.plan_nodes`), rows renumbered to the robot's block
    (inputs, bias, then the nodes in program order)."""
    planned, outputs = plan_nodes(genome)
    n_genome = len(genome.nodes)  # a source row past it is a previous value (recurrent)
    level_of_row = dict.fromkeys(range(n_fixed), 0)
    for node in planned:  # topological order: sources come first; previous values at level 0
        level_of_row[node.row] = 1 + max(
            [level_of_row[s] for s in node.sources if s < n_genome], default=0
        )
    nodes = sorted(planned, key=lambda p: level_of_row[p.row])  # stable: topological in a level
    block_row = {r: r for r in range(n_fixed)}  # inputs and bias keep their rows
    block_row.update({p.row: n_fixed + k for k, p in enumerate(nodes)})
    n_block = n_fixed + len(nodes)

    def source_row(s: int) -> int:
        return block_row[s] if s < n_genome else n_block + block_row[s - n_genome]

    sources = [source_row(s) for p in nodes for s in p.sources]
    levels = [level_of_row[p.row] for p in nodes]
    n_levels = levels[-1] if levels else 0
    return _GenomeProgram(
        levels=levels,
        level_sizes=[levels.count(lev) for lev in range(1, n_levels + 1)],
        codes=[p.code for p in nodes],
        degrees=[len(p.sources) for p in nodes],
        sources=sources,
        weights=[w for p in nodes for w in p.weights],
        output_rows=[block_row[r] for r in outputs],
        recurrent=any(s >= n_block for s in sources),
    )
