"""How much of Prim's work on a generation's experience points could exact pruning skip?

    .venv/bin/python benchmarks/perf/emst_pruning_probe.py [--config FILE] [--sets 10]
        [--blocks 16 32 64]

Simulates a paper-scale generation of the config's training problem (100 evolved-looking
genomes, as ``generation_bench.py``), then runs a plain Prim on the first ``--sets`` point sets
and counts, over all (newcomer, outside point) pairs that Prim measures:

* ``shorten``: the pairs that really shorten the outside point's link (work no exact method
  avoids: each must be measured exactly);
* ``projection <p>``: the pairs whose distance over the first p principal components (a lower
  bound of the distance: an orthogonal projection) is still below the link, so a screen on
  those p coordinates alone could not skip them; ``raw <p>`` the same over the first p
  coordinates as they come;
* ``block <B>``: the share of the pairs in blocks of B points (in kd-tree order, principal
  components) whose bounding box lies nearer to the newcomer than the block's largest link,
  so a box bound could not skip the block.

Also times a full float32 screening sweep per pair (the bounded kernel's ``_sweep32``), the
least a Prim that looks at every pair spends. Prints JSON. experiment E007,
"Experience gain: what exact pruning could skip".
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np

from mentor_core.objectives.emst_prim import _sweep32
from mentor_core.objectives.jit import compiled
from mentor_core.training.config import TrainerConfig
from mentor_core.training.trainer import make_problem

DEFAULT_CONFIG = "mentor_core/src/mentor_core/configs/train_ugv_paper.yaml"
PREFIXES = (1, 2, 3, 4, 6, 8, 12)


@compiled()
def join_nearest(inside: np.ndarray, best: np.ndarray) -> int:  # pragma: no cover - compiled
    """Prim's step: the outside point of the smallest link joins the tree; its index."""
    nearest, value = -1, np.inf
    for j in range(len(best)):
        if not inside[j] and best[j] < value:
            value, nearest = best[j], j
    inside[nearest] = True
    return nearest


@compiled()
def prefix_counts(points: np.ndarray, prefixes: np.ndarray) -> np.ndarray:  # pragma: no cover
    """[pairs, shorten, below-link over each prefix of the coordinates...] of a plain Prim."""
    n, d = points.shape
    inside = np.zeros(n, np.bool_)
    best = np.full(n, np.inf)
    counts = np.zeros(len(prefixes) + 2)
    inside[0] = True
    last = 0
    for _ in range(n - 1):
        for j in range(n):
            if inside[j]:
                continue
            counts[0] += 1
            s = 0.0
            p = 0
            for k in range(d):
                t = points[j, k] - points[last, k]
                s += t * t
                if p < len(prefixes) and k + 1 == prefixes[p]:
                    counts[2 + p] += s < best[j]
                    p += 1
            if s < best[j]:
                best[j] = s
                counts[1] += 1
        last = join_nearest(inside, best)
    return counts


@compiled()
def block_share(points: np.ndarray, size: int) -> float:  # pragma: no cover - compiled
    """Share of Prim's pairs in blocks of ``size`` rows whose box bound cannot skip them."""
    n, d = points.shape
    blocks = (n + size - 1) // size
    lo = np.full((blocks, d), np.inf)
    hi = np.full((blocks, d), -np.inf)
    for j in range(n):
        b = j // size
        for k in range(d):
            lo[b, k] = min(lo[b, k], points[j, k])
            hi[b, k] = max(hi[b, k], points[j, k])
    inside = np.zeros(n, np.bool_)
    best = np.full(n, np.inf)
    largest = np.full(blocks, np.inf)  # the block's largest link (inf: not yet swept)
    inside[0] = True
    last = 0
    swept = 0.0
    total = 0.0
    for _ in range(n - 1):
        for b in range(blocks):
            gap = 0.0
            for k in range(d):
                q = points[last, k]
                t = max(lo[b, k] - q, q - hi[b, k], 0.0)
                gap += t * t
            count = 0
            for j in range(b * size, min(n, (b + 1) * size)):
                count += not inside[j]
            total += count
            if count == 0 or gap >= largest[b]:
                continue
            swept += count
            top = 0.0
            for j in range(b * size, min(n, (b + 1) * size)):
                if inside[j]:
                    continue
                s = 0.0
                for k in range(d):
                    t = points[j, k] - points[last, k]
                    s += t * t
                best[j] = min(best[j], s)
                top = max(top, best[j])
            largest[b] = top
        last = join_nearest(inside, best)
    return swept / total


