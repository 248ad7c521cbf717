"""World families: seeded, procedurally generated layouts of kinds the paper's DoE never
draws (the benchmark's worlds, and training worlds for a curriculum).

Each family is a pure function ``(size, rng) -> World``: the same generator state gives the
same world. Layouts are drawn on the unit square and scaled to the arena side ``size`` (m), so
each robot gets them at its own scale (the UGV's 12 m test arena, the Swarm-Robot's 4 m; the
bodies are 3.2 % and 2.5 % of those sides, so every passage below, at least 8 % of the side,
is at least 2.5 body diagonals wide). Walls are ``WALL`` (2.5 % of the side: 0.3 m and
0.1 m) thick, as the training DoE's walls.

* ``rooms``: 2-3 x 2-3 rooms; a random spanning tree of the rooms gets doorways (8-14 % of
  the side), every other shared wall one with probability 0.35; 0-2 boxes of furniture per
  room, clear of its walls.
* ``corridors``: a corridor 9-13 % of the side wide along a self-avoiding walk of 5-10 cells
  on a 4 x 4 or 5 x 5 grid, with 1-2 dead-end branches; everything else is solid.
* ``slalom``: 3-5 walls across the arena, alternately from either side, each closing 55-75 %
  of it (in one of the square's 8 orientations).
* ``traps``: 2-3 U-shaped traps and dead ends (inner width 10-35 % of the side, depth
  18-40 %), randomly turned, with a passage of 10 % round each.
* ``forest_sparse``, ``forest_medium``, ``forest_dense``: 10, 24 and 40 boxes (sides 3-8 % of
  the side) at least 6 % apart (fewer when no more fit).
* ``maze``: a perfect maze on a 5 x 5 or 6 x 6 grid (randomised depth-first search), each
  remaining inner wall removed with probability 0.1 so that some have loops.
* ``doe``: the paper's composite DoE world (``mentor_core.sim.scenarios.sample_world``, its
  default config: small boxes in four grids, no walls), as training draws it.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from itertools import pairwise

import numpy as np
from numpy.typing import NDArray

from mentor_core.sim.scenarios import sample_world
from mentor_core.sim.world import World

FloatArray = NDArray[np.float64]
Box = tuple[float, float, float, float]
Family = Callable[[float, np.random.Generator], World]

WALL = 0.025  # wall thickness / arena side
DOOR = (0.08, 0.14)  # doorway width / arena side
PASSAGE = 0.10  # least passage round a trap / arena side
_TRIES = 400  # placement draws of one family's objects


def _world(size: float, boxes: Sequence[Box], name: str) -> World:
    """A world of side ``size`` from boxes on the unit square."""
    arr = np.asarray(boxes, dtype=np.float64).reshape(-1, 4) * size
    return World(size=size, obstacles=np.clip(arr, 0.0, size), name=name)


def _apart(a: Box, b: Box, gap: float) -> bool:
    """True when boxes a and b are at least ``gap`` apart along x or along y."""
    return bool(min(a[2], b[2]) - max(a[0], b[0]) <= -gap
                or min(a[3], b[3]) - max(a[1], b[1]) <= -gap)  # fmt: skip


def _symmetry(boxes: Sequence[Box], k: int) -> list[Box]:
    """Boxes under symmetry ``k`` (0-7) of the unit square: bit 0 flips x, bit 1 flips y,
    bit 2 swaps x and y."""
    out = []
    for x0, y0, x1, y1 in boxes:
        if k & 1:
            x0, x1 = 1.0 - x1, 1.0 - x0
        if k & 2:
            y0, y1 = 1.0 - y1, 1.0 - y0
        if k & 4:
            x0, y0, x1, y1 = y0, x0, y1, x1
        out.append((x0, y0, x1, y1))
    return out


def _grid_walls(
    xs: Sequence[float], ys: Sequence[float], v_gap: dict[tuple[int, int], tuple[float, float]],
    h_gap: dict[tuple[int, int], tuple[float, float]],
) -> list[Box]:
    """Walls on the inner lines of a grid with lines ``xs``, ``ys`` (0 and 1 included).

    Vertical wall ``(i, j)``: on line ``xs[i]`` (inner ``i``) between ``ys[j]`` and
    ``ys[j + 1]``; horizontal ``(i, j)``: on line ``ys[j]`` between ``xs[i]`` and
    ``xs[i + 1]``. A wall listed in ``v_gap``/``h_gap`` has an opening ``(centre, width)``
    along it (width >= the wall's length: no wall at all). Square posts join the walls where
    inner lines cross, so no two boxes overlap.
    """
    half = 0.5 * WALL
    boxes: list[Box] = []
    walled: set[tuple[int, int]] = set()  # crossings (i, j) with a wall ending there
    for vertical in (True, False):
        lines, across = (xs, ys) if vertical else (ys, xs)
        gaps = v_gap if vertical else h_gap
        for i in range(1, len(lines) - 1):
            for j in range(len(across) - 1):
                lo = across[j] + (half if j > 0 else 0.0)
                hi = across[j + 1] - (half if j + 1 < len(across) - 1 else 0.0)
                key = (i, j) if vertical else (j, i)
                centre, width = gaps.get(key, (0.0, 0.0))
                pieces = [(lo, hi)] if width <= 0.0 else [
                    (lo, centre - 0.5 * width), (centre + 0.5 * width, hi)]
                pieces = [(a, b) for a, b in pieces if b - a > 1e-9]
                for a, b in pieces:
                    c = lines[i]
                    boxes.append((c - half, a, c + half, b) if vertical
                                 else (a, c - half, b, c + half))  # fmt: skip
                if pieces:
                    ends = ((i, j), (i, j + 1)) if vertical else ((j, i), (j + 1, i))
                    walled.update(ends)
    for i, j in sorted(walled):
        if 0 < i < len(xs) - 1 and 0 < j < len(ys) - 1:
            boxes.append((xs[i] - half, ys[j] - half, xs[i] + half, ys[j] + half))
    return boxes


def _spanning_tree(cols: int, rows: int, rng: np.random.Generator) -> set[tuple[int, int]]:
    """Edges ``(a, b)`` (cell ids ``i + cols * j``, a < b) of a random spanning tree of the
    grid's cells: randomised depth-first search from a random cell."""
    n = cols * rows
    seen = {int(rng.integers(n))}
    stack = list(seen)
    edges: set[tuple[int, int]] = set()
    while stack:
        c = stack[-1]
        i, j = c % cols, c // cols
        options = [x + cols * y for x, y in ((i - 1, j), (i + 1, j), (i, j - 1), (i, j + 1))
                   if 0 <= x < cols and 0 <= y < rows and x + cols * y not in seen]  # fmt: skip
        if not options:
            stack.pop()
            continue
        nxt = options[int(rng.integers(len(options)))]
        seen.add(nxt)
        stack.append(nxt)
        edges.add((min(c, nxt), max(c, nxt)))
    return edges


def _lines(count: int, jitter: float, rng: np.random.Generator) -> list[float]:
    """``count + 1`` grid lines from 0 to 1, inner ones jittered by ``jitter / count``."""
    inner = [(k + rng.uniform(-jitter, jitter)) / count for k in range(1, count)]
    return [0.0, *inner, 1.0]


def _cell_walls(
    xs: Sequence[float], ys: Sequence[float], open_edges: set[tuple[int, int]],
    door: Callable[[float, float], tuple[float, float]],
) -> tuple[dict[tuple[int, int], tuple[float, float]], dict[tuple[int, int], tuple[float, float]]]:
    """Openings of :func:`_grid_walls` for the cells' shared walls in ``open_edges`` (pairs of
    cell ids), each ``door(lo, hi)`` on the wall from ``lo`` to ``hi``."""
    cols = len(xs) - 1
    v_gap: dict[tuple[int, int], tuple[float, float]] = {}
    h_gap: dict[tuple[int, int], tuple[float, float]] = {}
    for a, b in sorted(open_edges):
        i, j = a % cols, a // cols
        if b == a + 1:  # neighbour on the right: vertical wall on line i + 1
            v_gap[(i + 1, j)] = door(ys[j], ys[j + 1])
        else:  # neighbour above: horizontal wall on line j + 1
            h_gap[(i, j + 1)] = door(xs[i], xs[i + 1])
    return v_gap, h_gap


def _neighbours(cols: int, rows: int) -> list[tuple[int, int]]:
    """Every pair ``(a, b)`` of side-by-side cells, a < b."""
    pairs = []
    for c in range(cols * rows):
        if c % cols + 1 < cols:
            pairs.append((c, c + 1))
        if c // cols + 1 < rows:
            pairs.append((c, c + cols))
    return pairs


def rooms(size: float, rng: np.random.Generator) -> World:
    """Rooms joined by doorways (module docstring)."""
    cols, rows = int(rng.integers(2, 4)), int(rng.integers(2, 4))
    xs, ys = _lines(cols, 0.2, rng), _lines(rows, 0.2, rng)
    doors = _spanning_tree(cols, rows, rng)
    doors |= {e for e in _neighbours(cols, rows) if e not in doors and rng.random() < 0.35}

    def door(lo: float, hi: float) -> tuple[float, float]:
        width = rng.uniform(*DOOR)
        # a wall too short for the door drawn gets the widest that fits (seeds 169, 174 and
        # 198 of the validation split's rooms raised "high - low < 0" before)
        width = min(width, max(hi - lo - 2.0 * (WALL + 0.02), 0.0))
        margin = WALL + 0.02 + 0.5 * width
        if lo + margin > hi - margin:
            return 0.5 * (lo + hi), width
        return rng.uniform(lo + margin, hi - margin), width

    v_gap, h_gap = _cell_walls(xs, ys, doors, door)
    boxes = _grid_walls(xs, ys, v_gap, h_gap)
    clear = 0.12  # furniture keeps this far from its room's walls, so doorways stay free
    for j in range(rows):
        for i in range(cols):
            placed: list[Box] = []
            for _ in range(int(rng.integers(0, 3))):
                w, h = rng.uniform(0.04, 0.08, 2)
                x0 = rng.uniform(xs[i] + clear, max(xs[i] + clear, xs[i + 1] - clear - w))
                y0 = rng.uniform(ys[j] + clear, max(ys[j] + clear, ys[j + 1] - clear - h))
                box = (x0, y0, min(x0 + w, xs[i + 1] - clear), min(y0 + h, ys[j + 1] - clear))
                if box[2] > box[0] and box[3] > box[1] and all(
                        _apart(box, b, PASSAGE) for b in placed):
                    placed.append(box)
            boxes += placed
    return _world(size, boxes, "rooms")


def maze(size: float, rng: np.random.Generator) -> World:
    """A small maze (module docstring)."""
    n = int(rng.integers(5, 7))
    lines = [k / n for k in range(n + 1)]
    opened = _spanning_tree(n, n, rng)
    opened |= {e for e in _neighbours(n, n) if e not in opened and rng.random() < 0.1}
    v_gap, h_gap = _cell_walls(lines, lines, opened, lambda lo, hi: (0.5 * (lo + hi), 2.0))
    return _world(size, _grid_walls(lines, lines, v_gap, h_gap), "maze")


def corridors(size: float, rng: np.random.Generator) -> World:
    """A corridor with turns and dead-end branches (module docstring)."""
    n = int(rng.integers(4, 6))
    width = rng.uniform(0.09, 0.13)
    walk = [(int(rng.integers(n)), int(rng.integers(n)))]
    target = int(rng.integers(5, 11))
    while len(walk) < target:
        options = _free_steps(walk[-1], set(walk), n)
        if not options:
            break
        walk.append(options[int(rng.integers(len(options)))])
    edges = list(pairwise(walk))
    taken = set(walk)
    for _ in range(int(rng.integers(1, 3))):  # dead ends: 1-2 cells off the walk
        cell = walk[int(rng.integers(len(walk)))]
        for _ in range(int(rng.integers(1, 3))):
            options = _free_steps(cell, taken, n)
            if not options:
                break
            nxt = options[int(rng.integers(len(options)))]
            edges.append((cell, nxt))
            taken.add(nxt)
            cell = nxt
    free = []
    for (i0, j0), (i1, j1) in edges:
        cx0, cy0 = (i0 + 0.5) / n, (j0 + 0.5) / n
        cx1, cy1 = (i1 + 0.5) / n, (j1 + 0.5) / n
        half = 0.5 * width
        free.append((min(cx0, cx1) - half, min(cy0, cy1) - half,
                     max(cx0, cx1) + half, max(cy0, cy1) + half))  # fmt: skip
    return _world(size, _complement(free), "corridors")


def _free_steps(cell: tuple[int, int], taken: set[tuple[int, int]], n: int) -> list[
        tuple[int, int]]:
    i, j = cell
    return [(x, y) for x, y in ((i - 1, j), (i + 1, j), (i, j - 1), (i, j + 1))
            if 0 <= x < n and 0 <= y < n and (x, y) not in taken]  # fmt: skip


def _complement(free: Sequence[Box]) -> list[Box]:
    """Boxes covering the unit square outside the union of ``free`` boxes, none overlapping:
    the grid of every box edge, its blocked cells merged into runs along x, and runs of equal
    extent merged along y."""
    xs = sorted({0.0, 1.0, *(v for b in free for v in (b[0], b[2]))})
    ys = sorted({0.0, 1.0, *(v for b in free for v in (b[1], b[3]))})
    fb = np.asarray(free, dtype=np.float64).reshape(-1, 4)
    cx = 0.5 * (np.asarray(xs[:-1]) + np.asarray(xs[1:]))
    cy = 0.5 * (np.asarray(ys[:-1]) + np.asarray(ys[1:]))
    gx, gy = np.meshgrid(cx, cy, indexing="xy")  # (rows, cols)
    open_ = ((fb[:, 0, None, None] < gx) & (gx < fb[:, 2, None, None])
             & (fb[:, 1, None, None] < gy) & (gy < fb[:, 3, None, None])).any(axis=0)
    runs: dict[tuple[int, int], list[int]] = {}  # (x from, x to) -> rows, in order
    for r in range(len(cy)):
        c = 0
        while c < len(cx):
            if open_[r, c]:
                c += 1
                continue
            start = c
            while c < len(cx) and not open_[r, c]:
                c += 1
            runs.setdefault((start, c), []).append(r)
    boxes: list[Box] = []
    for (c0, c1), rows_ in sorted(runs.items()):
        first = prev = rows_[0]
        for r in [*rows_[1:], -1]:
            if r != prev + 1:
                boxes.append((xs[c0], ys[first], xs[c1], ys[prev + 1]))
                first = r
            prev = r
    return boxes


def slalom(size: float, rng: np.random.Generator) -> World:
    """Slalom walls (module docstring)."""
    n = int(rng.integers(3, 6))
    half = 0.5 * WALL
    boxes = []
    for k in range(n):
        x = (k + 0.5 + rng.uniform(-0.15, 0.15)) / n
        reach = rng.uniform(0.55, 0.75)
        y0, y1 = (0.0, reach) if k % 2 == 0 else (1.0 - reach, 1.0)
        boxes.append((x - half, y0, x + half, y1))
    return _world(size, _symmetry(boxes, int(rng.integers(8))), "slalom")


def traps(size: float, rng: np.random.Generator) -> World:
    """U-shaped traps and dead ends (module docstring)."""
    placed: list[Box] = []  # bounding boxes
    boxes: list[Box] = []
    want = int(rng.integers(2, 4))
    for _ in range(_TRIES):
        if len(placed) == want:
            break
        inner = rng.uniform(0.10, 0.35)
        depth = rng.uniform(0.18, 0.40)
        outer = inner + 2 * WALL
        turn = int(rng.integers(4))  # opening up, right, down, left
        w, h = (outer, depth) if turn % 2 == 0 else (depth, outer)
        if w > 1.0 - 2 * PASSAGE or h > 1.0 - 2 * PASSAGE:
            continue
        x0 = rng.uniform(PASSAGE, 1.0 - PASSAGE - w)
        y0 = rng.uniform(PASSAGE, 1.0 - PASSAGE - h)
        bound = (x0, y0, x0 + w, y0 + h)
        if not all(_apart(bound, b, PASSAGE) for b in placed):
            continue
        placed.append(bound)
        # a U opening up in its own frame [0, outer] x [0, depth], then turned
        local = [(0.0, 0.0, outer, WALL), (0.0, WALL, WALL, depth),
                 (outer - WALL, WALL, outer, depth)]  # fmt: skip
        boxes += [_place(b, turn, outer, depth, x0, y0) for b in local]
    return _world(size, boxes, "traps")


def _place(b: Box, turn: int, outer: float, depth: float, x0: float, y0: float) -> Box:
    """Box ``b`` of a U in its frame ``[0, outer] x [0, depth]`` turned by ``turn`` quarter
    turns (opening up, right, down, left) and moved to ``(x0, y0)``."""
    u0, v0, u1, v1 = b
    if turn == 0:
        r = (u0, v0, u1, v1)
    elif turn == 1:  # opening right: the base on the left
        r = (v0, u0, v1, u1)
    elif turn == 2:  # opening down: the base on top
        r = (u0, depth - v1, u1, depth - v0)
    else:  # opening left: the base on the right
        r = (depth - v1, u0, depth - v0, u1)
    return (r[0] + x0, r[1] + y0, r[2] + x0, r[3] + y0)


def _forest(count: int) -> Family:
    def forest(size: float, rng: np.random.Generator) -> World:
        placed: list[Box] = []
        for _ in range(_TRIES):
            if len(placed) == count:
                break
            w, h = rng.uniform(0.03, 0.08, 2)
            x0, y0 = rng.uniform(0.0, 1.0 - w), rng.uniform(0.0, 1.0 - h)
            box = (x0, y0, x0 + w, y0 + h)
            if all(_apart(box, b, 0.06) for b in placed):
                placed.append(box)
        return _world(size, placed, "forest")

    return forest


def doe(size: float, rng: np.random.Generator) -> World:
    """The paper's DoE world (module docstring)."""
    return sample_world(size, rng)


#: name -> (code, generator); the code enters the seed, so a family's worlds never change
#: when families are added or reordered
FAMILIES: dict[str, tuple[int, Family]] = {
    "rooms": (1, rooms),
    "corridors": (2, corridors),
    "slalom": (3, slalom),
    "traps": (4, traps),
    "forest_sparse": (5, _forest(10)),
    "forest_medium": (6, _forest(24)),
    "forest_dense": (7, _forest(40)),
    "maze": (8, maze),
    "doe": (9, doe),
}


def family_names_fault(names: Sequence[str]) -> str | None:
    """Why ``names`` is not a list of distinct families of :data:`FAMILIES` (a config key's
    message), or None when it is."""
    if any(f not in FAMILIES for f in names) or len(set(names)) != len(names):
        return f"must be distinct world families of {', '.join(FAMILIES)}, got {list(names)}"
    return None
