"""Probe: how much of a mapped planner's misses does the plan on its scan map decide?

    .venv/bin/python benchmarks/probes/plan_limit.py [GENOME ...] --robot swarm
        [--pairs-per-family 40] [--rotation-shim 45] [--aligned 0.4]

Every planner runs on its own scan map (``mentor-bench --set scan_map={}``: the carrot of a
plan on what its sensors have read, unknown space free) on the validation split, within 50 s:

* ``pursuit``: the plan followed as exactly as the action limits allow, with no reaction of
  its own (the oracle's rule on the carrot: a turn onto it with the smallest step while it
  lies more than ``--aligned`` rad off the heading, else the arc whose chord points at it);
* mapped VFH+ and mapped Bug2 within the shipped limits;
* each genome behind the rotation shim (``--rotation-shim``: a deployment with the scan map
  and ``stages.rotation_shim.threshold_deg``; 0: without), as recommended for the
  Swarm-Robot's planners.

Printed per planner: success, collisions and timeouts, per family; then the pairs that every
planner but the pursuit misses (the pursuit collides with what the map has not seen yet, so
it is left out of that count), per family. Those misses are the plan's, whatever follows it.
The test split is never touched.
"""

from __future__ import annotations

import argparse
from collections import Counter
from collections.abc import Sequence
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from mentor_core.benchmark.contenders import (
    Contender,
    PolicyMaker,
    evolved,
    hand_written,
    on_scan_map,
)
from mentor_core.benchmark.control import goal_polar, outputs_for
from mentor_core.benchmark.suite import build_suite, shipped_limits
from mentor_core.controller.deployment import load_deployment
from mentor_core.controller.episodes import run_episodes
from mentor_core.sim.episode import Policy
from mentor_core.sim.robots import RobotProfile, get_profile
from mentor_core.sim.world import Scenario

PAPER_LIMIT = 50.0
FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]


def pursuit(aligned: float) -> PolicyMaker:
    """The policy maker of the carrot pursuit (module docstring)."""

    def make(scenarios: Sequence[Scenario], profile: RobotProfile) -> Policy:
        h = profile.heading_change_max

        def policy(inputs: FloatArray, robots: IntArray) -> FloatArray:
            beta, _ = goal_polar(inputs, profile)
            turn = np.abs(beta) > aligned
            dtheta = np.where(turn, np.clip(beta, -h, h), 2.0 * beta)
            ds = np.where(turn, profile.step_min, profile.step_max)
            return outputs_for(dtheta, ds, profile)

        return policy

    return make


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("genomes", nargs="*")
    p.add_argument("--robot", default="swarm", choices=("ugv", "swarm"))
    p.add_argument("--pairs-per-family", type=int, default=40)
    p.add_argument("--rotation-shim", type=float, default=45.0, help="deg; 0: no shim")
    p.add_argument("--aligned", type=float, default=0.4, help="pursuit's turn threshold, rad")
    args = p.parse_args()
    robot = get_profile(args.robot)
    limits = shipped_limits(robot)
    suite = build_suite(robot, "validation", None, args.pairs_per_family)
    contenders = [Contender("pursuit", "baseline", limits, pursuit(args.aligned)),
                  hand_written("vfh", limits), hand_written("bug", limits)]  # fmt: skip
    settings = ["scan_map={}"]  # the plan's defaults, as for the baselines below
    if args.rotation_shim > 0:
        settings.append(f"stages.rotation_shim.threshold_deg={args.rotation_shim}")
    deployment, _ = load_deployment("none", robot.name, settings)
    plan = deployment.scan_map
    assert plan is not None
    mapped = [on_scan_map(c, plan.guide(c.profile)) for c in contenders]
    for g in args.genomes:  # named as before: mapped-[shim-]<run>
        name = ("shim-" if args.rotation_shim > 0 else "") + Path(g).parent.name
        mapped.append(evolved(g, robot, "mapped-" + name, deployment))
    families = [pair.family for pair in suite.pairs]
    fam = np.asarray(families)
    scenarios = [pair.scenario for pair in suite.pairs]
    missed: dict[str, set[int]] = {}
    for c in mapped:
        batch = run_episodes(scenarios, c.profile, c.policy(scenarios), time_budgets=PAPER_LIMIT,
                             input_goals=c.input_goals(scenarios), stages=c.stages)  # fmt: skip
        missed[c.name] = set(np.flatnonzero(~batch.reached).tolist())
        per = " ".join(f"{f[:8]}={100 * batch.reached[fam == f].mean():.0f}"
                       for f in suite.families)  # fmt: skip
        rates = [100 * x.mean() for x in (batch.reached, batch.collided, batch.timed_out)]
        print(f"{c.name:<28} success {rates[0]:5.1f} %, collisions {rates[1]:4.1f} %, "
              f"timeouts {rates[2]:4.1f} %  {per}", flush=True)  # fmt: skip
    others = [v for k, v in missed.items() if not k.endswith("pursuit")]
    common = set.intersection(*others) if others else set()
    print(f"missed by every planner but the pursuit: {len(common)} of {len(families)} pairs "
          f"({100 * len(common) / len(families):.1f} %): "
          f"{dict(Counter(families[i] for i in sorted(common)))}")  # fmt: skip


if __name__ == "__main__":
    main()
