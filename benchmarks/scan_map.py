"""Planners with and without a map of what their own sensors read, on the generalisation
benchmark (``mentor_core.navigation.scan_map``: a plan on that map, unknown space free).

    .venv/bin/python benchmarks/scan_map.py GENOME [GENOME ...] [--robot ugv]
        [--split validation] [--pairs-per-family 20] [--families F,G] [--baselines vfh,bug]
        [--resolution M] [--beam-arcs] [--margin K] [--lookahead K] [--mapped-only]
        [--out FILE.json]

Per contender (each genome, then each baseline) two runs of every pair with the paper's
50 s: plain, and steering to the carrot of a plan on its own scan map. Prints success per
family and overall, and (``--out``) writes them as JSON. An experiment: the map is built from
the readings the simulator gives the robot at its pose, nothing else of the world is known.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np

from mentor_core.benchmark.contenders import Contender, evolved, hand_written
from mentor_core.benchmark.suite import build_suite, reference_profile
from mentor_core.navigation.guide import guide_config
from mentor_core.navigation.scan_map import scan_guided_goals
from mentor_core.sim.episode import run_episodes
from mentor_core.sim.robots import get_profile

PAPER_LIMIT = 50.0


def main() -> None:
    """Run the comparison and print one line per contender and mode."""
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("genomes", nargs="*")
    p.add_argument("--robot", default="ugv")
    p.add_argument("--split", default="validation")
    p.add_argument("--pairs-per-family", type=int, default=20)
    p.add_argument("--families")
    p.add_argument("--baselines", default="vfh")
    p.add_argument("--resolution", type=float, default=0.1, help="scan map cell (m)")
    p.add_argument("--beam-arcs", action="store_true",
                   help="put a beam's hit on every ray of its cone (ScanMap)")
    p.add_argument("--margin", type=float,
                   help="plan's margin past the footprint, in half body diagonals (default 1)")
    p.add_argument("--lookahead", type=float,
                   help="carrot's distance along the plan, in goal radii (default 2)")
    p.add_argument("--mapped-only", action="store_true", help="skip the plain runs")
    p.add_argument("--out", type=Path)
    args = p.parse_args()
    robot = get_profile(args.robot)
    families = None if args.families is None else args.families.split(",")
    suite = build_suite(robot, args.split, families, args.pairs_per_family)
    contenders: list[Contender] = [evolved(g, robot, Path(g).parent.name) for g in args.genomes]
    contenders += [hand_written(b, reference_profile(robot))
                   for b in args.baselines.split(",") if b]  # fmt: skip
    fams = [pair.family for pair in suite.pairs]
    results: dict[str, dict[str, dict[str, float]]] = {}
    for c in contenders:
        for mode in ("scan_map",) if args.mapped_only else ("plain", "scan_map"):
            t0 = time.perf_counter()
            reached = np.zeros(len(suite.pairs), dtype=bool)
            plans = 0
            for family in suite.families:
                idx = [i for i, f in enumerate(fams) if f == family]
                scenarios = [suite.pairs[i].scenario for i in idx]
                goals = None
                if mode == "scan_map":
                    config = guide_config(
                        c.profile, resolution=args.resolution,
                        margin=None if args.margin is None
                        else args.margin * c.profile.half_diagonal,
                        lookahead=None if args.lookahead is None
                        else args.lookahead * c.profile.goal_radius,
                    )  # fmt: skip
                    goals, guides = scan_guided_goals(scenarios, c.profile, config,
                                                      args.beam_arcs)
                batch = run_episodes(scenarios, c.profile, c.policy(scenarios),
                                     time_budgets=PAPER_LIMIT, input_goals=goals)  # fmt: skip
                reached[idx] = batch.reached
                if mode == "scan_map":
                    plans += sum(g.plans for g in guides)
            row = {f: float(reached[[i for i, x in enumerate(fams) if x == f]].mean())
                   for f in suite.families}  # fmt: skip
            row["overall"] = float(reached.mean())
            results[f"{c.name} {mode}"] = row
            cells = " ".join(f"{f[:8]}={v:.2f}" for f, v in row.items())
            print(f"{c.name:<24} {mode:<8} {cells} (plans {plans}, "
                  f"{time.perf_counter() - t0:.0f} s)", flush=True)  # fmt: skip
    if args.out is not None:
        args.out.write_text(json.dumps(results, indent=1) + "\n")


if __name__ == "__main__":
    main()
