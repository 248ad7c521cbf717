"""Speed of the batched simulation engine vs the pymunk reference, printed as JSON.

Work: one paper-scale UGV generation of simulation, 100 genomes x 80 training scenarios =
8,000 robots, up to 50 decisions each (the UGV time budgets allow at most 34), with a
random-but-fixed linear policy (sigmoid of a per-genome linear map of the network inputs).
The pymunk reference redoes the same robot-steps (the range readings before each decision and
the swept collision test of the decision) for a slice of the robots, and its time is
extrapolated per robot-step.

    .venv/bin/python benchmarks/perf/sim_bench.py [--genomes 100] [--slice 160] [--repeats 3]

Times are wall-clock seconds (best of ``--repeats``) and process CPU seconds (``cpu_s``), the
latter less disturbed by other processes on a shared machine.
"""

from __future__ import annotations

import argparse
import json
import time
from collections.abc import Callable
from typing import Any

import numpy as np

from mentor_core.controller.episodes import run_episodes
from mentor_core.sim.collision import sample_counts
from mentor_core.sim.episode import EpisodeBatch
from mentor_core.sim.pymunk_world import PymunkWorld
from mentor_core.sim.robots import get_profile
from mentor_core.sim.scenarios import training_scenarios
from mentor_core.sim.sensors import HAVE_NUMBA
from mentor_core.sim.world import Scenario

SEED = 0
MAX_DECISIONS = 50


def linear_policy(n_genomes: int, n_inputs: int, n_scenarios: int) -> Callable[..., Any]:
    """Per-genome sigmoid(W [inputs, 1]) with fixed random weights."""
    weights = np.random.default_rng(SEED).normal(size=(n_genomes, n_inputs + 1, 2))

    def policy(inputs: np.ndarray, robots: np.ndarray) -> np.ndarray:
        x = np.concatenate([inputs, np.ones((len(robots), 1))], axis=1)
        z = np.einsum("mi,mio->mo", x, weights[robots // n_scenarios])
        return 1.0 / (1.0 + np.exp(-z))

    return policy


def timed(fn: Callable[[], Any], repeats: int) -> tuple[Any, float, float]:
    """Result, best wall seconds and best CPU seconds over ``repeats`` runs."""
    best_wall = best_cpu = float("inf")
    result = None
    for _ in range(repeats):
        w0, c0 = time.perf_counter(), time.process_time()
        result = fn()
        best_wall = min(best_wall, time.perf_counter() - w0)
        best_cpu = min(best_cpu, time.process_time() - c0)
    return result, best_wall, best_cpu


def pymunk_replay(batch: EpisodeBatch, scenarios: list[Scenario], robots: range,
                  k: int) -> tuple[int, int, float]:
    """Redo the batch's robot-steps for ``robots`` in pymunk: (steps, disagreements, seconds)."""
    profile = get_profile("ugv")
    t0 = time.perf_counter()
    reference = PymunkWorld(scenarios[0].world, profile)
    steps = disagreements = 0
    for i in robots:
        points = batch.experience[i]
        for t in range(batch.steps[i]):
            pose = batch.trajectories[i, t]
            ranges = np.minimum(reference.ranges(pose), profile.sensor_range)
            dtheta, ds = points[t, k], points[t, k + 1]
            hit = reference.swept_collision(pose, dtheta, ds)
            collided_here = batch.collided[i] and t == batch.steps[i] - 1
            disagreements += int(not np.allclose(ranges, points[t, :k], rtol=0, atol=1e-9))
            disagreements += int((hit >= 0) != collided_here and not batch.reached[i])
            steps += 1
    return steps, disagreements, time.perf_counter() - t0


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--genomes", type=int, default=100)
    parser.add_argument("--slice", type=int, default=160, help="robots replayed in pymunk")
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()

    profile = get_profile("ugv")
    scenarios = training_scenarios(profile, seed=SEED)
    n_scen = len(scenarios)
    robots = list(scenarios) * args.genomes
    policy = linear_policy(args.genomes, profile.n_inputs, n_scen)

    def generation(backend: str = "auto") -> EpisodeBatch:
        return run_episodes(robots, profile, policy, max_steps=MAX_DECISIONS,
                            backend=backend)  # type: ignore[arg-type]

    run_episodes(scenarios[:4], profile, policy, max_steps=2)  # compile / load the kernels
    batch, wall, cpu = timed(generation, args.repeats)
    robot_steps = int(batch.steps.sum())
    _, np_wall, np_cpu = timed(lambda: generation("numpy"), 1)

    n_slice = min(args.slice, len(robots))
    pm_steps, disagreements, pm_wall = pymunk_replay(batch, robots, range(n_slice),
                                                     profile.n_sensors)
    pm_rate = pm_steps / pm_wall
    mean_samples = float(sample_counts(*batch.experience[0][:, profile.n_sensors:
                                                            profile.n_sensors + 2].T,
                                       profile).mean()) if batch.steps[0] else 0.0
    report = {
        "benchmark": "sim_bench",
        "robot": profile.name,
        "numba": HAVE_NUMBA,
        "robots": len(robots),
        "genomes": args.genomes,
        "scenarios": n_scen,
        "obstacles": int(scenarios[0].world.obstacles.shape[0]),
        "max_decisions": MAX_DECISIONS,
        "robot_steps": robot_steps,
        "outcomes": {
            "reached": float(batch.reached.mean()),
            "collided": float(batch.collided.mean()),
            "timed_out": float(batch.timed_out.mean()),
            "max_steps": int(batch.steps.max()),
        },
        "engine": {
            "generation_s": wall,
            "generation_cpu_s": cpu,
            "robot_steps_per_s": robot_steps / wall,
            "worst_case_generation_s": len(robots) * MAX_DECISIONS / (robot_steps / wall),
        },
        "engine_numpy_backend": {"generation_s": np_wall, "generation_cpu_s": np_cpu,
                                 "robot_steps_per_s": robot_steps / np_wall},
        "pymunk_reference": {
            "robots_replayed": n_slice,
            "robot_steps": pm_steps,
            "seconds": pm_wall,
            "robot_steps_per_s": pm_rate,
            "extrapolated_generation_s": robot_steps / pm_rate,
            "disagreements": disagreements,
        },
        "speedup_vs_pymunk": (robot_steps / wall) / pm_rate,
        "speedup_numba_vs_numpy": np_wall / wall,
        "mean_swept_samples_robot0": mean_samples,
    }
    print(json.dumps(report, indent=2))


if __name__ == "__main__":
    main()