@compiled()
def screen_all(coords: np.ndarray, query: np.ndarray, acc: np.ndarray) -> None:  # pragma: no cover
    """The float32 sweeps of a Prim that screens every pair once (n^2 / 2 pairs)."""
    for m in range(coords.shape[1], 0, -1):
        _sweep32(coords, query, m, acc)


def kd_order(points: np.ndarray, rows: np.ndarray, leaf: int) -> list[np.ndarray]:
    """Rows in kd-tree order: halves at the median of the widest coordinate, down to ``leaf``."""
    if len(rows) <= leaf:
        return [rows]
    sub = points[rows]
    order = rows[np.argsort(sub[:, np.argmax(np.ptp(sub, axis=0))], kind="stable")]
    half = len(order) // 2
    return kd_order(points, order[:half], leaf) + kd_order(points, order[half:], leaf)


def principal(points: np.ndarray) -> np.ndarray:
    """The points in their principal components' coordinates, largest variance first."""
    centred = points - points.mean(axis=0)
    return np.asarray(centred @ np.linalg.svd(centred, full_matrices=False)[2].T)


def main() -> None:
    """Run the probe and print JSON."""
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--config", default=DEFAULT_CONFIG)
    p.add_argument("--sets", type=int, default=10)
    p.add_argument("--blocks", type=int, nargs="+", default=[16, 32, 64])
    args = p.parse_args()
    from generation_bench import evolved_looking  # benchmarks/ is on sys.path as the script's dir

    config = TrainerConfig.from_yaml(args.config)
    problem = make_problem(config, source=args.config)
    genomes = evolved_looking(100, problem.n_inputs, config.robot, 10, 1)
    batch = problem.simulate(genomes)
    n_scen = len(problem.scenarios)
    sets = [
        np.concatenate(batch.experience[g * n_scen : (g + 1) * n_scen], axis=0)
        for g in range(args.sets)
    ]
    prefixes = np.array(PREFIXES)  # counts come back as [pairs, shorten, one per prefix]
    rotated = sum(prefix_counts(np.ascontiguousarray(principal(s)), prefixes) for s in sets)
    raw = sum(prefix_counts(np.ascontiguousarray(s), prefixes) for s in sets)
    out: dict[str, object] = {
        "config": args.config,
        "sets": args.sets,
        "points_mean": float(np.mean([len(s) for s in sets])),
        "pairs": float(rotated[0]),
        "shorten": float(rotated[1] / rotated[0]),
        **{
            f"projection {q}": float(v / rotated[0])
            for q, v in zip(PREFIXES, rotated[2:], strict=True)
        },
        **{f"raw {q}": float(v / raw[0]) for q, v in zip(PREFIXES, raw[2:], strict=True)},
    }
    for size in args.blocks:
        shares = []
        for s in sets:
            rot = principal(s)
            order = np.concatenate(kd_order(rot, np.arange(len(rot)), size))
            shares.append(block_share(np.ascontiguousarray(rot[order]), size))
        out[f"block {size}"] = float(np.mean(shares))
    seconds, pairs = 0.0, 0.0
    for s in sets:
        coords = np.ascontiguousarray((s - s.mean(axis=0)).T.astype(np.float32))
        acc = np.empty(len(s), dtype=np.float32)
        screen_all(coords, coords[:, 0].copy(), acc)  # compile / warm the cache
        t0 = time.perf_counter()
        screen_all(coords, coords[:, 0].copy(), acc)
        seconds += time.perf_counter() - t0
        pairs += len(s) * (len(s) + 1) / 2
    out["float32_screen_ns_per_pair"] = seconds / pairs * 1e9
    print(json.dumps(out, indent=2))


if __name__ == "__main__":
    main()
