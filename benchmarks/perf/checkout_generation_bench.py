"""Seconds per paper-scale generation of a trainer config, against whichever mentor_core is on
``PYTHONPATH`` (any checkout since the training wing: it needs only ``make_problem``,
``load_config_file``, ``make_evaluator`` and ``mutated_genomes``), to compare two checkouts'
shipped configs side by side:

    for i in 1 2 3 4 5; do for wt in /path/old /path/new; do
      PYTHONPATH=$wt/mentor_core/src NUMBA_CACHE_DIR=$wt/.venv/numba-cache \\
        .venv/bin/python benchmarks/perf/checkout_generation_bench.py \\
        $wt/mentor_core/src/mentor_core/configs/train_ugv_paper.yaml
    done; done

A generation is 100 genomes (10 rounds of the paper's mutation, seed 1) on the config's
training problem, evaluated in process (one worker; G on numba's threads), best of
``--repeats`` after a warm-up. Prints JSON: wall and CPU seconds of the generation, seconds of
the simulation alone, decisions and scenarios. ``generation_bench.py --config`` does the same
for this checkout alone, with more detail.
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np

from mentor_core.evolution.config import EvolutionConfig
from mentor_core.evolution.mutation import mutated_genomes
from mentor_core.training.config import load_config_file
from mentor_core.training.evaluators import make_evaluator
from mentor_core.training.trainer import make_problem


def main() -> None:
    """Time the generation and print JSON."""
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("config", help="a trainer config file")
    p.add_argument("--repeats", type=int, default=3)
    args = p.parse_args()
    config = load_config_file(args.config)[0]
    problem = make_problem(config)
    mutation = EvolutionConfig.paper(config.robot).mutation
    genomes = mutated_genomes(100, problem.n_inputs, mutation, 10, np.random.default_rng(1))
    wall, cpu = [], []
    with make_evaluator(problem, 1) as evaluator:
        evaluator.evaluate(genomes)  # warm-up: numba compile
        for _ in range(args.repeats):
            t, c = time.perf_counter(), time.process_time()
            evaluator.evaluate(genomes)
            wall.append(time.perf_counter() - t)
            cpu.append(time.process_time() - c)
    t = time.perf_counter()
    batch = problem.simulate(genomes)
    print(json.dumps({
        "generation_s": min(wall), "generation_cpu_s": min(cpu),
        "simulation_s": time.perf_counter() - t, "decisions": int(batch.steps.sum()),
        "scenarios": len(problem.scenarios),
    }))  # fmt: skip


if __name__ == "__main__":
    main()
