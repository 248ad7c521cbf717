"""One training setting changed at a time: what it does to training and unseen success.

    export NUMBA_CACHE_DIR=.venv/numba-cache
    .venv/bin/python benchmarks/probes/ablation.py --robot swarm --seed 1 \\
        --set input_encoding=paper --set heading_change_max_deg=180 \\
        --set evolution.speciation.assignment=first [--profile step_max=1.0] [--out DIR]

Trains one run with the shipped paper-scale config (``--framework``, default single) and the
``--set KEY=VALUE`` overrides (dotted keys into the trainer config, YAML values), then
evaluates its best genome on its own training scenarios (their time budgets) and on
``bags/unseen/<robot>`` (mentor-eval's test: 50 s, goal radius). ``--profile FIELD=VALUE``
replaces a field of the robot profile, outside the trainer config (``step_max=1.0``,
``beam_width_deg=30 --profile beam_rays=5``). ``--heldout N`` (default 100) also tests it,
with the same 50 s test, on scenarios no run trains or is tested on otherwise: N pairs in 4
DoE worlds of seed 999 (``heldout_*``) and N / 2 pairs in a walled layout unlike the DoE's
boxes and the unseen S-corridor (``walls_*``); choose settings on these, not on the 10 unseen
pairs. Prints one JSON object.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import math
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np
import yaml

from mentor_core.cli.train import resolve_config
from mentor_core.controller.turn_commitment import TurnCommitment
from mentor_core.files.bags import read_scenario_bag
from mentor_core.sim.robots import RobotProfile, get_profile
from mentor_core.sim.scenarios import sample_scenarios, training_scenarios
from mentor_core.sim.world import Scenario, World
from mentor_core.training.assessment import assess
from mentor_core.training.config import TrainerConfig
from mentor_core.training.evaluators import InProcessEvaluator
from mentor_core.training.trainer import make_problem, train

ROOT = Path(__file__).resolve().parents[2]
HELDOUT_SEED = 999  # training DoEs use the config's scenario seed (0); this one no run sees
# a walled layout unlike both the DoE's boxes and the unseen S-corridor, (xmin, ymin, xmax,
# ymax) on a 12 x 12 m drawing, scaled to the robot's test arena
HELDOUT_WALLS_12M = (
    (1.5, 6.0, 6.0, 6.3),
    (8.0, 2.0, 8.3, 9.0),
    (3.0, 9.5, 10.0, 9.8),
    (3.0, 2.5, 6.5, 2.8),
    (4.5, 3.8, 4.8, 5.0),
    (10.0, 4.0, 10.6, 4.6),
    (1.5, 8.0, 2.1, 8.6),
)


def heldout_walls(profile: RobotProfile, n: int) -> list[Scenario]:
    """``n`` start/goal pairs (seed 999, at least a quarter of the arena apart, as the unseen
    bags' pairs) in the walled held-out layout at the robot's test-arena size."""
    size = profile.test_arena
    boxes = np.asarray(HELDOUT_WALLS_12M, dtype=np.float64) * (size / 12.0)
    world = World(size, boxes, name=f"{profile.name}-heldout-walls")
    rng = np.random.default_rng(HELDOUT_SEED)
    return sample_scenarios(world, profile, n, rng, min_distance=size / 4)


def apply(config: dict[str, Any], assignment: str) -> None:
    """Set ``a.b.c=value`` (value parsed as YAML) in a nested config dict."""
    key, _, text = assignment.partition("=")
    *path, last = key.split(".")
    node = config
    for part in path:
        node = node.setdefault(part, {})
    node[last] = yaml.safe_load(text)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--robot", choices=("ugv", "swarm"), required=True)
    p.add_argument("--framework", choices=("single", "dual"), default="single")
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--set", action="append", default=[], help="KEY=VALUE config override")
    p.add_argument(
        "--profile", action="append", default=[], metavar="FIELD=VALUE",
        help="replace a robot profile field, e.g. step_max=1.0 (a FIELD_deg in degrees)",
    )  # fmt: skip
    p.add_argument("--robots", type=Path, help="robot file to take the profile from")
    p.add_argument("--unseen", help="robot whose unseen bag to test on (default: --robot)")
    p.add_argument("--out", type=Path, help="run directory (default: a temporary one)")
    p.add_argument(
        "--heldout", type=int, default=100, metavar="N",
        help="also test on N pairs in 4 held-out DoE worlds and N/2 in a held-out walled "
             "layout (seed 999; 0: skip)",
    )  # fmt: skip
    args = p.parse_args()

    data = resolve_config(args.robot, args.framework, "paper").to_dict()
    for assignment in args.set:
        apply(data, assignment)
    config = TrainerConfig.from_dict(data, source="--set")
    profile = get_profile(args.robot, args.robots)
    for assignment in args.profile:
        name, _, text = assignment.partition("=")
        value = yaml.safe_load(text)
        if name.endswith("_deg"):
            name, value = name.removesuffix("_deg"), math.radians(value)
        profile = dataclasses.replace(profile, **{name: value})
    problem = make_problem(config, profile)
    start = time.perf_counter()
    with tempfile.TemporaryDirectory() as tmp:
        result = train(
            config, args.out or Path(tmp) / "run", seed=args.seed,
            evaluator=InProcessEvaluator(problem), profile=profile,
        )  # fmt: skip
    best = result.best_genome
    _, scenarios, _, _ = read_scenario_bag(ROOT / "bags" / "unseen" / (args.unseen or args.robot))
    own = problem.evaluate([best])  # the training episodes, with their time budgets
    # tested as mentor-eval runs it: the stages its metadata names (its view corridor and
    # rotation shim; a turn commitment is training's alone)
    stages = tuple(s for s in problem.stages if s.name != TurnCommitment.name)
    unseen = assess(best, problem.profile, scenarios, stages=stages)
    heldout = walls = None
    if args.heldout:
        doe = training_scenarios(problem.profile, HELDOUT_SEED, n=args.heldout, worlds=4)
        heldout = assess(best, problem.profile, doe, stages=stages)
        walls = assess(best, problem.profile, heldout_walls(problem.profile, args.heldout // 2),
                       stages=stages)  # fmt: skip
    print(json.dumps({
        "robot": args.robot, "framework": args.framework, "seed": args.seed,
        "set": args.set, "profile": args.profile,
        "training_success": float(own.success_rate[0]),
        "training_collisions": float(own.collision_rate[0]),
        "unseen_reached": sum(r.reached for r in unseen.results),
        "unseen_collided": sum(r.collided for r in unseen.results),
        "heldout_success": None if heldout is None else heldout.success_rate,
        "heldout_collisions": None if heldout is None else heldout.collision_rate,
        "walls_success": None if walls is None else walls.success_rate,
        "walls_collisions": None if walls is None else walls.collision_rate,
        "hidden_nodes": len(best.hidden_nodes),
        "seconds": round(time.perf_counter() - start, 1),
    }))  # fmt: skip


if __name__ == "__main__":
    main()
