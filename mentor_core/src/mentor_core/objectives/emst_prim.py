"""Exact Euclidean MST length by Prim's algorithm on the fly (numba kernels).

``prim_length`` is the plain algorithm: every step measures the point that just joined the
tree against every point outside it, O(n^2 d) time and O(n d) memory.

``bounded_prim_length`` visits the points in the same order and adds the same edges in the
same order, so it returns the plain kernel's number bit for bit (a test holds it to that). It
skips only measurements that provably cannot shorten a point's link to the tree, where the
plain kernel's ``if dist2 < best`` would be false:

* **float32 filter.** A sweep first measures the newcomer against a centred float32 copy of
  the points (16 numbers a vector instead of 8). A rigorous error bound turns each float32
  squared distance into a lower bound on the true distance; a point is measured exactly
  (float64, dimensions summed in order, as the plain kernel does) only where that bound does
  not already exceed its link ``sqrt(best)``. Float32 alone is not exact: it only filters.
* **drift bounds.** After a sweep every point j keeps ``recheck[j] = LB_j - sqrt(best_j) + D``:
  the lower bound LB_j on its distance to the newcomer, less its link, plus ``D``, the length
  walked so far along the chain of newcomers (an upper bound on each hop). By the triangle
  inequality a later newcomer cannot be nearer to j than its link while the walk since then
  is shorter than that margin, so a step whose newcomer is close to the previous one checks
  only the points with ``recheck[j] <= D``; it sweeps everything when more than one in
  ``_RECHECK_SHARE`` would need it.
* **exact duplicates.** A newcomer equal to the point it hung from measures the same
  distances: its sweep is skipped (tested only when its link is 0, as it is exactly then).

Few slots pass either test (at most 1 in ``_RECHECK_SHARE`` on a recheck, a few percent after
a sweep), so they are flagged in a loop the compiler vectorises and gathered eight flags at a
time (:func:`_compact`): a branch per slot, mispredicted at every pass, cost more than the
sweep's arithmetic.

The outside points stay in the plain kernel's slots (the last one moves into the hole), and the
running minimum is kept per block of ``_BLOCK`` slots with the first slot winning a tie, as the
plain kernel's scan does: equal choices are made alike, so even ties give the same sum. Points
whose float32 copy could overflow go to the plain kernel.

Measured (experiment E005): 1.6x the plain kernel's speed over a paper-scale
generation's point sets (1.0-3x set by set, most where experiences repeat), 1.6-2.2x on 4,000
trajectory-like points in 18-D; the flags and the duplicate test on the link then made it
1.2x faster again on real training sets ("Experience gain: a quarter of a stage-1 generation").
"""

from __future__ import annotations

import numpy as np

from mentor_core.objectives.jit import compiled

# float32 and float64 unit roundoffs
_U32 = 2.0**-24
_U64 = 2.0**-53
# Slots per block of the running minimum (the argmin scans blocks, then one block).
_BLOCK = 64
# A step checks by its drift bounds alone while at most 1 in this many points need it.
_RECHECK_SHARE = 8
# Below this many points the plain kernel is faster than setting up the bounds.
_SMALL = 64
# Largest distance from the centroid whose float32 squares cannot overflow (d <= 1e6).
_FLOAT32_SAFE = 1e15
# Relative slack on travelled lengths, far above their float64 rounding.
_SLACK = 2.0**-40


@compiled()
def prim_length(points: np.ndarray) -> float:  # pragma: no cover - compiled
    """Prim's algorithm on the fly; distances are recomputed, never stored (O(n d) memory).

    The points outside the tree are kept compacted in a (d, m) array (a point joining the tree
    is replaced by the last one), so each step is a branch-free sweep over contiguous rows that
    the compiler vectorises; the squared distance still sums the dimensions in order 0..d-1.
    """
    n, d = points.shape
    if n < 2:
        return 0.0
    outside = np.ascontiguousarray(points[1:].T)  # (d, m) coordinates of the outside points
    best = np.full(n - 1, np.inf)  # squared distance of each outside point to the tree
    dist2 = np.empty(n - 1)
    last = points[0].copy()
    total = 0.0
    for m in range(n - 1, 0, -1):
        dist2[:m] = 0.0
        for k in range(d):
            row = outside[k]
            value = last[k]
            for j in range(m):
                delta = row[j] - value
                dist2[j] += delta * delta
        nearest = 0
        nearest_dist2 = np.inf
        for j in range(m):
            if dist2[j] < best[j]:
                best[j] = dist2[j]
            if best[j] < nearest_dist2:
                nearest_dist2 = best[j]
                nearest = j
        total += np.sqrt(nearest_dist2)
        for k in range(d):
            last[k] = outside[k, nearest]
            outside[k, nearest] = outside[k, m - 1]
        best[nearest] = best[m - 1]
    return total


