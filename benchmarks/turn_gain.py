"""Probe: the shipped planners as deployed, with their network's turn scaled by each gain.

    .venv/bin/python benchmarks/turn_gain.py GENOME [GENOME ...] --robot swarm
        [--gains 1 0.8 0.75 0.7] [--pairs-per-family 40]

An evolved planner's turn output is nearly bang-bang: on a straight way it drives arcs of
about +h and -h in turn, whose chords line up but which are longer than their chords. The
turn gain (``mentor_core.sim.turn_gain``; ``mentor-bench --turn-gain``) scales the network's
turn about its middle. This runs each genome as deployed (on its scan map, behind the
rotation shim and the collision guard: ``contenders.as_deployed``) with each gain on the
**validation** split within the paper's 50 s, and prints success, SPL and collisions, per
genome and as the mean over the genomes, and how much longer the driven paths of the
successes are than their chords (the arcs' share of the excess). The test split is never
touched. experiment E054, "A gain on the turn", chose the Swarm-Robot's 0.75 with
it.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from mentor_core.benchmark.contenders import as_deployed, evolved
from mentor_core.benchmark.scores import spl
from mentor_core.benchmark.suite import PAPER_LIMIT, build_suite
from mentor_core.sim.episode import run_episodes
from mentor_core.sim.robots import get_profile


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("genomes", nargs="+")
    p.add_argument("--robot", default="swarm", choices=("ugv", "swarm"))
    p.add_argument("--gains", type=float, nargs="+", default=[1.0, 0.8, 0.75, 0.7])
    p.add_argument("--pairs-per-family", type=int, default=40)
    args = p.parse_args()
    robot = get_profile(args.robot)
    suite = build_suite(robot, "validation", None, args.pairs_per_family)
    scenarios = [pair.scenario for pair in suite.pairs]
    shortest = np.array([pair.shortest for pair in suite.pairs])
    families = np.array([pair.family for pair in suite.pairs])
    print(f"{len(scenarios)} validation pairs of {robot.name}, {PAPER_LIMIT:.0f} s")
    for gain in args.gains:
        rows = []
        for g in args.genomes:
            c = as_deployed(evolved(g, robot, Path(g).stem), turn_gain=gain)
            goals = c.input_goals(scenarios)
            batch = run_episodes(scenarios, c.profile, c.policy(scenarios),
                                 time_budgets=PAPER_LIMIT, input_goals=goals)  # fmt: skip
            driven = batch.path_length(c.profile)
            chords = np.linalg.norm(np.diff(batch.trajectories[:, :, :2], axis=1), axis=2).sum(1)
            arcs = np.median(driven[batch.reached] / chords[batch.reached])
            values = spl(batch.reached, shortest, driven)
            rows.append((batch.reached.mean(), values.mean(), batch.collided.mean()))
            per = " ".join(f"{f[:8]} {100 * batch.reached[families == f].mean():.0f}"
                           for f in suite.families)  # fmt: skip
            print(f"gain {gain:4.2f} {Path(g).stem:<24} {100 * rows[-1][0]:5.1f} % / "
                  f"{rows[-1][1]:.3f}, collisions {100 * rows[-1][2]:4.1f} %, driven / chords "
                  f"{arcs:.3f} | {per}", flush=True)  # fmt: skip
        mean = np.mean(rows, axis=0)
        print(f"gain {gain:4.2f} mean over {len(rows)}: {100 * mean[0]:.1f} % / {mean[1]:.3f}, "
              f"collisions {100 * mean[2]:.1f} %", flush=True)  # fmt: skip


if __name__ == "__main__":
    main()
