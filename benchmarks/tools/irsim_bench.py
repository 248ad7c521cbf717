"""The IR-SIM benchmark of issue 59: shipped planners, baselines and a pure pursuit in the
committed IR-SIM worlds, static and dynamic, per seed.

    python benchmarks/tools/irsim_bench.py --robot ugv --split test --out bench/irsim-ugv

Every pair of every world of ``benchmarks/irsim_worlds/SPLIT/ROBOT-*.yaml`` is driven
(:func:`mentor_core.irsim.episode.run_episode`, the 50 s limit) by each shipped planner of
the robot (``planners/ROBOT-paper-dual-sN.json`` as deployed, N a seed of ``--seeds``, with
IR-SIM's draws, lidar noise and wandering goals, from the same N, or from the seed at its
place in ``--irsim-seeds``: ``--seeds 1,2,3,1,2,3 --irsim-seeds 1,2,3,4,5,6`` pools two
draws under each planner, E100), by the baselines
(``--baselines``, as ``mentor-bench`` builds them, on the shipped limits, their guard and
plan the deployment's; each seed of ``--baseline-seeds``) and by a pure pursuit of the
seed-1 planner's plan (``--pursuit``). Progress on stderr; the tables (Markdown) on stdout
and in ``OUT/tables.md``, every episode in ``OUT/episodes.json``. ``--set KEY=VALUE``
changes the deployment as ``mentor-bench --set`` does (settings tried in E097);
``--fading N`` lets the planners' scan map forget what moved (E098). ``--families`` runs some
families only, and ``--replace DIR`` puts their episodes in place of those of an earlier run
(E096: the stopper worlds drawn again).
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from mentor_core.controller.deployment import load_deployment
from mentor_core.irsim.drivers import DriverSpec, baseline_driver, genome_driver, pursuit_driver
from mentor_core.irsim.episode import EpisodeResult, run_episode
from mentor_core.irsim.tally import HEADER, as_rows, row, scores
from mentor_core.irsim.world_file import IrsimWorld, load_world
from mentor_core.sim.robots import get_profile

ROOT = Path(__file__).resolve().parents[2]
WORLDS = ROOT / "benchmarks" / "irsim_worlds"
#: an agent slower than this share of the robot's rated speed counts as standing
STANDING = 0.05


def planner_path(robot: str, seed: int) -> Path:
    """The shipped dual-stage planner of ``robot`` trained with ``seed``."""
    return ROOT / "planners" / f"{robot}-paper-dual-s{seed}.json"


def run_all(worlds: list[IrsimWorld], runs: list[tuple[DriverSpec, int]],
            limit: float) -> list[EpisodeResult]:  # fmt: skip
    """Every pair of ``worlds`` by each ``(driver, seed)``, with progress on stderr."""
    total = sum(len(w.pairs) for w in worlds) * len(runs)
    done, began, out = 0, time.monotonic(), []
    for spec, seed in runs:
        for world in worlds:
            for k in range(len(world.pairs)):
                out.append(run_episode(world, k, spec, seed, limit))
                done += 1
            took = time.monotonic() - began
            print(f"[{done}/{total}] {spec.name} seed {seed} {world.name}: "
                  f"{took:.0f} s, about {took / done * (total - done):.0f} s left",
                  file=sys.stderr, flush=True)  # fmt: skip
    return out


def episode(row: dict) -> EpisodeResult:
    """An episode of an earlier run's ``episodes.json``."""
    speed = row["agent_speed"]
    return EpisodeResult(**{**row, "agent_speed": math.nan if speed is None else speed})


def label(result: EpisodeResult) -> str:
    """The row a result counts in: a planner's seeds apart, the others by name."""
    return result.driver


