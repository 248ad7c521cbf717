"""Write ``bags/unseen/{ugv,swarm}``: the unseen test environments (paper section IV-D).

    .venv/bin/python scripts/make_unseen_bags.py [--out bags/unseen] [--overwrite]

One hand-drawn layout, unlike the training design of experiments (random boxes in four grid
cells): two long walls that turn the arena into an S-shaped corridor, a short free-standing
wall and a few pillars. The UGV gets it at 12 x 12 m, the Swarm-Robot the same drawing
scaled to 4 x 4 m.
Ten start/goal pairs per robot are drawn in free space from a fixed seed with the trainer's
clearance rule, between a quarter of the arena side and the distance the 50 s test limit
allows. The script is deterministic: running it again gives the same scenarios.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

from mentor_core.files.bags import write_scenario_bag
from mentor_core.sim.robots import get_profile
from mentor_core.sim.scenarios import sample_scenarios
from mentor_core.sim.world import World

# (xmin, ymin, xmax, ymax) on a 12 x 12 m drawing
LAYOUT_12M = (
    (0.0, 3.9, 7.5, 4.2),  # lower wall, open on the right
    (4.5, 7.8, 12.0, 8.1),  # upper wall, open on the left
    (9.6, 4.6, 9.9, 6.4),  # short free-standing wall in the middle corridor
    (2.0, 1.5, 2.8, 2.3),  # pillars
    (9.0, 1.2, 9.8, 2.0),
    (2.5, 5.8, 3.3, 6.6),
    (6.0, 5.6, 6.6, 6.2),
    (2.0, 9.8, 2.8, 10.6),
    (7.5, 10.0, 8.5, 10.6),
)
SEEDS = {"ugv": 2026, "swarm": 2027}
N_PAIRS = 10


def unseen_world(robot: str) -> World:
    """The unseen layout scaled to the robot's test arena."""
    profile = get_profile(robot)
    scale = profile.test_arena / 12.0
    boxes = np.asarray(LAYOUT_12M, dtype=np.float64) * scale
    return World(profile.test_arena, boxes, name=f"{robot}-unseen")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, default=Path("bags/unseen"))
    parser.add_argument("--overwrite", action="store_true")
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    for robot, seed in SEEDS.items():
        profile = get_profile(robot)
        world = unseen_world(robot)
        scenarios = sample_scenarios(
            world, profile, N_PAIRS, np.random.default_rng(seed), min_distance=world.size / 4
        )
        meta = {
            "description": "unseen test environment: S-shaped corridor with pillars",
            "generator": "scripts/make_unseen_bags.py",
            "seed": seed,
        }
        path = args.out / robot
        write_scenario_bag(path, world, scenarios, robot, meta, overwrite=args.overwrite)
        print(f"{path}: {len(scenarios)} start/goal pairs in a {world.size:g} m arena")
    return 0


if __name__ == "__main__":
    sys.exit(main())
