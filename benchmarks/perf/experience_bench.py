"""Benchmark of the experience-gain MST: seconds per MST for each method, printed as JSON.

Two kinds of data: "uniform" (i.i.d. uniform in the unit cube, the hard case for a kd-tree) and
"sensor" (experience points V = [U(t), A(t), U(t+1)] of range sensors that mostly read their
clip value, as the trainer produces). scipy's dense MST is timed only up to
``--scipy-max`` points (it needs the n x n matrix); larger sizes are listed under "skipped".

Every method's time is the best of ``--repeat`` calls after a warm-up; scipy's the best of
``--scipy-repeat``. ``scipy_over_<method>`` is scipy's time over the method's, in the same run.

Usage: .venv/bin/python benchmarks/perf/experience_bench.py [--sizes 1000 4000 16000] [--repeat 3]
    [--dims 8 18] [--kinds sensor uniform] [--scipy-repeat 1]
"""

from __future__ import annotations

import argparse
import json
import os
import time
from collections.abc import Callable

import numpy as np
from scipy.sparse.csgraph import minimum_spanning_tree
from scipy.spatial.distance import pdist, squareform

from mentor_core.objectives.experience import experience_gain, experience_gains

SENSOR_RANGE = 4.0  # m, UGV sensor range max
STEPS = 50  # decisions per scenario


def sensor_points(rng: np.random.Generator, n: int, dim: int) -> np.ndarray:
    """Experience points like the trainer's: readings clipped at range max, smooth in time."""
    n_sensors = (dim - 2) // 2
    n_scenarios = -(-n // STEPS)
    t = np.arange(STEPS + 1)[None, :, None]
    start = rng.uniform(-2.0, 2.5 * SENSOR_RANGE, size=(n_scenarios, 1, n_sensors))
    drift = rng.normal(0.0, 0.3, size=(n_scenarios, 1, n_sensors))
    noise = rng.normal(0.0, 0.02, size=(n_scenarios, STEPS + 1, n_sensors))
    readings = np.clip(start + drift * t + noise, 0.0, SENSOR_RANGE)
    dtheta = np.clip(rng.normal(0.0, 0.7, size=(n_scenarios, STEPS, 1)), -np.pi, np.pi)
    step = rng.uniform(0.1, 2.0, size=(n_scenarios, STEPS, 1))
    points = np.concatenate([readings[:, :-1], dtheta, step, readings[:, 1:]], axis=2)
    return points.reshape(-1, 2 * n_sensors + 2)[:n]


def scipy_dense(points: np.ndarray) -> float:
    unique = np.unique(points, axis=0)
    return float(minimum_spanning_tree(squareform(pdist(unique))).sum())


def seconds(function: Callable[[], object], repeat: int) -> float:
    """Best wall time of ``repeat`` calls (after one warm-up call that also compiles)."""
    function()
    best = np.inf
    for _ in range(repeat):
        start = time.perf_counter()
        function()
        best = min(best, time.perf_counter() - start)
    return float(best)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[1000, 4000, 16000])
    parser.add_argument("--dims", type=int, nargs="+", default=[8, 18])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--scipy-repeat", type=int, default=1)
    parser.add_argument("--kinds", nargs="+", default=["sensor", "uniform"])
    parser.add_argument("--scipy-max", type=int, default=4000)
    parser.add_argument("--numpy-max", type=int, default=4000)
    parser.add_argument("--prim-max", type=int, default=16000)
    parser.add_argument("--batch", type=int, default=100, help="genomes in the batch timing")
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    rng = np.random.default_rng(args.seed)

    rows = []
    skipped = []
    for kind in args.kinds:
        for dim in args.dims:
            for n in args.sizes:
                points = sensor_points(rng, n, dim) if kind == "sensor" else rng.random((n, dim))
                row: dict[str, object] = {"data": kind, "n": n, "d": dim}
                gains = {}
                limits = {
                    "bounded": n, "prim": args.prim_max, "boruvka": n, "numpy": args.numpy_max,
                }  # fmt: skip
                for method, limit in limits.items():
                    if n > limit:
                        skipped.append(f"{method} {kind} n={n} d={dim}")
                        continue
                    row[f"{method}_s"] = seconds(
                        lambda m=method, p=points: experience_gain(p, m), args.repeat
                    )
                    gains[method] = experience_gain(points, method)
                if n <= args.scipy_max:
                    scipy_s = seconds(lambda p=points: scipy_dense(p), args.scipy_repeat)
                    row["scipy_dense_s"] = scipy_s
                    gains["scipy"] = scipy_dense(points)
                    for method in limits:
                        if f"{method}_s" in row:
                            row[f"scipy_over_{method}"] = scipy_s / float(row[f"{method}_s"])
                else:
                    skipped.append(f"scipy {kind} n={n} d={dim}")
                if "prim_s" in row:
                    row["prim_over_bounded"] = float(row["prim_s"]) / float(row["bounded_s"])
                row["bounded_equals_prim"] = gains["bounded"] == gains.get("prim")
                ref = gains.get("scipy", gains["boruvka"])
                row["max_rel_diff"] = max(abs(g - ref) / ref for g in gains.values())
                rows.append(row)
                print(json.dumps(row), flush=True)

    batch = [sensor_points(rng, 4000, 18) for _ in range(args.batch)]
    batch_result: dict[str, object] = {
        "genomes": args.batch,
        "n": 4000,
        "d": 18,
        "data": "sensor",
        "numba_threads": os.environ.get("NUMBA_NUM_THREADS", "default"),
    }
    for method in ("bounded", "prim", "boruvka"):
        batch_result[f"{method}_gains_s"] = seconds(lambda m=method: experience_gains(batch, m), 1)
    batch_result["boruvka_serial_s"] = seconds(
        lambda: [experience_gain(points, "boruvka") for points in batch], 1
    )
    print(json.dumps({"per_mst": rows, "batch": batch_result, "skipped": skipped}, indent=1))


if __name__ == "__main__":
    main()
