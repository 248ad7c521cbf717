"""Seconds per paper-scale generation: simulation plus experience gain, per backend.

    .venv/bin/python benchmarks/perf/generation_bench.py [--robot ugv] [--genomes 100]
        [--scenarios 80] [--repeats 2] [--workers 1 2] [--step-max M] [--step-min M]
        [--clearance-margin M] [--config FILE]

A generation is every genome on every training scenario in the batched engine (up to the
scenario's time budget, 50 decisions at most), then one Euclidean MST per genome over its
experience points. Genomes are evolved-looking: minimal genomes put through a few rounds of
the paper's mutation so they carry hidden nodes. ``--step-max`` runs the planners with a
shorter step, as the shipped UGV training configs do (``step_max: 0.5``; longer episodes);
``--step-min`` and ``--clearance-margin`` set the rest of their step rule (0.02 and 0.2 m:
``--step-max 0.5 --step-min 0.02 --clearance-margin 0.2`` is the shipped UGV planner).
Also times the experience gain alone (``experience_gains`` on the generation's point sets: 100
MSTs spread over numba's threads) and its share of an in-process generation, in wall-clock
seconds and in CPU seconds of this process (all threads; steadier than wall time when other
jobs share the cores). The in-process evaluator runs G beside the simulation where numba has
two threads or more (``training.gain_overlap``), so G alone is no longer what it adds to a
generation: ``experience_gain_cost_workers1`` is the in-process generation less the simulation
alone (each the best of ``--repeats``, taken in turn), and ``experience_gain_cost_share_workers1``
that over the generation. Prints JSON. ``benchmarks/perf/side_by_side.py``
runs this script against two checkouts. ``--config`` takes the training problem of a trainer
config file instead (its robot, planner settings, pairs and time budgets;
``--scenarios`` then sets its DoE scenario count), to compare the cost of two configs.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import time

import numpy as np

from mentor_core.evolution.config import EvolutionConfig
from mentor_core.evolution.genome import Genome
from mentor_core.evolution.mutation import mutated_genomes
from mentor_core.objectives.experience import experience_gains
from mentor_core.sim.planner_settings import with_planner
from mentor_core.sim.robots import get_profile
from mentor_core.sim.scenarios import training_scenarios
from mentor_core.training.evaluators import make_evaluator
from mentor_core.training.problem import NavigationProblem


def evolved_looking(n: int, n_inputs: int, robot: str, rounds: int, seed: int) -> list[Genome]:
    """``n`` genomes after ``rounds`` of the paper's mutation (hidden nodes, extra edges)."""
    mutation = EvolutionConfig.paper(robot).mutation
    return mutated_genomes(n, n_inputs, mutation, rounds, np.random.default_rng(seed))


def main() -> None:
    """Run the benchmark and print JSON."""
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--robot", default="ugv")
    p.add_argument("--genomes", type=int, default=100)
    p.add_argument("--scenarios", type=int, default=80)
    p.add_argument("--repeats", type=int, default=2)
    p.add_argument("--rounds", type=int, default=10, help="mutation rounds per genome")
    p.add_argument("--workers", type=int, nargs="+", default=[1, 2])
    p.add_argument("--step-max", type=float, help="the planners' largest step (m)")
    p.add_argument("--step-min", type=float, help="the planners' smallest step (m)")
    p.add_argument("--clearance-margin", type=float, help="the planners' clearance margin (m)")
    p.add_argument("--config", help="a trainer config file: its training problem (module doc)")
    args = p.parse_args()

    if args.config:
        from mentor_core.training.config import TrainerConfig
        from mentor_core.training.trainer import make_problem

        config = TrainerConfig.from_yaml(args.config)
        data = {**config.to_dict(), "n_scenarios": args.scenarios}
        problem = make_problem(TrainerConfig.from_dict(data), source=args.config)
        profile, scenarios, args.robot = problem.profile, list(problem.scenarios), config.robot
    else:
        profile = with_planner(
            get_profile(args.robot), step_max=args.step_max, step_min=args.step_min,
            clearance_margin=args.clearance_margin,
        )  # fmt: skip
        scenarios = training_scenarios(profile, 0, args.scenarios)
        problem = NavigationProblem(profile, scenarios)
    genomes = evolved_looking(args.genomes, profile.n_inputs, args.robot, args.rounds, 1)
    out: dict[str, object] = {
        "config": args.config,
        "robot": args.robot,
        "step_max": profile.step_max,
        "step_min": profile.step_min,
        "clearance_margin": profile.clearance_margin,
        "genomes": args.genomes,
        "scenarios": args.scenarios,
        "mean_hidden_nodes": float(np.mean([len(g.hidden_nodes) for g in genomes])),
    }
    batch = problem.simulate(genomes)
    out["robot_steps"] = int(batch.steps.sum())
    n_scen = len(scenarios)
    out["experience_points_per_genome_mean"] = float(
        np.mean([
            sum(len(e) for e in batch.experience[g * n_scen : (g + 1) * n_scen])
            for g in range(args.genomes)
        ])
    )
    point_sets = [
        np.concatenate(batch.experience[g * n_scen : (g + 1) * n_scen], axis=0)
        for g in range(args.genomes)
    ]
    experience_gains(point_sets)  # warm-up: numba compile or cache load
    mst_times, mst_cpu = [], []
    for _ in range(args.repeats):
        t0, c0 = time.perf_counter(), time.process_time()
        experience_gains(point_sets)
        mst_times.append(time.perf_counter() - t0)
        mst_cpu.append(time.process_time() - c0)
    mst_seconds = min(mst_times)
    out["seconds_experience_gain"] = mst_seconds
    out["cpu_seconds_experience_gain"] = min(mst_cpu)
    reference = None
    for workers in args.workers:
        with make_evaluator(problem, workers) as evaluator:
            evaluator.evaluate(genomes)  # warm-up: numba compile / pool start
            times, cpu, simulation = [], [], []
            for _ in range(args.repeats):
                t0, c0 = time.perf_counter(), time.process_time()
                result = evaluator.evaluate(genomes)
                times.append(time.perf_counter() - t0)
                cpu.append(time.process_time() - c0)
                if workers == 1:
                    t0 = time.perf_counter()
                    problem.simulate(genomes)
                    simulation.append(time.perf_counter() - t0)
        if reference is None:
            reference = result.objectives
            out["objectives_sha256"] = hashlib.sha256(reference.tobytes()).hexdigest()
        out[f"seconds_per_generation_workers{workers}"] = min(times)
        if workers == 1:  # in process: this process's CPU time is the generation's
            out["experience_gain_share_workers1"] = mst_seconds / min(times)
            out["cpu_seconds_per_generation_workers1"] = min(cpu)
            out["cpu_experience_gain_share_workers1"] = min(mst_cpu) / min(cpu)
            out["seconds_simulation_only"] = min(simulation)
            out["experience_gain_cost_workers1"] = min(times) - min(simulation)
            out["experience_gain_cost_share_workers1"] = 1.0 - min(simulation) / min(times)
        out[f"identical_to_first_backend_workers{workers}"] = bool(
            np.array_equal(reference, result.objectives)
        )
    print(json.dumps(out, indent=2))


if __name__ == "__main__":
    main()
