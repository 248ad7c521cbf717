"""The last decisions before each collision of a planner on the generalisation benchmark.

    .venv/bin/python benchmarks/probes/collision_decisions.py GENOME [--robot ugv]
        [--split validation] [--pairs-per-family 20] [--last 4] [--show 8]

Runs the genome on the suite's pairs with the paper's 50 s (as ``mentor-bench``) and, for the
first ``--show`` episodes that ended in a collision, prints the family and, for each of its
last ``--last`` decisions, the readings ``U(t)`` (m) and the action taken (heading change in
degrees, step in m), read from the episode's experience points ``[U(t), A(t), U(t+1)]``. It is
how the UGV planners' dithering at walls was seen (experiment E023, "Better
planners").
"""

from __future__ import annotations

import argparse
import math

import numpy as np

from mentor_core.benchmark.contenders import evolved
from mentor_core.benchmark.suite import PAPER_LIMIT, build_suite
from mentor_core.controller.episodes import run_episodes
from mentor_core.sim.robots import get_profile


def main() -> None:
    """Run the genome and print the decisions before its collisions."""
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("genome")
    p.add_argument("--robot", default="ugv")
    p.add_argument("--split", default="validation")
    p.add_argument("--pairs-per-family", type=int, default=20)
    p.add_argument("--last", type=int, default=4)
    p.add_argument("--show", type=int, default=8)
    args = p.parse_args()
    robot = get_profile(args.robot)
    suite = build_suite(robot, args.split, pairs_per_family=args.pairs_per_family)
    planner = evolved(args.genome, robot)
    scenarios = [pair.scenario for pair in suite.pairs]
    batch = run_episodes(scenarios, planner.profile, planner.policy(scenarios),
                         time_budgets=PAPER_LIMIT, stages=planner.stages)  # fmt: skip
    k = planner.profile.n_sensors
    collided = np.flatnonzero(batch.collided)
    print(f"{len(collided)} collisions, {int(batch.reached.sum())} reached of {len(scenarios)}")
    for i in collided[: args.show]:
        print(f"{suite.pairs[i].family}, {int(batch.steps[i])} decisions")
        for row in batch.experience[i][-args.last :]:
            print(f"   U {np.round(row[:k], 2)}  dtheta {math.degrees(row[k]):4.0f} deg  "
                  f"ds {row[k + 1]:.3f} m")  # fmt: skip


if __name__ == "__main__":
    main()
