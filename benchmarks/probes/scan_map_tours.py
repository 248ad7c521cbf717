"""Tours of goals in one world: the planner node's scan map kept from goal to goal, or started
empty at each goal (the node's ``scan_map_keep``).

    .venv/bin/python benchmarks/probes/scan_map_tours.py GENOME [GENOME ...] --robot ugv
        [--pairs-per-family 40] [--rotation-shim 45] [--json OUT]

A tour is one world of the validation split: the robot starts at its first pair's start and
is sent to the goals of the world's pairs one after another, each leg from wherever the last
one ended, with 50 s a leg (a collision ends the tour; a timeout goes on from where it
stopped). Each genome drives as the planner node runs it with a deployment of a scan map (its
plan's defaults), the rotation shim and a collision guard (``deployment`` a file of
``scan_map: {}`` and ``stages: {rotation_shim: {threshold_deg: 45}, collision_guard: {}}``),
on no arena (:class:`mentor_core.ScanGuidedPlanner`,
through :func:`mentor_core.runtime.simulator.run_reference_episode`, which feeds it what the
node receives). Between legs the planner is reset as the node resets it for a new goal,
keeping its map or not. Printed per genome and mode: the legs reached of all the tours' legs,
the later legs (every one but the first) reached of those driven, the mean time of the later
legs reached, and the share of tours ended by a collision. The test split is never touched.
"""

from __future__ import annotations

import argparse
import json
import math
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from mentor_core.benchmark.suite import BenchPair, build_suite
from mentor_core.controller.deployment import Deployment, load_deployment
from mentor_core.runtime.guided_planner import ScanGuidedPlanner
from mentor_core.runtime.planner import GenomePlanner
from mentor_core.runtime.simulator import RobotSetup, run_reference_episode
from mentor_core.sim.robots import get_profile

LEG_LIMIT = 50.0  # s, the paper's limit, for every leg


def tour(genome: Path, robot: str, pairs: Sequence[BenchPair], keep: bool,
         deployment: Deployment) -> list[dict[str, Any]]:  # fmt: skip
    """The legs of one tour (module docstring) of the genome run as ``deployment`` (one with a
    scan map): family, leg, outcome, time (s)."""
    planner = GenomePlanner.load(genome, robot, deployment)
    world = pairs[0].scenario.world
    assert deployment.scan_map is not None
    guide = deployment.scan_map.guide(planner.profile)
    mapped = ScanGuidedPlanner(planner, guide, world.size)
    pose = tuple(pairs[0].scenario.start)
    legs = []
    for k, pair in enumerate(pairs):
        if k:
            mapped.reset(keep_map=keep)  # a new goal, as the planner node resets for one
        setup = RobotSetup("robot", planner.profile, pose, tuple(pair.scenario.goal), k,
                           LEG_LIMIT)  # fmt: skip
        trace = run_reference_episode(world, [setup], {"robot": mapped.decide})["robot"]
        legs.append({"family": pair.family, "seed": pair.seed, "leg": k,
                     "outcome": trace.outcome, "time": trace.time_used})  # fmt: skip
        pose = tuple(float(v) for v in trace.poses[-1])
        if trace.outcome == "collided":
            break
    return legs


def summary(legs: Sequence[dict[str, Any]], n_tours: int, per_tour: int) -> str:
    """One line: legs reached of all, later legs reached of those driven, their mean time,
    tours ended by a collision."""
    reached = sum(leg["outcome"] == "reached" for leg in legs)
    later = [leg for leg in legs if leg["leg"] > 0]
    later_ok = [leg["time"] for leg in later if leg["outcome"] == "reached"]
    crashed = sum(leg["outcome"] == "collided" for leg in legs)
    return (f"legs {100 * reached / (n_tours * per_tour):.1f} % of {n_tours * per_tour}, "
            f"later legs {100 * len(later_ok) / max(1, len(later)):.1f} % of {len(later)} "
            f"in {np.mean(later_ok) if later_ok else math.nan:.1f} s, "
            f"tours crashed {100 * crashed / n_tours:.0f} %")  # fmt: skip


def main(argv: Sequence[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("genomes", nargs="+", type=Path)
    parser.add_argument("--robot", default="ugv")
    parser.add_argument("--pairs-per-family", type=int, default=40)
    parser.add_argument("--rotation-shim", type=float, default=45.0,
                        help="deg (0: without)")  # fmt: skip
    parser.add_argument("--json", type=Path, help="write every leg here")
    args = parser.parse_args(argv)
    suite = build_suite(get_profile(args.robot), "validation",
                        pairs_per_family=args.pairs_per_family)
    tours: dict[tuple[str, int], list[BenchPair]] = {}
    for pair in suite.pairs:
        tours.setdefault((pair.family, pair.seed), []).append(pair)
    per_tour = max(len(pairs) for pairs in tours.values())
    settings = ["scan_map={}", "stages.collision_guard.memory=3"]
    if args.rotation_shim > 0:  # before the guard, as shipped
        settings.insert(1, f"stages.rotation_shim.threshold_deg={args.rotation_shim}")
    deployment, _ = load_deployment("none", args.robot, settings)
    out: dict[str, dict[str, list[dict[str, Any]]]] = {}
    for genome in args.genomes:
        for keep in (False, True):
            start = time.perf_counter()
            legs = [leg for pairs in tours.values()
                    for leg in tour(genome, args.robot, pairs, keep, deployment)]  # fmt: skip
            out.setdefault(str(genome), {})["kept" if keep else "empty"] = legs
            print(f"{genome} map {'kept' if keep else 'empty at each goal'}: "
                  f"{summary(legs, len(tours), per_tour)} "
                  f"({time.perf_counter() - start:.0f} s)", flush=True)
    if args.json:
        args.json.write_text(json.dumps(out))


if __name__ == "__main__":
    main()
