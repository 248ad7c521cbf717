"""Probe: what do the evolved planners lose by driving while they first turn to the goal?

    .venv/bin/python benchmarks/rotation_shim.py GENOME [GENOME ...] --robot swarm
        [--thresholds 30 45 60] [--pairs-per-family 20]

A robot starts facing anywhere. With a heading change of at most 45 deg a decision, an
evolved planner turns towards its goal in up to four decisions and, as it learned, drives
while it turns: an arc away from the goal and back, which costs path length (SPL) though
little time. Nav2's answer is a shim in front of the controller (``RotationShimController``):
while the robot's heading is more than a threshold off the way (its default 45 deg) at the
start of a new path, it rotates in place towards it, then hands over to the controller.

This runs each genome on the validation split plain and behind such a shim: until the goal's
bearing has first come within the threshold, the turn output is replaced by the turn onto
the bearing (clipped to the heading limit) and the step output by the smallest step; from
then on the network drives as trained. Evaluation only (the networks were not trained with
the shim); the test split is never touched.
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from mentor_core.benchmark.scores import spl
from mentor_core.benchmark.suite import build_suite
from mentor_core.evolution.network import FeedForwardNetwork
from mentor_core.files.genome_file import load_genome_and_metadata
from mentor_core.runtime.planner import planner_profile
from mentor_core.sim.episode import Policy, run_episodes
from mentor_core.sim.robots import RobotProfile, get_profile

PAPER_LIMIT = 50.0
FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]


def shimmed(policy: Policy, profile: RobotProfile, n: int, threshold_deg: float) -> Policy:
    """``policy`` behind a rotation shim (module docstring) for ``n`` robots; needs the
    egocentric goal inputs (``cos beta, sin beta`` after the sensors)."""
    if profile.input_encoding != "egocentric":
        raise ValueError("the rotation shim reads the egocentric goal inputs")
    k, limit = profile.n_sensors, profile.heading_change_max
    cos_threshold = math.cos(math.radians(threshold_deg))
    aligned = np.zeros(n, dtype=bool)

    def shim(inputs: FloatArray, robots: IntArray) -> FloatArray:
        out = np.array(policy(inputs, robots), dtype=np.float64)
        aligned[robots[inputs[:, k] >= cos_threshold]] = True
        hold = ~aligned[robots]
        beta = np.arctan2(inputs[hold, k + 1], inputs[hold, k])
        out[hold, 0] = 0.5 + np.clip(beta, -limit, limit) / (2.0 * limit)
        out[hold, 1] = 0.0
        return out

    return shim


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("genomes", nargs="+", type=Path)
    parser.add_argument("--robot", required=True)
    parser.add_argument("--thresholds", type=float, nargs="+", default=[30.0, 45.0, 60.0])
    parser.add_argument("--pairs-per-family", type=int, default=20)
    args = parser.parse_args()
    base = get_profile(args.robot)
    suite = build_suite(base, "validation", pairs_per_family=args.pairs_per_family)
    scenarios = [p.scenario for p in suite.pairs]
    shortest = np.array([p.shortest for p in suite.pairs], dtype=np.float64)
    family = np.array([p.family for p in suite.pairs])
    n = len(scenarios)
    for path in args.genomes:
        genome, metadata = load_genome_and_metadata(path)
        profile = planner_profile(base, metadata, path)
        for threshold in [None, *args.thresholds]:
            policy = FeedForwardNetwork.from_genome(genome).episode_policy(n)
            if threshold is not None:
                policy = shimmed(policy, profile, n, threshold)
            batch = run_episodes(scenarios, profile, policy, time_budgets=np.full(n, PAPER_LIMIT))
            weight = spl(batch.reached, shortest, batch.path_length(profile))
            per_family = " ".join(
                f"{f}:{batch.reached[family == f].mean():.0%}/{weight[family == f].mean():.2f}"
                for f in suite.families
            )
            name = "plain" if threshold is None else f"shim {threshold:g} deg"
            print(f"{path}: {name}: {batch.reached.mean():.0%} / SPL {weight.mean():.3f}, "
                  f"collisions {batch.collided.mean():.0%}; {per_family}", flush=True)  # fmt: skip


if __name__ == "__main__":
    main()
