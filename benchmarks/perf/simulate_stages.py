"""Where ``NavigationProblem.simulate`` spends its time, stage by stage, on a paper-scale batch.

    export NUMBA_CACHE_DIR=.venv/numba-cache
    cd benchmarks && ../.venv/bin/python simulate_stages.py [--repeats 10]

The genomes and scenarios of ``throughput_vs_neat.py`` (100 evolved-looking UGV genomes x 80
training scenarios, the robot's own 2 m steps). Wall-clock timers wrap the stages of an episode
step (the engine's step and its narrow phase, observe and its compiled readings loop, the
network's compile and activate, inputs, actions, experience points); each stage's
share is of the whole ``simulate`` (mean of ``--repeats`` runs after a warm-up). The timers
add a few microseconds per call. Prints one JSON object.
"""

from __future__ import annotations

import argparse
import json
import time
from collections import defaultdict
from collections.abc import Callable
from typing import Any

from generation_bench import evolved_looking

from mentor_core.evolution import batch_network
from mentor_core.sim import engine, observation, sensors
from mentor_core.sim.robots import get_profile
from mentor_core.sim.scenarios import training_scenarios
from mentor_core.training.problem import NavigationProblem

STAGES = (
    (engine.BatchEngine, "step", "engine step (arc, swept collision, goal)"),
    (engine, "swept_events", "  of which narrow phase (swept_events)"),
    (engine.BatchEngine, "observe", "observe (all sensor work)"),
    (sensors, "_readings_numba", "  of which readings kernel"),
    (batch_network.BatchNetwork, "activate", "network activate"),
    (batch_network.BatchNetwork, "from_genomes", "network compile"),
    (observation, "network_inputs", "network inputs"),
    (observation, "actions_from_outputs", "actions"),
    (observation, "experience_point", "experience points"),
)


def timed(seconds: dict[str, float], label: str, f: Callable[..., Any]) -> Callable[..., Any]:
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        t0 = time.perf_counter()
        try:
            return f(*args, **kwargs)
        finally:
            seconds[label] += time.perf_counter() - t0

    return wrapper


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--repeats", type=int, default=10)
    args = p.parse_args()
    profile = get_profile("ugv")
    problem = NavigationProblem(profile, training_scenarios(profile, 0))
    genomes = evolved_looking(100, profile.n_inputs, "ugv", 10, 0)
    seconds: dict[str, float] = defaultdict(float)
    for owner, name, label in STAGES:
        if getattr(owner, name, None) is not None:  # the kernel is None without numba
            setattr(owner, name, timed(seconds, label, getattr(owner, name)))
    problem.simulate(genomes)  # warm-up
    seconds.clear()
    t0 = time.perf_counter()
    for _ in range(args.repeats):
        problem.simulate(genomes)
    total = (time.perf_counter() - t0) / args.repeats
    shares = {label: round(seconds[label] / args.repeats / total, 3) for _, _, label in STAGES}
    print(json.dumps({"simulate_seconds": total, "share_of_simulate": shares}, indent=2))


if __name__ == "__main__":
    main()
