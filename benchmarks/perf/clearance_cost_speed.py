"""How long a plan on a scan map takes with the clearance cost and with the hard disc, on the
same maps, side by side in one process.

    .venv/bin/python benchmarks/perf/clearance_cost_speed.py [--robot swarm] [--pairs-per-family 4]

The maps are those the robot's shipped dual-stage seed-1 planner read, as deployed
(``--deployment shipped``), on the validation split's pairs (each guide's map at the episode's
end). On each map, from the episode's start to its goal, a planner is built and plans
(``GuideConfig.planner`` and ``GridPlanner.plan``, what ``PathGuide.set_map`` and a new plan
cost) with the robot's scan-map settings, once with its clearance cost and once as a hard
disc, alternating, and the median of ``--repeats`` rounds is printed per map set, with the
ratio.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import statistics
import time
from pathlib import Path

from mentor_core.benchmark.contenders import evolved
from mentor_core.benchmark.suite import build_suite
from mentor_core.controller.deployment import load_deployment
from mentor_core.controller.episodes import run_episodes
from mentor_core.navigation.scan_map import scan_guide_config, scan_guided_goals
from mentor_core.sim.robots import get_profile

PLANNERS = Path(__file__).resolve().parents[2] / "planners"


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--robot", default="swarm")
    p.add_argument("--pairs-per-family", type=int, default=4)
    p.add_argument("--repeats", type=int, default=5)
    args = p.parse_args(argv)
    robot = get_profile(args.robot)
    suite = build_suite(robot, "validation", pairs_per_family=args.pairs_per_family)
    shipped, _ = load_deployment("shipped", args.robot)
    contender = evolved(PLANNERS / f"{args.robot}-paper-dual-s1.json", robot, deployment=shipped)
    scenarios = [pair.scenario for pair in suite.pairs]
    config = contender.guide
    assert config is not None
    goals, guides = scan_guided_goals(scenarios, contender.profile, config)
    run_episodes(scenarios, contender.profile, contender.policy(scenarios),
                 time_budgets=50.0, input_goals=goals, stages=contender.stages)  # fmt: skip
    grids = [guide.map.grid() for guide in guides]
    costly = scan_guide_config(robot, clearance_cost=1.0)
    hard = dataclasses.replace(costly, least_margin=None, clearance_cost=0.0)
    seconds: dict[str, list[float]] = {"cost": [], "hard": []}
    for _ in range(args.repeats):
        for name, settings in (("cost", costly), ("hard", hard)):
            began = time.perf_counter()
            for grid, sc in zip(grids, scenarios, strict=True):
                settings.planner(grid).plan(sc.start[:2], sc.goal)
            seconds[name].append(time.perf_counter() - began)
    cost, hard_s = statistics.median(seconds["cost"]), statistics.median(seconds["hard"])
    print(json.dumps({"robot": args.robot, "maps": len(grids), "seconds_cost": cost,
                      "seconds_hard": hard_s, "ratio_cost_to_hard": cost / hard_s}))  # fmt: skip
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
