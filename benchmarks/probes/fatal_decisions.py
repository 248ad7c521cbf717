"""What a trained planner did at the decision that ended each colliding training episode.

    .venv/bin/python benchmarks/probes/fatal_decisions.py RUN_DIR [--robots FILE] [--margin 0.2]

Runs the best genome of a ``mentor-train`` (or ``ablation.py --out``) run directory on its own
training scenarios again and, for every episode that ends in a collision, reads the last
experience point ``[U(t), A(t), U(t+1)]``: the readings before the fatal decision and its action
``(dtheta, ds)``. An episode counts as *drove into what it saw* when the step was longer than
the smallest reading of the sensors facing within 30 deg of straight ahead, less ``--margin``
m; else as *turned into the unseen* when the turn exceeded 20 deg. Prints one JSON object.
"""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

import numpy as np

from mentor_core.files.genome_file import load_genome_and_metadata
from mentor_core.sim.robots import get_profile
from mentor_core.training.config import load_config_file
from mentor_core.training.trainer import make_problem

FRONT = math.radians(30.0)
TURN = math.radians(20.0)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("run", type=Path)
    p.add_argument("--robots", type=Path, help="robot file the run was trained with")
    p.add_argument("--margin", type=float, default=0.2, help="m (0.2)")
    args = p.parse_args()

    config, _ = load_config_file(args.run / "config.yaml")  # the run's seed is not needed
    problem = make_problem(config, get_profile(config.robot, args.robots))
    genome, _ = load_genome_and_metadata(args.run / "best_genome.json")
    batch = problem.simulate([genome])
    k = problem.profile.n_sensors
    facing = problem.profile.sensor_angles
    front = np.abs(np.remainder(facing + math.pi, 2 * math.pi) - math.pi) <= FRONT
    saw = turned = 0
    steps = []
    for i in np.flatnonzero(batch.collided):
        last = batch.experience[i][-1]
        dtheta, ds = last[k], last[k + 1]
        steps.append(float(ds))
        if ds >= last[:k][front].min() - args.margin:
            saw += 1
        elif abs(dtheta) > TURN:
            turned += 1
    print(json.dumps({
        "run": str(args.run), "scenarios": int(batch.reached.size),
        "reached": int(batch.reached.sum()), "collided": int(batch.collided.sum()),
        "drove_into_what_it_saw": saw, "turned_into_the_unseen": turned,
        "other": int(batch.collided.sum()) - saw - turned,
        "fatal_step_median_m": float(np.median(steps)) if steps else None,
        "step_max_m": problem.profile.step_max,
    }, indent=2))  # fmt: skip


if __name__ == "__main__":
    main()