@compiled(contract=True)
def _sweep32(
    coords: np.ndarray, query: np.ndarray, m: int, acc: np.ndarray
) -> None:  # pragma: no cover - compiled
    """float32 squared distances of slots < m to ``query``; ``coords`` is (d, slots).

    Six dimensions per pass keep the running sums in registers (fewer loads and stores than
    one pass per dimension); each pass is a loop the compiler vectorises.
    """
    d = coords.shape[0]
    k = 0
    while k < d:
        if d - k >= 6:
            r0, r1, r2 = coords[k], coords[k + 1], coords[k + 2]
            r3, r4, r5 = coords[k + 3], coords[k + 4], coords[k + 5]
            q0, q1, q2 = query[k], query[k + 1], query[k + 2]
            q3, q4, q5 = query[k + 3], query[k + 4], query[k + 5]
            if k == 0:
                for j in range(m):
                    t = r0[j] - q0
                    a = t * t
                    t = r1[j] - q1
                    a += t * t
                    t = r2[j] - q2
                    a += t * t
                    t = r3[j] - q3
                    a += t * t
                    t = r4[j] - q4
                    a += t * t
                    t = r5[j] - q5
                    acc[j] = a + t * t
            else:
                for j in range(m):
                    t = r0[j] - q0
                    a = acc[j] + t * t
                    t = r1[j] - q1
                    a += t * t
                    t = r2[j] - q2
                    a += t * t
                    t = r3[j] - q3
                    a += t * t
                    t = r4[j] - q4
                    a += t * t
                    t = r5[j] - q5
                    acc[j] = a + t * t
            k += 6
        else:
            row = coords[k]
            value = query[k]
            if k == 0:
                for j in range(m):
                    t = row[j] - value
                    acc[j] = t * t
            else:
                for j in range(m):
                    t = row[j] - value
                    acc[j] += t * t
            k += 1


@compiled()
def _refresh_rechecks(
    acc: np.ndarray,
    limit32: np.ndarray,
    reach: np.ndarray,
    recheck: np.ndarray,
    m: int,
    scale: float,
    shift: float,
    base: float,
    flags: np.ndarray,
) -> None:  # pragma: no cover - compiled
    """After a sweep, in one pass over j < m: recheck[j] = (lower bound on the distance, from
    ``acc``) - reach[j] + base, and flags[j] = acc[j] < limit32[j] (measure j exactly)."""
    for j in range(m):
        flags[j] = acc[j] < limit32[j]
        bound = np.float64(np.sqrt(acc[j])) * scale - shift
        recheck[j] = (bound - reach[j]) + base


@compiled()
def _block_minimum(
    best: np.ndarray, block: int, m: int
) -> tuple[float, int]:  # pragma: no cover - compiled
    """Smallest ``best`` of the block's slots below m and its first slot (inf if none)."""
    value = np.inf
    slot = block * _BLOCK
    for j in range(block * _BLOCK, min(m, (block + 1) * _BLOCK)):
        if best[j] < value:
            value = best[j]
            slot = j
    return value, slot


@compiled()
def _flag_at_most(
    values: np.ndarray, limit: float, m: int, flags: np.ndarray
) -> None:  # pragma: no cover - compiled
    """flags[j] = values[j] <= limit for j < m."""
    for j in range(m):
        flags[j] = values[j] <= limit


