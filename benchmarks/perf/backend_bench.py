"""Seconds per paper-scale UGV generation with each evaluation backend, one JSON object.

    export NUMBA_CACHE_DIR=.venv/numba-cache
    .venv/bin/python benchmarks/perf/backend_bench.py [--genomes 100] [--scenarios 80]
        [--generations 3] [--workers 2] [--backends inprocess pool ray]

A generation is what the trainer's evaluator does once per generation:
``Evaluator.evaluate(population)`` = every genome on every training scenario in the batched
engine, then F and one Euclidean MST (experience gain G) per genome; the evolution's
ask/tell (milliseconds) is not included. The population: ``--genomes`` minimal UGV genomes
put through ``--rounds`` of the paper's mutation (:func:`generation_bench.evolved_looking`,
so they carry hidden nodes like a population some generations in).

Backends (:mod:`mentor_core.training.evaluators`): ``inprocess``; ``pool``, a spawn process pool of
``--workers`` processes; ``ray``, a local Ray started with ``--workers`` CPUs (no dashboard).
Each is started (``startup_s``), runs one warm-up generation (numba kernels loaded in every
worker, problem shipped), then ``--generations`` timed generations of the same population;
the median is reported, with every sample. Objectives must be bit-identical across
backends (``identical_to_first_backend``). On a machine with fewer free cores than
``--workers`` (see ``loadavg_1m``) the parallel backends cannot gain.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import time
from datetime import date

import numpy as np
from generation_bench import evolved_looking

from mentor_core.sim.robots import get_profile
from mentor_core.sim.scenarios import training_scenarios
from mentor_core.training.evaluators import (
    Evaluator,
    InProcessEvaluator,
    PoolEvaluator,
    RayEvaluator,
)
from mentor_core.training.problem import NavigationProblem


def start(name: str, problem: NavigationProblem, workers: int) -> Evaluator:
    """The evaluator called ``name``."""
    if name == "inprocess":
        return InProcessEvaluator(problem)
    if name == "pool":
        return PoolEvaluator(problem, workers)
    if name == "ray":
        return RayEvaluator(problem, "local", workers)
    raise SystemExit(f"unknown backend {name!r}")


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--genomes", type=int, default=100)
    p.add_argument("--scenarios", type=int, default=80)
    p.add_argument("--rounds", type=int, default=10, help="mutation rounds per genome")
    p.add_argument("--generations", type=int, default=3, help="timed generations per backend")
    p.add_argument("--workers", type=int, default=2)
    p.add_argument("--backends", nargs="+", default=["inprocess", "pool", "ray"])
    p.add_argument("--seed", type=int, default=1)
    args = p.parse_args()

    profile = get_profile("ugv")
    scenarios = training_scenarios(profile, 0, args.scenarios)
    genomes = evolved_looking(args.genomes, profile.n_inputs, "ugv", args.rounds, args.seed)
    problem = NavigationProblem(profile, scenarios)
    out: dict[str, object] = {
        "benchmark": "backend_bench",
        "date": date.today().isoformat(),
        "host": {"cpus": os.cpu_count(), "loadavg_1m_at_start": os.getloadavg()[0]},
        "robot": profile.name,
        "genomes": args.genomes,
        "scenarios": len(scenarios),
        "workers": args.workers,
        "mean_hidden_nodes": float(np.mean([len(g.hidden_nodes) for g in genomes])),
        "mean_enabled_connections": float(
            np.mean([len(g.enabled_connections) for g in genomes])
        ),
        "includes": "Evaluator.evaluate(population): simulation of genomes x scenarios in the "
                    "batched engine + F + experience-gain MST per genome; no ask/tell",
    }
    reference = None
    results: dict[str, object] = {}
    for name in args.backends:
        t0 = time.perf_counter()
        evaluator = start(name, problem, args.workers)
        startup = time.perf_counter() - t0
        try:
            t0 = time.perf_counter()
            evaluator.evaluate(genomes)  # warm-up
            warmup = time.perf_counter() - t0
            samples = []
            for _ in range(args.generations):
                t0 = time.perf_counter()
                result = evaluator.evaluate(genomes)
                samples.append(time.perf_counter() - t0)
        finally:
            evaluator.close()
        if reference is None:
            reference = result.objectives
        results[name] = {
            "seconds_per_generation_median": statistics.median(samples),
            "samples_s": samples,
            "startup_s": startup,
            "warmup_generation_s": warmup,
            "identical_to_first_backend": bool(np.array_equal(reference, result.objectives)),
            "loadavg_1m_after": os.getloadavg()[0],
        }
    out["first_backend"] = args.backends[0]
    out["backends"] = results
    print(json.dumps(out, indent=2))


if __name__ == "__main__":
    main()
