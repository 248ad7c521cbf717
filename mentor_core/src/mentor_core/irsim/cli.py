"""``mentor-irsim``: drive planners through the start/goal pairs of IR-SIM worlds.

    mentor-irsim benchmarks/irsim_worlds/test/ugv-crowd-0.yaml \\
        --genome planners/ugv-paper-dual-s1.json

Each world file (:mod:`mentor_core.irsim.world_file`; all of one robot) is driven pair by
pair by each planner named: ``--genome FILE`` as the planner node deploys it
(``--deployment``: ``shipped``, the default, ``none`` or a file), ``--baseline NAME``
(``vfh``, ``bug``, with ``guard-`` and ``mapped-`` as ``mentor-bench`` builds them) and
``--pursuit FILE`` (a pure pursuit of that genome's plan). One line per episode, then each
planner's scores (:mod:`mentor_core.irsim.tally`); ``--out`` writes every episode as JSON,
``--figure`` their trajectories as a PNG. Exit status 0, or 2 with one line on stderr for a
bad world, genome or argument; needs the extra ``mentor-core[irsim]``.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from pathlib import Path

from mentor_core.atomic import write_json_atomic
from mentor_core.benchmark.suite import PAPER_LIMIT
from mentor_core.controller.deployment import load_deployment
from mentor_core.errors import MentorError, one_line
from mentor_core.irsim.dependency import load_irsim
from mentor_core.irsim.drivers import DriverSpec, baseline_driver, genome_driver, pursuit_driver
from mentor_core.irsim.episode import EpisodeResult, run_episode
from mentor_core.irsim.tally import HEADER, as_rows, row, scores
from mentor_core.irsim.world_file import IrsimWorld, load_world

PROG = "mentor-irsim"


def build_parser() -> argparse.ArgumentParser:
    """The command's options (module docstring)."""
    p = argparse.ArgumentParser(prog=PROG, description=__doc__.split("\n")[0])
    p.add_argument("worlds", nargs="+", type=Path, help="IR-SIM world files of this project")
    p.add_argument("--genome", action="append", default=[], help="a genome JSON file")
    p.add_argument("--baseline", action="append", default=[],
                   help="[mapped-][guard-](vfh|bug)")  # fmt: skip
    p.add_argument("--pursuit", action="append", default=[],
                   help="a genome whose plan a pure pursuit follows")  # fmt: skip
    p.add_argument("--deployment", default="shipped",
                   help="shipped (default), none or a deployment file")  # fmt: skip
    p.add_argument("--pairs", default="", help="pair numbers of each world, e.g. 0,2 (all)")
    p.add_argument("--seed", type=int, default=1, help="IR-SIM's draws (lidar noise, agents)")
    p.add_argument("--limit", type=float, default=PAPER_LIMIT, help="s an episode may take")
    p.add_argument("--out", type=Path, help="write every episode as JSON here")
    p.add_argument("--figure", type=Path, help="draw the episodes' trajectories (PNG)")
    return p


def drivers(args: argparse.Namespace, robot: str, size: float) -> list[DriverSpec]:
    """The planners the arguments name (module docstring); MentorError for none."""
    deployment = load_deployment(args.deployment, robot)[0]
    specs = [genome_driver(g, robot, size, deployment) for g in args.genome]
    specs += [baseline_driver(b, robot, size, deployment) for b in args.baseline]
    specs += [pursuit_driver(g, robot, size, deployment) for g in args.pursuit]
    if not specs:
        raise MentorError("nothing to drive: give --genome, --baseline or --pursuit")
    return specs


def chosen_pairs(text: str, world: IrsimWorld) -> list[int]:
    """The pair numbers ``--pairs`` names in ``world`` (all when empty); MentorError for a
    bad one."""
    if not text:
        return list(range(len(world.pairs)))
    try:
        picked = [int(v) for v in text.split(",") if v.strip()]
    except ValueError:
        raise MentorError(f"--pairs: expected numbers like 0,2, got {text!r}") from None
    bad = [k for k in picked if not 0 <= k < len(world.pairs)]
    if bad:
        raise MentorError(f"--pairs: {world.name} has pairs 0..{len(world.pairs) - 1}, "
                          f"not {bad[0]}")  # fmt: skip
    return picked


def run(args: argparse.Namespace) -> list[EpisodeResult]:
    """Every episode the arguments ask for, printed as it ends."""
    load_irsim()
    worlds = [load_world(path) for path in args.worlds]
    robots = {w.robot for w in worlds}
    if len(robots) > 1:
        raise MentorError(f"the worlds are for several robots ({', '.join(sorted(robots))}); "
                          "give one robot's")  # fmt: skip
    if not (args.limit > 0 and args.limit < float("inf")):
        raise MentorError(f"--limit: expected a positive number of s, got {args.limit}")
    specs = drivers(args, worlds[0].robot, worlds[0].size)
    results = []
    for world in worlds:
        for k in chosen_pairs(args.pairs, world):
            for spec in specs:
                r = run_episode(world, k, spec, args.seed, args.limit,
                                record=args.figure is not None)  # fmt: skip
                print(f"{world.name} pair {k}: {spec.name}: {r.outcome} after {r.time:.1f} s, "
                      f"{r.path_length:.2f} m driven, SPL {r.spl:.3f}", flush=True)
                results.append(r)
    return results


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point; the exit status (module docstring)."""
    args = build_parser().parse_args(argv)
    try:
        results = run(args)
        print(HEADER)
        for name in dict.fromkeys(r.driver for r in results):
            print(row(name, scores([r for r in results if r.driver == name])))
        if args.out is not None:
            write_json_atomic(args.out, {"seed": args.seed, "limit": args.limit,
                                         "episodes": as_rows(results)}, indent=1)
        if args.figure is not None:
            from mentor_core.irsim.figures import save_episodes

            worlds = {w.name: w for w in (load_world(p) for p in args.worlds)}
            save_episodes(args.figure, [(worlds[r.world], r) for r in results])
    except (MentorError, OSError) as err:
        print(f"{PROG}: {one_line(err)}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
