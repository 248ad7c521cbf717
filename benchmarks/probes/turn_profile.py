"""Probe: how a deployed planner turns, beside mapped guarded Bug2, on one family's pairs.

    .venv/bin/python benchmarks/probes/turn_profile.py GENOME [GENOME ...] --robot ugv \
        --family forest_sparse --split validation --pairs 40

Each genome runs as ``mentor-bench --deployment shipped`` runs it (its robot's shipped
deployment: its scan map, the rotation shim, the collision guard, its robot's decision period,
gain on the turn and view corridor); Bug2 on its scan map behind the guard, as that
deployment's ``mapped-guard-bug``, at the shipped planners' action limits. For each: success
within 50 s, the path over the shortest path on the pairs every planner reaches (mean and
median), and the heading change per decision along the successful runs (median, and the share
at 40 deg or more, near the +-45 deg limit). A planner that swings its full turn at most
decisions zig-zags; a proportional one turns a little at most. For the evolved planners it also
reports how the network's turns split by whether anything is read near (within 2 m, or for a
robot whose sensors reach less, anything read at all): the share of decisions with a reading
that near, the share of full turns with and without one, and where nothing is that near, the
slope of the turn over the bearing of the goal the network sees (bearings within 30 deg; 1
turns onto the carrot in one decision, 2 overshoots it by as much).
experiment E061, "Where the UGV's full turns come from" (2026-12-04).
"""

from __future__ import annotations

import argparse
import dataclasses
import math
from collections.abc import Sequence

import numpy as np

from mentor_core import MentorError, get_profile
from mentor_core.benchmark.contenders import (
    Contender,
    behind_collision_guard,
    evolved,
    hand_written,
    on_scan_map,
)
from mentor_core.benchmark.runner import run_family
from mentor_core.benchmark.scores import under_limit
from mentor_core.benchmark.suite import PAPER_LIMIT, build_suite, shipped_limits
from mentor_core.controller.collision_guard import CollisionGuardStage
from mentor_core.controller.deployment import load_deployment
from mentor_core.sim.observation import ranges_from_inputs
from mentor_core.sim.robots import RobotProfile

FULL_TURN_DEG = 40.0


def recorded(contender: Contender, log: list[tuple[np.ndarray, np.ndarray]]) -> Contender:
    """``contender`` whose policy appends each decision's ``(inputs, outputs)`` to ``log``."""
    make = contender.make_policy

    def make_recorded(scenarios, profile):  # type: ignore[no-untyped-def]
        policy = make(scenarios, profile)

        def decide(inputs, idx):  # type: ignore[no-untyped-def]
            out = np.asarray(policy(inputs, idx), dtype=np.float64).reshape(len(idx), -1)
            log.append((np.array(inputs, dtype=np.float64), out.copy()))
            return out

        return decide

    return dataclasses.replace(contender, make_policy=make_recorded)


def heading_changes(trajectories: Sequence[np.ndarray], ok: np.ndarray) -> np.ndarray:
    """|heading change| per decision (deg) along the successful runs."""
    parts = []
    for t, success in zip(trajectories, ok, strict=True):
        if success and len(t) > 1:
            d = np.diff(t[:, 2])
            parts.append(np.abs(np.degrees((d + math.pi) % (2 * math.pi) - math.pi)))
    return np.concatenate(parts) if parts else np.zeros(0)


def near_range(profile: RobotProfile) -> float:
    """What counts as near, m: 2 m, or just under the sensors' range where they reach less
    (the Swarm-Robot's 0.6 m), so that "near" means anything read at all."""
    return min(2.0, 0.99 * profile.sensor_range)


def network_turns(log: list[tuple[np.ndarray, np.ndarray]],
                  profile: RobotProfile) -> tuple[float, float, float, float]:  # fmt: skip
    """Over the logged decisions: the share with a reading near (:func:`near_range`); the
    share of full turns among those and among the others; the slope of the network's turn
    over the goal's bearing (within 30 deg) where nothing is read that near."""
    x = np.concatenate([i for i, _ in log])
    o = np.concatenate([out for _, out in log])
    k = profile.n_sensors
    bearing = np.degrees(np.arctan2(x[:, k + 1], x[:, k]))
    turn = math.degrees(profile.heading_change_max) * (2.0 * np.clip(o[:, 0], 0.0, 1.0) - 1.0)
    near = ranges_from_inputs(x, profile).min(axis=1) < near_range(profile)  # m, any encoding
    full = np.abs(turn) >= FULL_TURN_DEG
    small = (np.abs(bearing) <= 30.0) & ~near
    slope = float(np.polyfit(bearing[small], turn[small], 1)[0]) if small.sum() > 2 else math.nan
    open_full = float(np.mean(full[~near])) if (~near).any() else math.nan
    return float(np.mean(near)), float(np.mean(full[near])), open_full, slope


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("genomes", nargs="+")
    p.add_argument("--robot", default="ugv")
    p.add_argument("--family", default="forest_sparse")
    p.add_argument("--split", default="validation", choices=("validation", "test"))
    p.add_argument("--pairs", type=int, default=40)
    args = p.parse_args()
    try:
        robot = get_profile(args.robot)
        suite = build_suite(robot, args.split, [args.family], args.pairs)
        shipped, _ = load_deployment("shipped", robot.name)
        [guard] = [s for s in shipped.build() if isinstance(s, CollisionGuardStage)]
        assert shipped.scan_map is not None
        guarded = behind_collision_guard(hand_written("bug", shipped_limits(robot)), guard)
        bug = on_scan_map(guarded, shipped.scan_map.guide(guarded.profile))
        logs: dict[str, list[tuple[np.ndarray, np.ndarray]]] = {}
        planners: dict[str, Contender] = {"mapped guarded Bug2": bug}
        for path in args.genomes:
            logs[path] = []
            planners[path] = recorded(evolved(path, robot, path, shipped), logs[path])
    except (MentorError, ValueError) as err:
        p.exit(1, f"turn_profile.py: {err}\n")
    shortest = np.array([pair.shortest for pair in suite.pairs])
    limits = np.full(len(shortest), PAPER_LIMIT)
    runs = {name: run_family(suite, c, args.family) for name, c in planners.items()}
    ok = {name: under_limit(r, limits, planners[name].profile.control_period)[0]
          for name, r in runs.items()}  # fmt: skip
    common = np.logical_and.reduce(list(ok.values()))
    print(f"{args.family}, {args.split}, {len(shortest)} pairs; {common.sum()} reached by all")
    for name, r in runs.items():
        ratio = r.path_length[common] / shortest[common]
        turns = heading_changes(r.trajectories, ok[name])
        line = (f"{name}: success {100 * ok[name].mean():.1f} %; path / shortest "
                f"{ratio.mean():.3f} (median {np.median(ratio):.3f}); |heading change| "
                f"median {np.median(turns):.1f} deg, {100 * np.mean(turns >= FULL_TURN_DEG):.0f} "
                f"% at {FULL_TURN_DEG:g} deg or more")  # fmt: skip
        if name in logs:
            profile = planners[name].profile
            near, full_near, full_open, slope = network_turns(logs[name], profile)
            line += (f"; network: {100 * near:.0f} % of decisions with a reading within "
                     f"{near_range(profile):.2g} m, "
                     f"full turns at {100 * full_near:.0f} % of those and {100 * full_open:.0f} "
                     f"% of the others; turn / bearing in the open {slope:.2f}")  # fmt: skip
        print(line, flush=True)


if __name__ == "__main__":
    main()
