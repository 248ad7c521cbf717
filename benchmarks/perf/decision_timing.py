"""How long one decision and one plan take on scan maps of 20, 50 and 100 m (issue 57).

    .venv/bin/python benchmarks/perf/decision_timing.py [--robots ugv swarm]
        [--sides 20 50 100] [--pairs-per-family 4] [--planning inline thread]

Per robot, map side and planning mode: the shipped ``<robot>-paper-dual-s1`` as deployed
deciding through ``ScanGuidedPlanner.decide`` (the call the planner node makes), closed loop in
the reference simulator, on the validation split's rooms, dense forests and mazes
(``--pairs-per-family`` each; the arena sits in the middle of the scan map; a side of 0: the
map that grows from the first pose, as the planner node's without a size). ``inline``: each
plan made inside the decision that asks for it (the benchmark's and lockstep's way); ``thread``:
made beside the decisions (``ThreadPlans``, a plan again at least every second, the planner
node deciding on its timer). Prints one JSON object: per case the decisions' p50, p95, p99 and
max (ms), the same of one full plan (planner built and path found on the final map of each
episode, from its start to its goal), the map's cells and bytes, and the outcomes. A side whose
cells exceed the bound (``mentor_core.MAX_CELLS``) is reported as refused.
"""

from __future__ import annotations

import argparse
import json
import sys
import time

import numpy as np

from mentor_core.benchmark.suite import build_suite
from mentor_core.controller.deployment import load_deployment
from mentor_core.navigation.plan_worker import ThreadPlans
from mentor_core.runtime.guided_planner import ScanGuidedPlanner
from mentor_core.runtime.planner import GenomePlanner
from mentor_core.runtime.simulator import RobotSetup, run_reference_episode
from mentor_core.sim.robots import get_profile

FAMILIES = ("rooms", "forest_dense", "maze")


def quantiles(values: list[float]) -> dict[str, float]:
    """p50, p95, p99 and max of ``values`` (s), in ms."""
    a = np.asarray(values) * 1e3
    return {"n": len(a), **{k: round(float(np.percentile(a, q)), 3)
                            for k, q in (("p50", 50), ("p95", 95), ("p99", 99))},
            "max": round(float(a.max()), 3)}  # fmt: skip


def run_case(robot: str, side: float, planning: str, pairs: int) -> dict[str, object]:
    """One robot, map side and planning mode (module docstring)."""
    deployment, _ = load_deployment("shipped", robot)
    assert deployment.scan_map is not None
    genome = f"planners/{robot}-paper-dual-s1.json"
    plain = GenomePlanner.load(genome, robot, deployment)
    config = deployment.scan_map.guide(plain.profile)
    suite = build_suite(get_profile(robot), "validation", FAMILIES, pairs)
    decisions: list[float] = []
    plans: list[float] = []
    outcomes: dict[str, int] = {}
    cells = nbytes = 0
    for pair in suite.pairs:
        world = pair.scenario.world
        corner = (world.size / 2 - side / 2, world.size / 2 - side / 2)
        worker = ThreadPlans() if planning == "thread" else None
        try:
            mapped = ScanGuidedPlanner(plain, config, side or None, corner, worker=worker,
                                       replan_every=1.0 if worker else 0.0)  # fmt: skip
        except ValueError as err:
            return {"refused": str(err)}
        mapped.reset()

        def decide(ranges: np.ndarray, pose: tuple[float, float, float],
                   goal: tuple[float, float], mapped: ScanGuidedPlanner = mapped,
                   ) -> tuple[float, float]:  # fmt: skip
            began = time.perf_counter()
            out = mapped.decide(ranges, pose, goal)
            decisions.append(time.perf_counter() - began)
            return out

        start = tuple(float(v) for v in pair.scenario.start)
        goal = (float(pair.scenario.goal[0]), float(pair.scenario.goal[1]))
        setup = RobotSetup("robot", plain.profile, start, goal,  # type: ignore[arg-type]
                           time_budget=pair.time_limit)  # fmt: skip
        trace = run_reference_episode(world, [setup], {"robot": decide})["robot"]
        outcomes[trace.outcome] = outcomes.get(trace.outcome, 0) + 1
        if worker is not None:
            worker.close()
        scan = mapped.scan
        began = time.perf_counter()
        config.planner(scan.map.planning_grid()).plan(start[:2], goal)
        plans.append(time.perf_counter() - began)
        cells, nbytes = scan.map.hits.size, scan.map.nbytes
        print(f"decision_timing: {robot} {side:g} m {planning}: {pair.family} "
              f"{trace.outcome}", file=sys.stderr)
    return {"decision_ms": quantiles(decisions), "plan_ms": quantiles(plans),
            "control_period_s": plain.profile.control_period, "map_cells": cells,
            "map_mb": round(nbytes / 1e6, 1), "outcomes": outcomes}  # fmt: skip


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--robots", nargs="+", default=["ugv", "swarm"])
    p.add_argument("--sides", nargs="+", type=float, default=[20.0, 50.0, 100.0, 0.0],
                   help="m; 0: a growing map")  # fmt: skip
    p.add_argument("--pairs-per-family", type=int, default=4)
    p.add_argument("--planning", nargs="+", default=["inline", "thread"],
                   choices=["inline", "thread"])  # fmt: skip
    args = p.parse_args(argv)
    out: dict[str, object] = {"date": time.strftime("%Y-%m-%d")}
    for robot in args.robots:
        run_case(robot, 20.0, "inline", 1)  # warm-up: numba kernels compiled or loaded
        for side in args.sides:
            for planning in args.planning:
                out[f"{robot} {side:g} m {planning}"] = run_case(robot, side, planning,
                                                                 args.pairs_per_family)
    print(json.dumps(out, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
