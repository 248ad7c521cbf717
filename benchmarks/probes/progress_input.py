"""Experiment: a ready-made memory input, the goal distance against the least one so far.

    .venv/bin/python benchmarks/probes/progress_input.py train CONFIG --seed S --out RUN_DIR
    .venv/bin/python benchmarks/probes/progress_input.py score GENOME [GENOME ...] [--robot ugv]
        [--split validation] [--pairs-per-family 20]

DistBug leaves an obstacle once it can get nearer to the goal than it has been since it met
it; a reactive planner has no such memory, and NEAT does not evolve one from its memory units
(experiment E023, "Better planners", "The way round"). Here the network gets it
ready-made: the config must set ``feedback_action: true`` (and the egocentric inputs); the
second fed-back slot (the previous step output) is replaced by ``P = S / S_max``, the goal
signal ``S = R / max(d, R)`` over the largest one of the episode so far, i.e. ``d_min / d``:
1 while the robot is as near as it has ever been, less when it has had to move away. The
first slot stays the previous turn output. ``train`` trains with it (in process), ``score``
runs genomes trained so on the benchmark with it. An experiment, not a planner setting: a
genome trained here runs as intended only through this script.
"""

from __future__ import annotations

import argparse
import dataclasses
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from mentor_core.benchmark.contenders import Contender, evolved
from mentor_core.benchmark.runner import run_contender
from mentor_core.benchmark.suite import build_suite
from mentor_core.controller.episodes import run_episodes
from mentor_core.controller.turn_commitment import TurnCommitment
from mentor_core.evolution.batch_network import BatchNetwork
from mentor_core.evolution.genome import Genome
from mentor_core.sim.episode import EpisodeBatch, FloatArray, IntArray, Policy
from mentor_core.sim.robots import RobotProfile, get_profile
from mentor_core.sim.world import Scenario
from mentor_core.training.config import load_config_file
from mentor_core.training.evaluators import InProcessEvaluator
from mentor_core.training.problem import NavigationProblem
from mentor_core.training.trainer import make_problem, train


class Progress:
    """``S_max`` per robot; :meth:`__call__` writes ``P`` into the inputs (a copy)."""

    def __init__(self, profile: RobotProfile, n_robots: int) -> None:
        if not profile.feedback_action or profile.input_encoding != "egocentric":
            raise SystemExit("progress_input: the config needs feedback_action: true and "
                             "input_encoding: egocentric")  # fmt: skip
        self.k = profile.n_sensors
        self.best = np.zeros(n_robots)

    def __call__(self, inputs: FloatArray, robots: IntArray) -> FloatArray:
        x = np.array(inputs, dtype=np.float64, copy=True)
        signal = x[:, self.k + 2]
        self.best[robots] = np.maximum(self.best[robots], signal)
        x[:, self.k + 4] = signal / self.best[robots]
        return x


class ProgressProblem(NavigationProblem):
    """The training problem with the progress input (module docstring)."""

    def simulate(self, genomes: Sequence[Genome]) -> EpisodeBatch:
        n_scen = len(self.scenarios)
        network = BatchNetwork.from_genomes(genomes)
        progress = Progress(self.profile, n_scen * len(genomes))

        def policy(inputs: FloatArray, robots: IntArray) -> FloatArray:
            return network.activate(progress(inputs, robots), robots // n_scen)

        budgets = self.time_budget
        return run_episodes(list(self.scenarios) * len(genomes), self.profile, policy,
                            time_budgets=budgets, stages=self.stages)  # fmt: skip


def with_progress(contender: Contender) -> Contender:
    """``contender`` fed the progress input."""

    def make(scenarios: Sequence[Scenario], profile: RobotProfile) -> Policy:
        base = contender.policy(scenarios)
        progress = Progress(profile, len(scenarios))
        return lambda inputs, robots: base(progress(inputs, robots), robots)

    return dataclasses.replace(contender, name=contender.name + "+progress", make_policy=make)


def main() -> None:
    """Train or score (module docstring)."""
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("command", choices=["train", "score"])
    p.add_argument("paths", nargs="+")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--out", type=Path)
    p.add_argument("--robot", default="ugv")
    p.add_argument("--split", default="validation")
    p.add_argument("--pairs-per-family", type=int, default=20)
    args = p.parse_args()
    if args.command == "train":
        config, _ = load_config_file(args.paths[0])
        base = make_problem(config, source=args.paths[0])
        # the config's view corridor and rotation shim; its turn commitment never ran here
        stages = [s for s in base.stages if s.name != TurnCommitment.name]
        problem = ProgressProblem(base.profile, base.scenarios, time_budget=base.time_budget,
                                  stages=stages)  # fmt: skip
        result = train(config, args.out, seed=args.seed, evaluator=InProcessEvaluator(problem))
        print(f"best F {result.best_objectives[0]:.3f}; {result.paths.root}")
        return
    robot = get_profile(args.robot)
    suite = build_suite(robot, args.split, pairs_per_family=args.pairs_per_family)
    for path in args.paths:
        c = with_progress(evolved(path, robot))
        o = run_contender(suite, c).scores["paper"]["overall"]
        print(f"{c.name}: success {100 * o['success']:.0f} % collisions "
              f"{100 * o['collision']:.0f} % timeouts {100 * o['timeout']:.0f} % SPL "
              f"{o['spl']:.2f}", flush=True)  # fmt: skip


if __name__ == "__main__":
    main()
