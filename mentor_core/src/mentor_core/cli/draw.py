"""``mentor-draw``: draw a world, one scenario and the robot's rays at its start as a PNG.

Examples::

    mentor-draw --robot ugv --seed 3 --scenario 5 --demo --out world.png
    mentor-draw --robot ugv --walls 1 2 --out world.png   # the shipped configs' training world
    mentor-draw --robot swarm --world my_world.yaml --out world.png

The world comes from a world file (``--world``, which may name a ROS map) or is the training
DoE of ``--seed`` (the paper's, or with ``--walls MIN MAX`` long walls as the shipped training
configs' ``doe: {wall_count: [1, 2]}``). Rays are read with the reference physics
(:class:`mentor_core.sim.pymunk_world.PymunkWorld`).
``--demo`` adds a naive straight-to-goal run (turn to the goal, step as far as allowed, stop
at the goal radius, on a collision or when the time budget is spent). Bad input gives a
one-line error naming the fault and exit code 2 (``--walls`` more than fit in the arena
included); the PNG is written atomically, never over the world file, and over an existing file
only with ``--force`` (checked before anything is drawn).
"""

from __future__ import annotations

import argparse
import math
import sys
from collections.abc import Sequence
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from mentor_core.cli.arguments import Parser, fail, index, seed
from mentor_core.cli.outputs import check_file
from mentor_core.errors import ConfigError, MentorError
from mentor_core.navigation.map_world import load_world_file
from mentor_core.report.plots import draw_world, new_figure, save_png
from mentor_core.sim.collision import sample_counts
from mentor_core.sim.kinematics import arc_samples, unicycle_arc, wrap_angle
from mentor_core.sim.pymunk_world import PymunkWorld
from mentor_core.sim.robots import RobotProfile, load_profiles
from mentor_core.sim.scenarios import DoEConfig, training_scenarios
from mentor_core.sim.world import Scenario

PROG = "mentor-draw"


def build_parser() -> argparse.ArgumentParser:
    parser = Parser(prog=PROG, description=__doc__.splitlines()[0])
    parser.add_argument("--robot", required=True, help="robot profile name (ugv, swarm)")
    source = parser.add_mutually_exclusive_group()
    source.add_argument("--world", type=Path, help="world file (YAML, format mentor-world)")
    source.add_argument("--seed", type=seed, default=0, help="seed of the training DoE (0)")
    parser.add_argument(
        "--walls", type=index, nargs=2, metavar=("MIN", "MAX"), default=(0, 0),
        help="long walls in the training DoE (default 0 0: the paper's; shipped configs: 1 2)",
    )  # fmt: skip
    parser.add_argument("--scenario", type=index, help="scenario index to draw (default 0)")
    parser.add_argument("--demo", action="store_true", help="add a straight-to-goal run")
    parser.add_argument("--out", type=Path, required=True, help="PNG file to write")
    parser.add_argument("--force", action="store_true", help="replace an existing --out file")
    return parser


def straight_to_goal(pw: PymunkWorld, scenario: Scenario) -> NDArray[np.float64]:
    """Positions (m, 2) of a naive run: turn to the goal, step up to ``step_max``, repeat.

    A turn sharper than 90 deg takes ``step_min``, so the arc does not swing wide.
    Stops inside the goal radius, at the last free sample before a collision, or when the
    scenario's time budget (one decision per control period) is spent.
    """
    profile = pw.profile
    pose = np.asarray(scenario.start, dtype=np.float64)
    goal = np.asarray(scenario.goal, dtype=np.float64)
    path = [pose[:2].copy()]
    budget = profile.time_budget(pose[:2], goal)
    for _ in range(math.ceil(budget / profile.control_period)):
        to_goal = goal - pose[:2]
        dist = float(np.hypot(*to_goal))
        if dist <= profile.goal_radius:
            break
        dtheta = float(wrap_angle(math.atan2(to_goal[1], to_goal[0]) - pose[2]))
        # a sharp turn takes the shortest step, so the arc does not swing wide
        reach = dist if abs(dtheta) <= 0.5 * math.pi else profile.step_min
        ds = float(np.clip(reach, profile.step_min, profile.step_max))
        n = int(sample_counts(dtheta, ds, profile))
        samples = arc_samples(pose[None, :], dtheta, ds, n)[0]
        hit = pw.swept_collision(pose, dtheta, ds, n_samples=n)
        path.extend(s[:2] for s in samples[1 : n + 1 if hit < 0 else hit])
        if hit >= 0:
            break
        pose = unicycle_arc(pose[None, :], dtheta, ds)[0]
    return np.array(path)


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        check_file("--out", args.out, [] if args.world is None else [args.world], args.force)
        profiles = load_profiles()
        if args.robot not in profiles:
            raise ValueError(f"unknown robot {args.robot!r} (known: {', '.join(profiles)})")
        profile = profiles[args.robot]
        if args.world is not None:
            world, scenarios = load_world_file(args.world)
            label = str(args.world)
        else:
            scenarios = _training_scenarios(profile, args.seed, args.walls)
            world, label = scenarios[0].world, f"{profile.name} training DoE, seed {args.seed}"
        index = args.scenario if args.scenario is not None else (0 if scenarios else None)
        if index is not None and not 0 <= index < len(scenarios):
            raise ValueError(f"scenario {index} does not exist ({len(scenarios)} scenarios)")
        fig = new_figure()
        ax = fig.add_subplot()
        if index is None:
            draw_world(ax, world, profile=profile)
        else:
            sc = scenarios[index]
            pw = PymunkWorld(world, profile)
            draw_world(
                ax,
                world,
                [sc],
                profile,
                pose=sc.start,
                rays=pw.ranges(sc.start),
                trajectory=straight_to_goal(pw, sc) if args.demo else None,
            )
            label += f", scenario {index}"
        ax.set_title(label, fontsize=9)
        save_png(fig, args.out)
    except (MentorError, ValueError, OSError) as err:
        return fail(PROG, f"error: {err}")
    return 0


def _training_scenarios(profile: RobotProfile, seed: int, walls: Sequence[int]) -> list[Scenario]:
    """The training DoE of ``seed`` with ``walls`` (min, max) long walls; a fault of the
    walls (more than fit in the arena) names ``--walls``."""
    try:
        return training_scenarios(profile, seed, cfg=DoEConfig(wall_count=(walls[0], walls[1])))
    except ConfigError as err:
        if err.key != "wall_count":
            raise
        raise MentorError(f"--walls {walls[0]} {walls[1]}: {err}") from None


if __name__ == "__main__":
    sys.exit(main())
