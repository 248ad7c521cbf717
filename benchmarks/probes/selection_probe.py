"""Probe: is the best genome by training F the one that generalises best in its run?

    .venv/bin/python benchmarks/probes/selection_probe.py RUN_DIR [RUN_DIR ...] --out DIR
        [--holdout-seed 101] [--families all] [--family-pairs 5]

For each run directory this builds a held-out selection set with the run's own config but
another ``scenario_seed`` (other DoE worlds and pairs, and one world of each structured family
of ``training/curriculum.py``, whose seeds never meet the benchmark's), evaluates the final
population, the stage-1 Pareto set and the best genome on it, and writes the genome that
reaches most of the held-out goals (ties: higher F there) as ``DIR/<run>/selected_genome.json``
with the best genome's metadata, next to a line per run: held-out success of the best genome
and of the selected one. Score both with ``mentor-bench --split validation`` afterwards.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
from pathlib import Path

import numpy as np

from mentor_core.evolution.genome import Genome
from mentor_core.evolution.genome_codec import genome_from_dict
from mentor_core.files.genome_file import load_genome_and_metadata, save_genome
from mentor_core.sim.families import FAMILIES
from mentor_core.training.config import load_config_file
from mentor_core.training.run_files import load_population
from mentor_core.training.trainer import make_problem


def candidates(run: Path) -> tuple[list[Genome], dict[str, object]]:
    """The best genome (first), the final population and the stage-1 Pareto set of ``run``."""
    best, meta = load_genome_and_metadata(run / "best_genome.json")
    found = [best] + [g for g, _ in load_population(run / "population.json")]
    pareto = json.loads((run / "pareto.json").read_text(encoding="utf-8"))
    found += [genome_from_dict(d, str(run / "pareto.json")) for d in pareto["genomes"]]
    return found, meta


def main() -> None:
    """Select per run and print a line each."""
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("runs", nargs="+", type=Path)
    p.add_argument("--out", type=Path, required=True)
    p.add_argument("--holdout-seed", type=int, default=101)
    p.add_argument("--families", default="all", help="comma-separated, 'all' or 'none'")
    p.add_argument("--family-pairs", type=int, default=5)
    args = p.parse_args()
    families = (
        tuple(FAMILIES) if args.families == "all"
        else () if args.families == "none" else tuple(args.families.split(","))
    )  # fmt: skip
    for run in args.runs:
        config, _ = load_config_file(run / "config.yaml")
        held = dataclasses.replace(
            config, scenario_seed=args.holdout_seed, families=families,
            family_pairs=args.family_pairs,
        )  # fmt: skip
        problem = make_problem(held)
        problem.with_experience = False
        genomes, meta = candidates(run)
        ev = problem.evaluate(genomes)
        order = np.lexsort((-ev.objectives[:, 0], -ev.success_rate))
        pick = int(order[0])
        out = args.out / run.name
        out.mkdir(parents=True, exist_ok=True)
        save_genome(genomes[pick], out / "selected_genome.json", meta)
        print(
            f"{run.name}: {len(problem.scenarios)} held-out scenarios, {len(genomes)} genomes;"
            f" best genome {ev.success_rate[0]:.0%}, selected #{pick}"
            f" {ev.success_rate[pick]:.0%} (population median {np.median(ev.success_rate):.0%})",
            flush=True,
        )


if __name__ == "__main__":
    main()
