"""Probe: evolved planners under a rule on their turns, or with Bug's memory as their recovery.

    .venv/bin/python benchmarks/probes/turn_commitment.py GENOME [GENOME ...] [--robot ugv]
        [--split validation] [--pairs-per-family 20] [--rule commit|goal_frame|bug]

The UGV planners' collisions on the benchmark end in alternating +-45 deg turns at the smallest
step while the way ahead is blocked (experiment E023, "Better planners"). This wraps
each genome's policy, at evaluation time only, with a Bug-like commitment: while the clearance
limit holds the step at its smallest (``observation.clearance_limit`` of the chosen turn is
``step_min``), a turn to the other side than the previous decision's is mirrored to the
previous side (same magnitude). Prints success / collisions / timeouts (50 s) per family and
overall for each genome, plain and committed. A probe of the hypothesis, not a planner: the
genomes were trained without the rule. ``--rule goal_frame`` instead reads the turn output as
a heading relative to the goal (``mentor_core.sim.goal_frame``): the "+goal_frame" line is
the one for genomes trained with ``turn_frame: goal``; the commitment's "+commit" line is the
one for genomes trained with ``turn_commitment: true``. ``--rule bug`` runs the genome as the
**to goal** controller of the Bug baseline (``bug_policy(..., driver=...)``: the network
drives until Bug's hit rule fires, Bug follows the obstacle until its leaving rule fires),
with a line for Bug alone at the genome's limits: Bug's memory as the planner's recovery.
"""

from __future__ import annotations

import argparse
import dataclasses
from collections.abc import Sequence

from mentor_core.benchmark.bug import bug_policy
from mentor_core.benchmark.contenders import Contender, PolicyMaker, evolved
from mentor_core.benchmark.runner import run_contender
from mentor_core.benchmark.suite import build_suite
from mentor_core.controller.turn_commitment import TurnCommitment
from mentor_core.sim.episode import FloatArray, IntArray, Policy
from mentor_core.sim.goal_frame import goal_frame_turns
from mentor_core.sim.robots import RobotProfile, get_profile
from mentor_core.sim.world import Scenario


def renamed(contender: Contender, suffix: str, make: PolicyMaker) -> Contender:
    """``contender`` named ``<name><suffix>`` deciding with the policies of ``make``, its
    stages (those it was trained with) kept."""
    return dataclasses.replace(contender, name=contender.name + suffix, make_policy=make)


def committed(contender: Contender) -> Contender:
    """``contender`` with the turn commitment (``mentor_core.controller.turn_commitment``) on
    its network's outputs, before its stages."""

    def make(scenarios: Sequence[Scenario], profile: RobotProfile) -> Policy:
        base = contender.policy(scenarios)
        rule = TurnCommitment().start(len(scenarios), profile, None)

        def policy(inputs: FloatArray, robots: IntArray) -> FloatArray:
            return rule.outputs(robots, base(inputs, robots), inputs)

        return policy

    return renamed(contender, "+commit", make)


def goal_framed(contender: Contender) -> Contender:
    """``contender`` with turns relative to the goal (``mentor_core.sim.goal_frame``), for
    genomes trained with ``turn_frame: goal``."""

    def make(scenarios: Sequence[Scenario], profile: RobotProfile) -> Policy:
        base = contender.policy(scenarios)

        def policy(inputs: FloatArray, robots: IntArray) -> FloatArray:
            return goal_frame_turns(base(inputs, robots), inputs, profile)

        return policy

    return renamed(contender, "+goal_frame", make)


def with_bug_recovery(contender: Contender) -> Contender:
    """``contender`` driving the Bug baseline's **to goal** mode (module docstring)."""

    def make(scenarios: Sequence[Scenario], profile: RobotProfile) -> Policy:
        return bug_policy(scenarios, profile, driver=contender.policy(scenarios))

    return renamed(contender, "+bug", make)


RULES = {"commit": committed, "goal_frame": goal_framed, "bug": with_bug_recovery}


def main() -> None:
    """Run the probe and print a line per genome and variant."""
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("genomes", nargs="+")
    p.add_argument("--robot", default="ugv")
    p.add_argument("--split", default="validation")
    p.add_argument("--pairs-per-family", type=int, default=20)
    p.add_argument("--rule", choices=sorted(RULES), default="commit")
    args = p.parse_args()
    robot = get_profile(args.robot)
    suite = build_suite(robot, args.split, pairs_per_family=args.pairs_per_family)
    for i, path in enumerate(args.genomes):
        plain = evolved(path, robot)
        variants = [plain, RULES[args.rule](plain)]
        if args.rule == "bug" and i == 0:
            variants.append(Contender("bug", "baseline", plain.profile, bug_policy,
                                      stages=plain.stages))  # fmt: skip
        for c in variants:
            scores = run_contender(suite, c).scores["paper"]
            cells = [f"{f} {100 * s['success']:.0f}" for f, s in scores.items() if f != "overall"]
            o = scores["overall"]
            print(f"{c.name}: success {100 * o['success']:.0f} % collisions "
                  f"{100 * o['collision']:.0f} % timeouts {100 * o['timeout']:.0f} % SPL "
                  f"{o['spl']:.2f} | {' '.join(cells)}", flush=True)  # fmt: skip


if __name__ == "__main__":
    main()