def tables(results: list[EpisodeResult], worlds: dict[str, IrsimWorld], robot: str) -> str:
    """The Markdown tables: static and dynamic worlds, each planner and seed, then the
    shipped planners' seeds pooled (mean and sd of the per-seed rates); dynamic per family."""
    pace = get_profile(robot).rated_speed
    lines = []
    for kind in ("static", "dynamic"):
        mine = [r for r in results if worlds[r.world].kind == kind]
        lines += [f"\n**{robot}, {kind} worlds**\n", HEADER]
        names = list(dict.fromkeys(label(r) for r in mine))
        for name in names:
            lines.append(row(name, scores([r for r in mine if label(r) == name])))
        shipped = [n for n in names if n.startswith(f"{robot}-paper-dual-s")]
        if len(shipped) > 1:
            per = [scores([r for r in mine if label(r) == n]) for n in shipped]
            rates = {key: [p[key] for p in per] for key in ("success", "collision_static",
                                                            "collision_agent", "spl")}
            lines.append(
                f"\nshipped planners, {len(shipped)} seeds: success "
                f"{100 * np.mean(rates['success']):.1f} ± {100 * np.std(rates['success']):.1f} %,"
                f" collisions static {100 * np.mean(rates['collision_static']):.1f} %, "
                f"with agents {100 * np.mean(rates['collision_agent']):.1f} ± "
                f"{100 * np.std(rates['collision_agent']):.1f} %, SPL "
                f"{np.mean(rates['spl']):.3f}")  # fmt: skip
        standing = [r for r in mine if r.outcome == "collision_agent"
                    and r.agent_speed < STANDING * pace]  # fmt: skip
        if kind == "dynamic":
            lines.append(f"\ncollisions with a standing agent: {len(standing)} "
                         f"({', '.join(sorted({r.driver for r in standing})) or 'none'})")
            lines += [f"\n**{robot}, dynamic worlds by family** (success / collision with an "
                      "agent)\n"]  # fmt: skip
            families = list(dict.fromkeys(worlds[r.world].family for r in mine))
            lines.append("| planner | " + " | ".join(families) + " |")
            lines.append("| --- |" + " --- |" * len(families))
            for name in names:
                cells = []
                for family in families:
                    s = scores([r for r in mine if label(r) == name
                                and worlds[r.world].family == family])  # fmt: skip
                    cells.append(f"{100 * s['success']:.0f} / {100 * s['collision_agent']:.0f}")
                lines.append(f"| {name} | " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def main(argv: Sequence[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--robot", required=True, choices=("ugv", "swarm"))
    p.add_argument("--split", default="validation", choices=("validation", "test"))
    p.add_argument("--seeds", default="1,2,3")
    p.add_argument("--irsim-seeds", default="",
                   help="IR-SIM's seed for each planner seed, in order (default: the same)")
    p.add_argument("--baselines", default="mapped-guard-vfh,mapped-guard-bug")
    p.add_argument("--baseline-seeds", default="1,2,3")
    p.add_argument("--pursuit", action=argparse.BooleanOptionalAction, default=True)
    p.add_argument("--kinds", default="static,dynamic")
    p.add_argument("--families", default="", help="only these families (default: all)")
    p.add_argument("--replace", type=Path, default=None,
                   help="an earlier run's folder: its episodes, but those of the worlds run "
                        "now, join this run's in the tables")  # fmt: skip
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    p.add_argument("--fading", type=int, default=None,
                   help="the scan map forgets what appeared after N decisions (E098)")
    p.add_argument("--limit", type=float, default=50.0)
    p.add_argument("--out", type=Path, required=True)
    args = p.parse_args(argv)
    seeds = [int(s) for s in args.seeds.split(",") if s]
    base_seeds = [int(s) for s in args.baseline_seeds.split(",") if s]
    kinds = args.kinds.split(",")
    paths = sorted((WORLDS / args.split).glob(f"{args.robot}-*.yaml"))
    every = [load_world(p, args.robot) for p in paths]
    families = [f for f in args.families.split(",") if f]
    worlds = [w for w in every if w.kind in kinds and (not families or w.family in families)]
    if not worlds:
        print(f"irsim_bench: no {args.robot} worlds of {args.split}", file=sys.stderr)
        return 2
    size = worlds[0].size
    deployment = load_deployment("shipped", args.robot, args.set)[0]
    draws = [int(s) for s in args.irsim_seeds.split(",") if s] or seeds
    if len(draws) != len(seeds):
        print("irsim_bench: --irsim-seeds needs one seed a planner seed", file=sys.stderr)
        return 2
    runs = [(genome_driver(planner_path(args.robot, s), args.robot, size, deployment,
                           fading=args.fading), d)
            for s, d in zip(seeds, draws, strict=True)]  # fmt: skip
    names = [b for b in args.baselines.split(",") if b]
    runs += [(baseline_driver(b, args.robot, size, deployment), s)
             for b in names for s in base_seeds]  # fmt: skip
    if args.pursuit:
        runs.append((pursuit_driver(planner_path(args.robot, seeds[0]), args.robot, size,
                                    deployment), seeds[0]))  # fmt: skip
    results = run_all(worlds, runs, args.limit)
    if args.replace is not None:
        rerun = {w.name for w in worlds}
        earlier = json.loads((args.replace / "episodes.json").read_text())["episodes"]
        results = [episode(e) for e in earlier if e["world"] not in rerun] + results
    text = tables(results, {w.name: w for w in every}, args.robot)
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "tables.md").write_text(text)
    (args.out / "episodes.json").write_text(json.dumps(
        {"robot": args.robot, "split": args.split, "set": args.set, "limit": args.limit,
         "fading": args.fading,
         "episodes": as_rows(results)}, indent=0, default=lambda v: None
        if isinstance(v, float) and math.isnan(v) else v))  # fmt: skip
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
