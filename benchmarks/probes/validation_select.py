"""Probe: does choosing a run's planner on the validation split beat its training champion?

    .venv/bin/python benchmarks/probes/validation_select.py RUN_DIR [RUN_DIR ...] --robot swarm
        [--pairs-per-family 20] [--out FILE.json]

A run ships ``best_genome.json``, the genome of the highest training F. Its final population
holds 100 genomes, many nearly as fit on the training scenarios, that may generalise better
or worse. This scores every one of them (and the champion) on the benchmark's validation
split, chooses the one with the most successes (then the highest SPL) on half of the
validation worlds (even world seeds), and compares the chosen genome with the champion on
the other half (odd world seeds), which the choice never saw. Selection by a held-out set is
model selection as the field does it; the test split is never touched.

All genomes of a run drive together in one batch (one network program), each on every pair,
with the planner settings and the stages of the champion's metadata (its view corridor and
rotation shim), as ``mentor-bench`` runs them.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np

from mentor_core.benchmark.scores import spl
from mentor_core.benchmark.suite import build_suite
from mentor_core.controller.deployment import trained_stages
from mentor_core.controller.episodes import run_episodes
from mentor_core.evolution.batch_network import BatchNetwork
from mentor_core.files.genome_file import load_genome_and_metadata
from mentor_core.runtime.planner import planner_profile
from mentor_core.sim.robots import get_profile
from mentor_core.training.run_files import load_population

PAPER_LIMIT = 50.0


def score_run(run: Path, robot: str, pairs_per_family: int) -> dict[str, object]:
    """Every genome of ``run`` on the validation suite: per genome and half, success and SPL."""
    champion, metadata = load_genome_and_metadata(run / "best_genome.json")
    base = get_profile(robot)
    profile = planner_profile(base, metadata, run / "best_genome.json")
    stages = trained_stages(metadata, run / "best_genome.json")
    genomes = [champion] + [g for g, _ in load_population(run / "population.json")]
    suite = build_suite(base, "validation", pairs_per_family=pairs_per_family)
    scenarios = [p.scenario for p in suite.pairs]
    n_pairs, n_gen = len(scenarios), len(genomes)
    network = BatchNetwork.from_genomes(genomes)
    n = n_pairs * n_gen
    memory = network.new_memory(n)

    def policy(inputs: np.ndarray, robots: np.ndarray) -> np.ndarray:
        return network.activate(inputs, robots // n_pairs, memory=memory, slots=robots)

    began = time.perf_counter()
    batch = run_episodes(scenarios * n_gen, profile, policy,
                         time_budgets=np.full(n, PAPER_LIMIT), stages=stages)  # fmt: skip
    reached = batch.reached & (batch.time_used <= PAPER_LIMIT)
    shortest = np.tile([p.shortest for p in suite.pairs], n_gen)
    weights = spl(reached, shortest, batch.path_length(profile)).reshape(n_gen, n_pairs)
    reached = reached.reshape(n_gen, n_pairs)
    odd = np.array([p.seed % 2 == 1 for p in suite.pairs])
    halves = {"select": ~odd, "held_out": odd, "all": np.ones(n_pairs, dtype=bool)}
    table = {
        name: {"success": reached[:, m].mean(axis=1), "spl": weights[:, m].mean(axis=1)}
        for name, m in halves.items()
    }
    key = table["select"]["success"] + 1e-6 * table["select"]["spl"]
    chosen = int(np.argmax(key))

    def row(i: int) -> dict[str, float]:
        return {f"{h}_{s}": float(table[h][s][i]) for h in halves for s in ("success", "spl")}

    return {
        "run": str(run),
        "genomes": n_gen,
        "seconds": time.perf_counter() - began,
        "champion": row(0),
        "chosen": {"index": chosen, **row(chosen)},
        "population_held_out_success": {
            "mean": float(table["held_out"]["success"].mean()),
            "max": float(table["held_out"]["success"].max()),
        },
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("runs", nargs="+", type=Path)
    parser.add_argument("--robot", required=True)
    parser.add_argument("--pairs-per-family", type=int, default=20)
    parser.add_argument("--out", type=Path)
    args = parser.parse_args()
    results = []
    for run in args.runs:
        res = score_run(run, args.robot, args.pairs_per_family)
        results.append(res)
        c, s = res["champion"], res["chosen"]
        assert isinstance(c, dict) and isinstance(s, dict)
        print(f"{run}: champion held-out {c['held_out_success']:.0%} / {c['held_out_spl']:.2f}"
              f" (select half {c['select_success']:.0%}); chosen #{s['index']} held-out "
              f"{s['held_out_success']:.0%} / {s['held_out_spl']:.2f} (select half "
              f"{s['select_success']:.0%}); {res['seconds']:.0f} s", flush=True)  # fmt: skip
    if args.out:
        args.out.write_text(json.dumps(results, indent=1))


if __name__ == "__main__":
    main()