@compiled()
def _compact(
    flags: np.ndarray, m: int, todo: np.ndarray
) -> int:  # pragma: no cover - compiled
    """The flagged slots below m into ``todo`` in ascending order; their count.

    Few slots are flagged (at most 1 in ``_RECHECK_SHARE`` on a recheck, a few percent after
    a sweep), so eight flags are tested at once as one word and only words with a flag are
    unpacked, without a branch per slot (``todo`` has room for 8 past ``m``). The flags from
    m up to the next multiple of 8 are cleared first: a slot removed since is not flagged.
    """
    for j in range(m, (m + 7) // 8 * 8):
        flags[j] = 0
    words = flags.view(np.uint64)
    count = 0
    for w in range((m + 7) // 8):
        if words[w] != 0:
            for j in range(8 * w, 8 * w + 8):
                todo[count] = j
                count += flags[j]
    return count


@compiled()
def _exact_dist2(
    coords: np.ndarray, last: np.ndarray, slots: np.ndarray, count: int, out: np.ndarray
) -> None:  # pragma: no cover - compiled
    """Squared distances of ``slots[:count]`` to ``last``, summed as the plain kernel sums them.

    Two slots at a time: their sums are independent chains the processor overlaps.
    """
    d = coords.shape[1]
    c = 0
    while c + 1 < count:
        j0 = slots[c]
        j1 = slots[c + 1]
        s0 = 0.0
        s1 = 0.0
        for k in range(d):
            value = last[k]
            t0 = coords[j0, k] - value
            t1 = coords[j1, k] - value
            s0 += t0 * t0
            s1 += t1 * t1
        out[c] = s0
        out[c + 1] = s1
        c += 2
    if c < count:
        j0 = slots[c]
        s0 = 0.0
        for k in range(d):
            t0 = coords[j0, k] - last[k]
            s0 += t0 * t0
        out[c] = s0


@compiled()
def _centre_and_spread(points: np.ndarray) -> tuple[np.ndarray, float]:  # pragma: no cover
    """Centroid and the largest distance from it (rounded up by far more than its error)."""
    n, d = points.shape
    centre = np.zeros(d)
    for i in range(n):
        for k in range(d):
            centre[k] += points[i, k]
    for k in range(d):
        centre[k] /= n
    spread = 0.0
    for i in range(n):
        s = 0.0
        for k in range(d):
            t = points[i, k] - centre[k]
            s += t * t
        spread = max(spread, s)
    return centre, np.sqrt(spread) * (1.0 + 1e-6)


@compiled()
def bounded_prim_length(points: np.ndarray) -> float:  # pragma: no cover - compiled
    """``prim_length``'s result, bit for bit, measuring only what can matter (module doc).

    Error bounds (u32, u64 the unit roundoffs): a float32 coordinate is within
    (u32 + 2 u64) |x - centre| (+ 1e-45 for subnormals) of the exact centred value, so a
    float32 distance is within 2 ``err`` of the true one; a float32 squared distance of d
    terms is at most (1 + u32)^(d + 3) = ``grow`` times the squared distance of the float32
    copies. A float64 squared distance is within (d + 3) u64 of the true one, so
    ``reach = sqrt(best) (1 + 2 (d + 8) u64)`` <= the true distance implies ``dist2 >= best``.
    """
    n, d = points.shape
    if n < _SMALL or d == 0:
        return prim_length(points)
    centre, spread = _centre_and_spread(points)
    if not spread <= _FLOAT32_SAFE:
        return prim_length(points)
    err = (_U32 + 2.0 * _U64) * spread * (1.0 + 1e-6) + 1e-45 * np.sqrt(d)
    grow = (1.0 + _U32) ** (d + 3)
    exact_up = 1.0 + 2.0 * (d + 8) * _U64
    exact_down = (1.0 - 2.0 * (d + 8) * _U64) * (1.0 - _SLACK)
    scale32 = (1.0 - 2.0**-22) / np.sqrt(grow) * (1.0 - _SLACK)  # sqrt32 -> lower bound
    shift32 = 2.0 * err

    slots = n - 1
    coords = points[1:].copy()  # exact coordinates, row per slot
    coords32 = np.empty((d, slots), dtype=np.float32)
    for j in range(slots):
        for k in range(d):
            coords32[k, j] = np.float32(points[j + 1, k] - centre[k])
    row = np.arange(1, n)  # slot -> row of ``points``
    best = np.full(slots, np.inf)  # squared link of each outside point (the plain kernel's)
    reach = np.full(slots, np.inf)  # sqrt(best), rounded up
    limit32 = np.full(slots, np.inf, dtype=np.float32)  # float32 sums below this: measure
    recheck = np.full(slots, -np.inf)  # travelled length up to which j needs no check
    parent = np.full(slots, -1)  # row of the tree point that set best
    acc = np.empty(slots, dtype=np.float32)
    todo = np.empty(slots + 8, dtype=np.int64)
    flags = np.zeros((slots + 7) // 8 * 8, dtype=np.uint8)
    exact = np.empty(slots)
    query = np.empty(d, dtype=np.float32)
    n_blocks = (slots + _BLOCK - 1) // _BLOCK
    block_best = np.full(n_blocks, np.inf)
    block_slot = np.zeros(n_blocks, dtype=np.int64)

    last = points[0].copy()
    row_last = 0
    last_parent = -1
    last_link2 = np.inf  # the newcomer's squared link: 0 for a duplicate of its parent
    travelled = 0.0
    total = 0.0
    m = slots
    while m > 0:
        skip = last_parent >= 0 and last_link2 == 0.0  # else it differs from its parent
        if skip:
            for k in range(d):
                if points[last_parent, k] != last[k]:
                    skip = False
                    break
        if not skip:
            edge = travelled * (1.0 + _SLACK)
            due = 0
            for j in range(m):
                due += recheck[j] <= edge
            if due * _RECHECK_SHARE <= m:
                _flag_at_most(recheck, edge, m, flags)
                count = _compact(flags, m, todo)
            else:
                for k in range(d):
                    query[k] = np.float32(last[k] - centre[k])
                _sweep32(coords32, query, m, acc)
                base = travelled * (1.0 - _SLACK)
                _refresh_rechecks(acc, limit32, reach, recheck, m, scale32, shift32, base, flags)
                count = _compact(flags, m, todo)
            _exact_dist2(coords, last, todo, count, exact)
            for c in range(count):
                j = todo[c]
                s = exact[c]
                if s < best[j]:
                    best[j] = s
                    r = np.sqrt(s) * exact_up
                    reach[j] = r
                    u = (r + shift32) * (r + shift32) * grow * (1.0 + 2.0**-40)
                    limit32[j] = np.float32(u * (1.0 + 2.0**-23) + 1e-44)
                    parent[j] = row_last
                    b = j // _BLOCK
                    if s < block_best[b] or (s == block_best[b] and j < block_slot[b]):
                        block_best[b] = s
                        block_slot[b] = j
                recheck[j] = (np.sqrt(s) * exact_down - reach[j]) + travelled * (1.0 - _SLACK)
        # the nearest outside point joins: the first slot of the smallest link
        first = 0
        for b in range(1, (m + _BLOCK - 1) // _BLOCK):
            if block_best[b] < block_best[first]:
                first = b
        nearest = block_slot[first]
        total += np.sqrt(block_best[first])
        last_link2 = block_best[first]
        last_parent = parent[nearest]
        row_last = row[nearest]
        hop = 0.0
        for k in range(d):
            t = coords[nearest, k] - last[k]
            hop += t * t
            last[k] = coords[nearest, k]
            coords[nearest, k] = coords[m - 1, k]
            coords32[k, nearest] = coords32[k, m - 1]
        travelled = (travelled + np.sqrt(hop) * exact_up) * (1.0 + 2.0**-51)
        best[nearest] = best[m - 1]
        reach[nearest] = reach[m - 1]
        limit32[nearest] = limit32[m - 1]
        recheck[nearest] = recheck[m - 1]
        parent[nearest] = parent[m - 1]
        row[nearest] = row[m - 1]
        m -= 1
        for b in (nearest // _BLOCK, m // _BLOCK):
            if b * _BLOCK < m:
                block_best[b], block_slot[b] = _block_minimum(best, b, m)
            elif b < n_blocks:
                block_best[b] = np.inf
    return total
