"""``mentor-eval``: test evolved planners on unseen environments.

    mentor-eval runs/ugv-dual/best_genome.json --bag bags/unseen/ugv --out eval.json
    mentor-eval a.json b.json --robot swarm --world my_world.yaml
    mentor-eval a.json --robot ugv --seed 7 --n 10          # a freshly sampled world
    mentor-eval a.json --bag bags/unseen/swarm --record out/episodes   # + an episode bag
    mentor-eval a.json --robot ugv --map office.yaml --seed 3     # pairs sampled on a ROS map
    mentor-eval a.json --bag bags/unseen/ugv --global-plan        # + along a global plan
    mentor-eval a.json --bag bags/unseen/ugv --deployment shipped # as the shipped planners
    mentor-eval a.json --bag bags/unseen/swarm --deployment shipped --set stages.turn_gain=null
    mentor-eval a.json --bag bags/unseen/ugv --deployment my_deployment.yaml
    mentor-eval a.json --bag bags/unseen/ugv --deployment none --deployment shipped  # both

An episode ends within the goal radius, at the time limit (50 s) or on a collision. Prints a
table per planner and writes JSON (format ``mentor-eval``) that ``mentor-report`` draws.
``--record`` also writes the episodes as a rosbag2 episode bag (scan, odometry, cmd_vel, goal
and events per robot), for ``ros2 bag play`` or Foxglove. ``--map`` takes the world from a
ROS map (``map_server`` YAML + PGM; ``--n`` start/goal pairs sampled with ``--seed``, 0 by
default). ``--global-plan`` runs every genome a second time, labelled ``<label> +global-plan``,
its network steered towards a point ``--lookahead`` m along a shortest path planned on the
world's occupancy grid (:mod:`mentor_core.navigation.guide`), the plain run beside it.
``--deployment`` runs each genome as a deployment (:mod:`mentor_core.controller.deployment`:
``shipped``, ``none`` or a file; ``--set`` changes one key of it), as ``mentor-bench`` and the
planner node's ``deployment`` do; one whose deployment has a scan map steers to the carrot of
a plan on the map of its own readings (the ``--global-plan`` run along the world's grid
instead). Given more than once, each genome runs once per deployment, labelled ``<label>
(<deployment>)``: ``--deployment none --deployment shipped`` sets as trained beside as
deployed.

A scenario whose start puts the robot's body into an obstacle or a wall is skipped with a
warning line (as the simulator node skips it: :func:`mentor_core.sim.scenarios.start_overlap`);
the others keep their numbers. ``--out`` and ``--record`` never replace an input, nor an
existing file or bag unless ``--force`` is given; both are checked before anything runs.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path
from typing import Any

import numpy as np

from mentor_core.atomic import write_json_atomic
from mentor_core.cli.arguments import (
    Parser,
    add_deployment_arguments,
    count,
    deployment_files,
    deployment_names,
    deployment_of,
    duration,
    fail,
    seed,
)
from mentor_core.cli.outputs import check_bag, check_distinct, check_file
from mentor_core.errors import FileFormatError, MentorError, one_line
from mentor_core.files.bags import read_scenario_bag
from mentor_core.navigation.grid import world_grid
from mentor_core.navigation.guide import GuideConfig, guide_config, guided_goals, world_guides
from mentor_core.navigation.map_world import load_map_world, load_world_file
from mentor_core.navigation.scan_map import scan_guided_goals
from mentor_core.runtime.guided_planner import GuidedPlanner, ScanGuidedPlanner
from mentor_core.runtime.planner import GenomePlanner, deployed_genome
from mentor_core.runtime.recording import record_planners
from mentor_core.runtime.robot_graph import one_period
from mentor_core.runtime.simulator import Decide
from mentor_core.sim.robots import RobotProfile, get_profile
from mentor_core.sim.scenarios import sample_scenarios, sample_world, start_overlap
from mentor_core.sim.world import Scenario, World
from mentor_core.training.assessment import TEST_TIME_LIMIT, Assessment, assess

EVAL_FORMAT = "mentor-eval"
EVAL_VERSION = 1


def load_scenarios(args: argparse.Namespace) -> tuple[RobotProfile, World, list[Scenario], str]:
    """The robot profile, world and scenarios the command line names, and their source."""
    if args.seed is not None and (args.bag is not None or args.world is not None):
        raise MentorError("--seed samples a world or a map's pairs; not with --bag or --world")
    if args.bag is not None:
        world, scenarios, robot, _meta = read_scenario_bag(args.bag)
        if args.robot and args.robot != robot:
            raise FileFormatError(args.bag, f"bag is for robot '{robot}', not '{args.robot}'")
        return get_profile(robot), world, list(scenarios), str(args.bag)
    if args.world is None and args.map is None and args.seed is None:
        raise MentorError("give --bag, --world, --map or --seed")
    if not args.robot:
        raise MentorError("--robot is required with --world, --map or --seed")
    profile = get_profile(args.robot)
    if args.world is not None:
        world, scenarios = load_world_file(args.world)
        if not scenarios:
            raise FileFormatError(args.world, "world file has no start/goal pairs")
        return profile, world, list(scenarios), str(args.world)
    seed = 0 if args.seed is None else args.seed
    rng = np.random.default_rng(seed)
    if args.map is not None:
        world, _grid = load_map_world(args.map)
        try:
            scenarios = sample_scenarios(world, profile, args.n, rng)
        except ValueError as err:
            raise FileFormatError(args.map, f"no {args.n} start/goal pairs: {err}") from None
        return profile, world, scenarios, f"{args.map} seed {seed}"
    world = sample_world(profile.test_arena, rng)
    try:
        scenarios = sample_scenarios(world, profile, args.n, rng)
    except ValueError as err:
        raise MentorError(f"--n {args.n}: {one_line(err)}") from None
    return profile, world, scenarios, f"seed {seed}"


def _table(label: str, assessment: Assessment) -> str:
    lines = [f"{label}", f"  {'#':>3}  {'outcome':<9} {'time s':>7} {'dist m':>7}"]
    for r in assessment.results:
        outcome = r.outcome.replace("_", " ")
        lines.append(f"  {r.scenario:>3}  {outcome:<9} {r.time:7.1f} {r.final_distance:7.3f}")
    s = assessment.summary()
    mean_t = "-" if math.isnan(s["mean_time_reached"]) else f"{s['mean_time_reached']:.1f} s"
    lines.append(
        f"  success {s['success_rate']:.0%}  collisions {s['collision_rate']:.0%}  "
        f"survivability {s['survivability']:.0%}  mean time to goal {mean_t}"
    )
    return "\n".join(lines)


def _finite_or_none(x: float) -> float | None:
    return None if math.isnan(x) else x


def eval_document(
    profile: RobotProfile,
    world: World,
    scenarios: list[Scenario],
    source: str,
    time_limit: float,
    runs: list[tuple[str, str, Assessment]],
    skipped: dict[int, str] | None = None,
) -> dict[str, Any]:
    """The JSON document of an evaluation (format ``mentor-eval``, version 1); ``skipped``:
    the scenarios not run, with the reason (results name the others by number)."""
    return {
        "format": EVAL_FORMAT,
        "version": EVAL_VERSION,
        "robot": profile.name,
        "source": source,
        "world": {"size": world.size, "obstacles": world.obstacles.tolist()},
        "scenarios": [{"start": list(s.start), "goal": list(s.goal)} for s in scenarios],
        "skipped": [{"scenario": i, "reason": why} for i, why in sorted((skipped or {}).items())],
        "goal_radius": profile.goal_radius,
        "time_limit": time_limit,
        "runs": [
            {
                "genome": label,
                "path": path,
                "results": [
                    {
                        "scenario": r.scenario,
                        "reached": r.reached,
                        "collided": r.collided,
                        "timed_out": r.timed_out,
                        "time": r.time,
                        "final_distance": r.final_distance,
                        "trajectory": r.trajectory.tolist(),
                    }
                    for r in a.results
                ],
                "summary": {k: _finite_or_none(v) for k, v in a.summary().items()},
            }
            for label, path, a in runs
        ],
    }


def record(
    path: Path,
    profile: RobotProfile,
    world: World,
    scenarios: list[Scenario],
    time_limit: float,
    runs: list[tuple[str, str, Assessment]],
    planners: list[GenomePlanner | GuidedPlanner | ScanGuidedPlanner],
    numbers: list[int],
    force: bool = False,
) -> None:
    """Write the episodes of every genome as an episode bag (``--record``).

    The bag holds what the ROS simulator would publish: each genome's planner (``planners[i]``
    for ``runs[i]``) runs in the reference (pymunk) simulator, ``robot_<i>`` for genome ``i``.
    An outcome that differs from the batched evaluation (float32 scans can tip a borderline
    episode) is reported on stderr. ``numbers``: the scenarios' numbers in their source;
    ``force``: replace an existing bag at ``path``. ``profile``: the planners' (its control
    period is the recording's).
    """
    names = [f"robot_{i}" for i in range(len(planners))]
    decide: dict[str, Decide] = {ns: p.decide for ns, p in zip(names, planners, strict=True)}
    resets = {ns: p.reset for ns, p in zip(names, planners, strict=True)}  # each episode blank
    recorder, traces = record_planners(
        world, profile, decide, scenarios, time_limit, numbers, resets
    )
    labels = {f"robot_{i}": label for i, (label, _, _) in enumerate(runs)}
    recorder.save(
        path, profile, {"genomes": labels, "time_limit": time_limit}, overwrite=force
    )
    for i, (label, _, assessment) in enumerate(runs):
        for result, trace in zip(assessment.results, traces[f"robot_{i}"], strict=True):
            if result.outcome != trace.outcome:
                print(
                    f"mentor-eval: {label} scenario {result.scenario}: {trace.outcome} in the "
                    f"recording, {result.outcome} in the table",
                    file=sys.stderr,
                )
    print(f"mentor-eval: recorded {recorder.n_episodes} episodes in {path}", file=sys.stderr)


def _planner(
    plain: GenomePlanner, guide: GuideConfig | None, world: World, mode: str
) -> GenomePlanner | GuidedPlanner | ScanGuidedPlanner:
    """The planner recorded for a run of ``mode`` (``""`` or ``"+global-plan"``): the plain
    one, or with ``guide`` the one planning on the map of its own readings (the arena's
    square, as in the table), or the guided one planning on ``world``'s grid."""
    if not mode:
        return plain if guide is None else ScanGuidedPlanner(plain, guide, world.size)
    assert guide is not None
    planner = GuidedPlanner(plain, guide)
    planner.set_map(world_grid(world, guide.resolution))
    return planner


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of mentor-eval."""
    p = Parser(prog="mentor-eval", description=__doc__.split("\n")[0])
    p.add_argument("genomes", nargs="+", type=Path, help="genome JSON files")
    src = p.add_mutually_exclusive_group()
    src.add_argument("--bag", type=Path, help="scenario bag (e.g. bags/unseen/ugv)")
    src.add_argument("--world", type=Path, help="world YAML file with start/goal pairs")
    src.add_argument(
        "--map", type=Path, help="ROS map YAML (+ PGM); --n pairs sampled on it with --seed"
    )
    p.add_argument(
        "--seed", type=seed, help="sample a fresh test world (or a map's pairs), seed >= 0"
    )
    p.add_argument("--robot", choices=("ugv", "swarm"), help="robot profile")
    p.add_argument("--n", type=count, default=10, help="start/goal pairs with --seed (10)")
    p.add_argument("--time-limit", type=duration, default=TEST_TIME_LIMIT, help="s (50)")
    p.add_argument("--out", type=Path, help="write the results as JSON here")
    p.add_argument("--label", action="append", help="a label per genome (default: file path)")
    p.add_argument(
        "--record",
        type=Path,
        help="also run the episodes in the reference (pymunk) simulator and write them as an "
        "episode bag here (namespaces robot_0, robot_1, ... in run order)",
    )
    p.add_argument(
        "--global-plan",
        action="store_true",
        help="also run each genome along a shortest path planned on the world's grid",
    )
    p.add_argument(
        "--lookahead",
        type=float,
        metavar="M",
        help="with --global-plan: m along the path the network steers to (default: 2 goal "
        "radii)",
    )
    add_deployment_arguments(p, "each genome", repeatable=True)
    p.add_argument(
        "--force", action="store_true", help="replace an existing --out file or --record bag"
    )
    return p


def check_outputs(args: argparse.Namespace) -> None:
    """Refuse ``--out`` and ``--record`` paths that would replace an input, or an existing
    file or bag without ``--force`` (before any work)."""
    sources = (args.world, args.bag, args.map)
    inputs = [*args.genomes, *(p for p in sources if p is not None), *deployment_files(args)]
    check_distinct({"--out": args.out, "--record": args.record})
    if args.out is not None:
        check_file("--out", args.out, inputs, args.force)
    if args.record is not None:
        check_bag("--record", args.record, inputs, args.force)


def runnable(
    profile: RobotProfile, world: World, scenarios: list[Scenario], source: str
) -> tuple[list[int], dict[int, str]]:
    """The numbers of the scenarios the robot can start, and the others with the reason (one
    warning line each on stderr)."""
    keep: list[int] = []
    skipped: dict[int, str] = {}
    for i, sc in enumerate(scenarios):
        fault = start_overlap(world, sc.start, profile)
        if fault:
            skipped[i] = fault
            print(f"mentor-eval: warning: {source}: scenario {i} skipped: {fault}",
                  file=sys.stderr)  # fmt: skip
        else:
            keep.append(i)
    if not keep:
        raise FileFormatError(source, f"no scenario can start robot {profile.name!r}")
    return keep, skipped


def main(argv: list[str] | None = None) -> int:
    """Entry point; returns the exit status (2 on bad arguments or input)."""
    args = build_parser().parse_args(argv)
    labels = args.label or [str(g) for g in args.genomes]
    if len(labels) != len(args.genomes):
        return fail("mentor-eval", "--label: give one --label per genome")
    if args.lookahead is not None and not (math.isfinite(args.lookahead) and args.lookahead > 0):
        return fail("mentor-eval", "--lookahead must be a positive number of metres")
    if args.lookahead is not None and not args.global_plan:
        return fail("mentor-eval", "--lookahead: only with --global-plan")
    try:
        check_outputs(args)
        profile, world, scenarios, source = load_scenarios(args)
        deployments = list(zip(deployment_names(args), deployment_of(args, profile.name),
                               strict=True))  # fmt: skip
        numbers, skipped = runnable(profile, world, scenarios, source)
        chosen = [scenarios[i] for i in numbers]
        runs: list[tuple[str, str, Assessment]] = []
        planners: list[GenomePlanner | GuidedPlanner | ScanGuidedPlanner] = []
        modes = [""] + ["+global-plan"] * args.global_plan
        runs_of = [(label, path, name, *deployed_genome(path, profile.name, deployment))
                   for label, path in zip(labels, args.genomes, strict=True)
                   for name, deployment in deployments]  # fmt: skip
        if args.record is not None:  # one recording steps at one period: known before any run
            one_period([r[4].profile.control_period for r in runs_of],
                       "--record them one at a time")  # fmt: skip
        # the planners' profile (their period and the table's time budgets) steps a recording
        recording_profile = runs_of[0][4].profile
        for label, path, name, genome, deployed in runs_of:
            planner = deployed.profile
            goals = [sc.goal for sc in chosen]
            if len(deployments) > 1:
                label = f"{label} ({name})"
            for mode in modes:
                guide = deployed.guide
                aims = None
                if mode == "+global-plan":
                    guide = guide_config(planner, lookahead=args.lookahead)
                    aims = guided_goals(world_guides(world, guide, len(goals)), goals)
                elif guide is not None:
                    aims = scan_guided_goals(chosen, planner, guide)[0]
                try:
                    assessment = assess(genome, planner, chosen, args.time_limit, aims, numbers,
                                        deployed.stages)  # fmt: skip
                except ValueError as err:
                    raise FileFormatError(path, str(err)) from None
                run_label = f"{label} {mode}" if mode else label
                print(_table(run_label, assessment))
                runs.append((run_label, str(path), assessment))
                if args.record is not None:
                    # the guard counts the arena's border as known, as in the table
                    plain = GenomePlanner(genome, planner, str(path), world.size, deployed.stages)
                    planners.append(_planner(plain, guide, world, mode))
        if args.record is not None:
            record(args.record, recording_profile, world, chosen, args.time_limit, runs,
                   planners, numbers, args.force)  # fmt: skip
        if args.out is not None:
            doc = eval_document(
                profile, world, scenarios, source, args.time_limit, runs, skipped
            )
            write_json_atomic(args.out, doc)
            print(f"mentor-eval: wrote {args.out}", file=sys.stderr)
    except (MentorError, OSError) as err:
        return fail("mentor-eval", err)
    return 0


if __name__ == "__main__":
    sys.exit(main())
