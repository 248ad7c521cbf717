"""The compiled kernels of :mod:`~mentor_core.navigation.grid_planner`: each cell's clearance
computed when a search first needs it, A* over the cells a disc may stand on, the nearest
such cell, and the cells a segment crosses.

Clearance. A plan touches a small part of a large map, and only distances up to ``cap``
cells matter (beyond the planner's preferred disc every cell is traversable at no extra
cost), so a cell's squared distance to the nearest blocked cell is found when first asked,
by rings about it out to ``cap`` (exact within it: every blocked cell within ``cap`` lies in
the window), and remembered in ``memo`` (-1: not yet; :data:`FAR`: none within ``cap``). The
same integer as ``scipy.ndimage.distance_transform_edt``'s where it is at most ``cap^2``, so
every verdict of the planner on a whole-map transform stays the same.

Search. A* on the 8-connected cells with clearance at least ``need`` (m), a diagonal step
only where the two cells beside it are traversable too, edges of ``r`` and ``sqrt(2) r``
times ``1 + w (q_a + q_b) / 2`` (the clearance cost of the grid planner's docstring), and the
octile distance as heuristic (admissible: no edge weighs less than its length). Its cost is
Dijkstra's on the same graph (the planner before), checked in the tests against
``scipy.sparse.csgraph.dijkstra``; where several paths cost the same it may take another.

Every kernel is compiled by numba without the GIL, so a plan made on another thread leaves
the controller's thread free; without numba they run as Python (slowly, the same results).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

BoolArray = NDArray[np.bool_]
FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
Memo = NDArray[np.int32]
#: what the kernels read clearances from: the obstacle cells padded by one obstacle cell each
#: side, their :func:`block_counts`, the squared clearances found so far (cells; -1 not yet,
#: :data:`FAR` none within the cap), the cap (cells) and the cell side (m)
Field = tuple[BoolArray, Memo, Memo, int, float]
#: a remembered squared distance meaning "no blocked cell within cap"
FAR = np.int32(2**31 - 1)
#: the side (cells) of the blocks whose obstacle counts spare far cells a search
BLOCK = 8
_SQRT2 = math.sqrt(2.0)


def block_counts(blocked: BoolArray) -> Memo:
    """``(ceil(h / B), ceil(w / B))``: the blocked cells of each block of :data:`BLOCK`
    square cells of ``blocked``, so that a cell far from every obstacle (most cells of a
    map) is known to be far from a few blocks' counts."""
    h, w = blocked.shape
    out = np.zeros(((h + BLOCK - 1) // BLOCK, (w + BLOCK - 1) // BLOCK), dtype=np.int32)
    for i in range(h):
        for j in range(w):
            if blocked[i, j]:
                out[i // BLOCK, j // BLOCK] += 1
    return out


def _squared(blocked: BoolArray, blocks: Memo, memo: Memo, row: int, col: int,
             cap: int) -> int:  # fmt: skip
    """Squared distance (cells) from cell ``(row, col)`` to the nearest blocked cell of
    ``blocked`` (the grid padded by one blocked cell on each side; ``blocks`` its
    :func:`block_counts`), :data:`FAR` beyond ``cap``; remembered in ``memo`` (module
    docstring)."""
    known = memo[row, col]
    if known >= 0:
        return int(known)
    h, w = blocked.shape
    pr, pc = row + 1, col + 1  # in the padded mask
    any_blocked = False
    for bi in range(max(pr - cap, 0) // BLOCK, min(pr + cap, h - 1) // BLOCK + 1):
        for bj in range(max(pc - cap, 0) // BLOCK, min(pc + cap, w - 1) // BLOCK + 1):
            if blocks[bi, bj] > 0:
                any_blocked = True
    if not any_blocked:
        memo[row, col] = FAR
        return int(FAR)
    best = int(FAR)
    for d in range(cap + 1):  # the ring of cells d away (Chebyshev)
        if d * d > best:
            break
        r0, r1, c0, c1 = pr - d, pr + d, pc - d, pc + d
        for r in range(max(r0, 0), min(r1, h - 1) + 1):
            edge = r == r0 or r == r1
            step = 1 if edge else max(c1 - c0, 1)
            c = c0
            while c <= c1:
                if 0 <= c < w and blocked[r, c]:
                    dd = (r - pr) * (r - pr) + (c - pc) * (c - pc)
                    if dd < best:
                        best = dd
                c += step
    if best > cap * cap:
        best = int(FAR)
    memo[row, col] = best
    return best


def _clearance(field: Field, row: int, col: int) -> float:
    """Clearance (m) of cell ``(row, col)``: distance from its centre to the nearest blocked
    cell's, ``inf`` beyond the cap. The memo is read here, before any call: a compiled call
    that passes arrays counts their references, some 50 ns, a hundred times the read."""
    dd = field[2][row, col]
    if dd < 0:
        dd = _squared(field[0], field[1], field[2], row, col, field[3])
    return _metres(dd, field[4])


def _penalty(clear: float, r: float, preferred: float, span: float) -> float:
    """The clearance cost's ``q`` of a cell of clearance ``clear`` (grid planner docstring)."""
    if span <= 0.0:
        return 0.0
    kept = clear - _SQRT2 * r
    return min(max((preferred - kept) / span, 0.0), 1.0)


def _astar(field: Field, need: float, preferred: float, span: float, cost: float, source: int,
           target: int) -> IntArray:  # fmt: skip
    """Flat cell indices of a cheapest path ``source -> target`` (module docstring), empty
    when there is none; both must be traversable.

    The heap (f, then h: the entry nearer the target first) and the memo reads are written
    out here rather than called: a compiled call that passes arrays counts their references,
    which cost a plan on a large map more than the search itself."""
    blocked, blocks, memo, cap, r = field
    h, w = memo.shape
    seen = np.zeros(h * w, dtype=np.uint8)  # 1 open, 2 closed
    g = np.empty(h * w, dtype=np.float64)
    parent = np.empty(h * w, dtype=np.int32)  # a map holds fewer than 2^31 cells
    heap = np.empty((1024, 3), dtype=np.float64)  # f, h, node
    tr, tc = target // w, target % w
    g[source] = 0.0
    parent[source] = -1
    seen[source] = 1
    est = _octile(source // w, source % w, tr, tc, r)
    heap[0, 0], heap[0, 1], heap[0, 2] = est, est, source
    size = 1
    dr = (0, 1, 0, -1, 1, 1, -1, -1)
    dc = (1, 0, -1, 0, 1, -1, -1, 1)
    while size > 0:
        node = int(heap[0, 2])
        size -= 1
        heap[0] = heap[size]  # sift down
        i = 0
        while True:
            a, b, m = 2 * i + 1, 2 * i + 2, i
            for c in (a, b):  # the children in the heap
                if c < size:
                    fc, fm = heap[c, 0], heap[m, 0]
                    if fc < fm or (fc == fm and heap[c, 1] < heap[m, 1]):
                        m = c
            if m == i:
                break
            for k in range(3):
                heap[i, k], heap[m, k] = heap[m, k], heap[i, k]
            i = m
        if seen[node] == 2:
            continue  # an outdated entry
        seen[node] = 2
        if node == target:
            break
        row, col = node // w, node % w
        q_here = 0.0
        if cost > 0.0:
            dd = memo[row, col]
            if dd < 0:  # the source, when no one asked before
                dd = _squared(blocked, blocks, memo, row, col, cap)
            q_here = _penalty(_metres(dd, r), r, preferred, span)
        for k in range(8):
            nr, nc = row + dr[k], col + dc[k]
            if nr < 0 or nc < 0 or nr >= h or nc >= w:
                continue
            nb = nr * w + nc
            if seen[nb] == 2:
                continue
            dd = memo[nr, nc]
            if dd < 0:
                dd = _squared(blocked, blocks, memo, nr, nc, cap)
            clear = _metres(dd, r)
            if not clear >= need:
                continue
            length = r
            if k >= 4:  # diagonal: both cells beside the step traversable too
                d1, d2 = memo[row, nc], memo[nr, col]
                if d1 < 0:
                    d1 = _squared(blocked, blocks, memo, row, nc, cap)
                if d2 < 0:
                    d2 = _squared(blocked, blocks, memo, nr, col, cap)
                if not (_metres(d1, r) >= need and _metres(d2, r) >= need):
                    continue
                length = _SQRT2 * r
            step = length
            if cost > 0.0:
                q = _penalty(clear, r, preferred, span)
                step = length * (1.0 + cost * (q_here + q) / 2.0)
            new = g[node] + step
            if seen[nb] == 0 or new < g[nb]:
                g[nb] = new
                parent[nb] = node
                seen[nb] = 1
                est = _octile(nr, nc, tr, tc, r)
                if size == heap.shape[0]:
                    grown = np.empty((2 * size, 3), dtype=np.float64)
                    grown[:size] = heap
                    heap = grown
                i = size  # sift up
                heap[i, 0], heap[i, 1], heap[i, 2] = new + est, est, nb
                size += 1
                while i > 0:
                    up = (i - 1) // 2
                    fi, fu = heap[i, 0], heap[up, 0]
                    if not (fi < fu or (fi == fu and heap[i, 1] < heap[up, 1])):
                        break
                    for k2 in range(3):
                        heap[i, k2], heap[up, k2] = heap[up, k2], heap[i, k2]
                    i = up
    if seen[target] != 2:
        return np.empty(0, dtype=np.int64)
    n = 1
    at = target
    while parent[at] >= 0:
        at = parent[at]
        n += 1
    out = np.empty(n, dtype=np.int64)
    at = target
    for i in range(n - 1, -1, -1):
        out[i] = at
        at = parent[at]
    return out


def _metres(dd: int, r: float) -> float:
    """The clearance (m) of a squared clearance ``dd`` (cells): inf for :data:`FAR`."""
    return math.inf if dd == FAR else math.sqrt(float(dd)) * r


def _octile(r0: int, c0: int, r1: int, c1: int, r: float) -> float:
    a, b = abs(r1 - r0), abs(c1 - c0)
    lo, hi = min(a, b), max(a, b)
    return ((hi - lo) + _SQRT2 * lo) * r


def _nearest(field: Field, need: float, row: int, col: int, reach: int) -> int:
    """Flat index of the traversable cell nearest cell ``(row, col)`` (in cells; the first in
    row-major order among equals) within ``reach`` cells, -1 when there is none."""
    h, w = field[2].shape
    best, found = (reach + 1) * (reach + 1) * 2 + 1, -1
    for rr in range(max(row - reach, 0), min(row + reach, h - 1) + 1):
        for cc in range(max(col - reach, 0), min(col + reach, w - 1) + 1):
            dd = (rr - row) * (rr - row) + (cc - col) * (cc - col)
            if dd < best and _clearance(field, rr, cc) >= need:
                best, found = dd, rr * w + cc
    return found


def _along(ax: float, ay: float, bx: float, by: float, x0: float, y0: float, c: float,
           s: float, field: Field, need: float, preferred: float, span: float, cost: float,
           weighted: bool) -> float:  # fmt: skip
    """The segment ``a -> b`` (``map``) on a grid of origin ``(x0, y0)``, heading ``(cos,
    sin) = (c, s)`` and cells of ``r`` m: inf unless every cell it crosses (the cells of the
    midpoints between its successive grid-line crossings) lies on the grid and has a
    clearance of at least ``need``; else its length (m), each cell's share times its ``1 + w
    q`` when ``weighted``."""
    r = field[4]
    px, py = (c * (ax - x0) + s * (ay - y0)) / r, (-s * (ax - x0) + c * (ay - y0)) / r
    qx, qy = (c * (bx - x0) + s * (by - y0)) / r, (-s * (bx - x0) + c * (by - y0)) / r
    dx, dy = qx - px, qy - py
    # the grid lines it crosses across each axis: the first, how many, in the order met
    nx = ny = 0
    fx = fy = 0.0
    if dx != 0.0:
        fx = float(math.ceil(min(px, qx)))
        nx = max(0, math.floor(max(px, qx)) - int(fx) + 1)
    if dy != 0.0:
        fy = float(math.ceil(min(py, qy)))
        ny = max(0, math.floor(max(py, qy)) - int(fy) + 1)
    h, w = field[2].shape
    length = math.hypot(dx, dy) * r
    total = 0.0
    # the crossings of both axes merged in increasing t, clipped to [0, 1], each value
    # once (np.unique's), without an array: a long segment of a large map allocates nothing
    i = j = 0
    prev = 0.0
    while True:
        if i < nx or j < ny:
            tx = ty = 2.0
            if i < nx:
                k = i if dx > 0.0 else nx - 1 - i
                tx = min(max(((fx + k) - px) / dx, 0.0), 1.0)
            if j < ny:
                k = j if dy > 0.0 else ny - 1 - j
                ty = min(max(((fy + k) - py) / dy, 0.0), 1.0)
            if tx <= ty:
                t = tx
                i += 1
            else:
                t = ty
                j += 1
        elif prev < 1.0:
            t = 1.0
        else:
            break
        if t <= prev:
            continue  # the same value again (a corner, or clipped)
        m = (prev + t) / 2.0
        col, row = math.floor(px + m * dx), math.floor(py + m * dy)
        if row < 0 or col < 0 or row >= h or col >= w:
            return math.inf
        clear = _clearance(field, row, col)
        if not clear >= need:
            return math.inf
        weight = 1.0
        if weighted:
            weight = 1.0 + cost * _penalty(clear, r, preferred, span)
        total += (t - prev) * length * weight
        prev = t
    return total


def _shortcut(points: FloatArray, x0: float, y0: float, c: float, s: float, field: Field,
              need: float, preferred: float, span: float, cost: float) -> IntArray:  # fmt: skip
    """Indices of the points kept when the path ``points`` ``(k, 2)`` is pulled straight:
    from each kept point, the farthest next one in sight (the grid planner's step 3; with
    ``cost`` > 0 the farthest whose straight segment costs no more than the points it
    skips)."""
    n = points.shape[0]
    along = np.zeros(n, dtype=np.float64)
    costly = cost > 0.0
    if costly:
        for k in range(n - 1):
            along[k + 1] = along[k] + _along(points[k, 0], points[k, 1], points[k + 1, 0],
                                             points[k + 1, 1], x0, y0, c, s, field, need,
                                             preferred, span, cost, True)  # fmt: skip
    keep = np.empty(n, dtype=np.int64)
    keep[0] = 0
    kept = 1
    i, last = 0, n - 1
    while i < last:
        j = i + 1
        while j < last:
            seg = _along(points[i, 0], points[i, 1], points[j + 1, 0], points[j + 1, 1],
                         x0, y0, c, s, field, need, preferred, span, cost, costly)  # fmt: skip
            if costly:
                if not seg <= (along[j + 1] - along[i]) * (1.0 + 1e-9):
                    break
            elif not math.isfinite(seg):
                break
            j += 1
        keep[kept] = j
        kept += 1
        i = j
    return keep[:kept]


try:
    from numba import njit

    # callees first, so that the kernels calling them compile against them; the small
    # ones inlined (a call passes the field's arrays, counting their references each time)
    block_counts = njit(cache=True, nogil=True)(block_counts)
    _squared = njit(cache=True, nogil=True)(_squared)
    _clearance = njit(cache=True, nogil=True, inline="always")(_clearance)
    _metres = njit(cache=True, nogil=True, inline="always")(_metres)
    _penalty = njit(cache=True, nogil=True, inline="always")(_penalty)
    _octile = njit(cache=True, nogil=True, inline="always")(_octile)
    _astar = njit(cache=True, nogil=True)(_astar)
    _nearest = njit(cache=True, nogil=True)(_nearest)
    _along = njit(cache=True, nogil=True)(_along)
    _shortcut = njit(cache=True, nogil=True)(_shortcut)
except ImportError:  # pragma: no cover - numba is in the lock file; Python stays the fallback
    pass


def astar(field: Field, need: float, preferred: float, span: float, cost: float, source: int,
          target: int) -> IntArray:  # fmt: skip
    """:func:`_astar`, compiled where numba is there (module docstring)."""
    return _astar(field, need, preferred, span, cost, source, target)


def nearest(field: Field, need: float, row: int, col: int, reach: int) -> int:
    """:func:`_nearest`, compiled where numba is there."""
    return int(_nearest(field, need, row, col, reach))


def along(a: tuple[float, float], b: tuple[float, float],
          frame: tuple[float, float, float, float], field: Field, need: float,
          preferred: float, span: float, cost: float, weighted: bool) -> float:  # fmt: skip
    """:func:`_along` from ``a`` to ``b`` on a grid of ``frame`` ``(x0, y0, cos, sin)``,
    compiled where numba is there."""
    x0, y0, c, s = frame
    return float(_along(a[0], a[1], b[0], b[1], x0, y0, c, s, field, need, preferred, span,
                        cost, weighted))  # fmt: skip


def shortcut(points: FloatArray, frame: tuple[float, float, float, float], field: Field,
             need: float, preferred: float, span: float, cost: float) -> IntArray:
    """:func:`_shortcut`, compiled where numba is there."""
    x0, y0, c, s = frame
    return _shortcut(np.ascontiguousarray(points, dtype=np.float64), x0, y0, c, s, field, need,
                     preferred, span, cost)  # fmt: skip


def clearance(field: Field, row: int, col: int) -> float:
    """Clearance (m) of cell ``(row, col)`` (module docstring), inf beyond the cap."""
    return float(_clearance(field, row, col))
