"""Probe: how straight does a planner drive where nothing is in the way?

    .venv/bin/python benchmarks/probes/open_field.py GENOME [GENOME ...] --robot ugv
        [--distance 6] [--bearings 16] [--rotation-shim 45] [--limit 100]

An empty arena, the robot at its centre facing +x, one goal per bearing (``--bearings``
evenly spaced over the full circle) at ``--distance`` m (default: half the test arena). Each
genome runs with the planner settings of its metadata (as ``mentor-eval`` runs it), also
behind a rotation shim (``--rotation-shim``, a deployment of that stage alone:
``--set stages.rotation_shim.threshold_deg=DEG``; 0: not), as ``shim-<genome>``, and the two
baselines within the shipped limits beside them (``--baselines``). Printed per planner: goals
reached and SPL, overall and per bearing (the shortest path is the straight run into the
goal's disc).

A planner that crosses an empty world with an SPL well under 1 loses that share of every path
elsewhere too: the shipped UGV planners of 2026-12-02 zig-zag round their goal with an SPL of
0.6 here, while VFH+ and Bug2 reach 0.98 (experiment E047, "More scenarios, a
mirror-symmetric planner, ..."). Not a split of the benchmark: nothing here is tuned on it.
"""

from __future__ import annotations

import math

import numpy as np

from mentor_core.benchmark.contenders import (
    HAND_WRITTEN,
    Contender,
    evolved,
    hand_written,
)
from mentor_core.benchmark.scores import spl
from mentor_core.benchmark.suite import shipped_limits
from mentor_core.cli import arguments
from mentor_core.controller.deployment import Deployment, load_deployment
from mentor_core.controller.episodes import run_episodes
from mentor_core.errors import MentorError
from mentor_core.sim.robots import get_profile
from mentor_core.sim.world import Scenario, World


def open_field(arena: float, distance: float, bearings: int) -> list[Scenario]:
    """One scenario per bearing: start at the centre of an empty ``arena`` (m) facing +x,
    goal ``distance`` m away at bearing ``2 pi i / bearings - pi``."""
    world = World(arena, name="open field")
    c = arena / 2.0
    angles = [2.0 * math.pi * i / bearings - math.pi for i in range(bearings)]
    return [Scenario(world, (c, c, 0.0), (c + distance * math.cos(a), c + distance * math.sin(a)))
            for a in angles]


def main() -> None:
    parser = arguments.Parser(description=__doc__.split("\n\n")[0])
    parser.add_argument("genomes", nargs="*", help="genome JSON files")
    parser.add_argument("--robot", default="ugv")
    parser.add_argument("--distance", type=float, default=None,
                        help="m from start to goal (default: half the test arena)")
    parser.add_argument("--bearings", type=arguments.count, default=16)
    parser.add_argument("--rotation-shim", type=float, default=45.0,
                        help="also run each genome behind this shim (deg; 0: not)")
    parser.add_argument("--baselines", default="vfh,bug", help="comma-separated; '' for none")
    parser.add_argument("--limit", type=arguments.duration, default=100.0, help="time limit, s")
    args = parser.parse_args()
    try:
        robot = get_profile(args.robot)
    except MentorError as err:
        parser.exit(1, f"open_field.py: {err}\n")
    shim: Deployment | None = None
    if args.rotation_shim:  # 0: not
        try:
            shim, _ = load_deployment("none", robot.name,
                                      [f"stages.rotation_shim.threshold_deg={args.rotation_shim}"])
        except MentorError as err:
            parser.error(f"--rotation-shim: {err}")
    distance = robot.test_arena / 2.0 if args.distance is None else args.distance
    if not robot.goal_radius < distance < robot.test_arena:
        parser.error(f"--distance must be in ({robot.goal_radius:g}, {robot.test_arena:g}) m "
                     f"(the goal radius, the test arena), got {distance}")
    # an arena twice the distance wide each way, so that no wall is near a wide detour
    scenarios = open_field(4.0 * distance, distance, args.bearings)
    shortest = np.full(len(scenarios), distance - robot.goal_radius)

    baselines = [name for name in args.baselines.split(",") if name]
    unknown = sorted(set(baselines) - set(HAND_WRITTEN))
    if unknown:
        known = ", ".join(HAND_WRITTEN)
        parser.error(f"--baselines: unknown {', '.join(unknown)} (known: {known})")
    contenders: list[Contender] = []
    try:
        for path in args.genomes:
            contenders.append(evolved(path, robot))
            if shim is not None:
                contenders.append(evolved(path, robot, f"shim-{path}", shim))
    except MentorError as err:
        parser.exit(1, f"open_field.py: {err}\n")
    if baselines:
        try:
            limits = shipped_limits(robot)
        except ValueError as err:
            parser.exit(1, f"open_field.py: --baselines: {err}\n")
        contenders += [hand_written(name, limits) for name in baselines]

    print(f"{args.robot}: goals {distance:g} m away at {args.bearings} bearings from -180 deg, "
          f"{args.limit:g} s each")
    for c in contenders:
        batch = run_episodes(scenarios, c.profile, c.policy(scenarios),
                             time_budgets=args.limit, input_goals=c.input_goals(scenarios),
                             stages=c.stages)  # fmt: skip
        values = spl(batch.reached, shortest, batch.path_length(c.profile))
        per_bearing = " ".join(f"{v:.2f}" for v in values)
        print(f"{c.name}: reached {int(batch.reached.sum())}/{len(scenarios)}, "
              f"SPL {values.mean():.2f}; per bearing {per_bearing}")


if __name__ == "__main__":
    main()
