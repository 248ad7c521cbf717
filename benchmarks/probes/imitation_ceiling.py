"""Probe: how far can a planner without memory get on the evolved planners' own inputs?

    .venv/bin/python benchmarks/probes/imitation_ceiling.py --robot ugv --out DIR
        [--seeds 0 1 2 3 4] [--family-pairs 5] [--rounds 8] [--hidden 64 64]

The evolved planners stop at 60-66 % (UGV) and about 80 % (Swarm-Robot) of the benchmark's
validation pairs, whatever the search is given (experiment E028). Is that NEAT's
search, or what any reactive planner can do with these inputs? This trains a reactive
planner another way, by imitation, and scores it on the same pairs.

DAgger (Ross, Gordon and Bagnell 2011): an expert that knows the world labels every state the
learner visits with its own action, a multilayer perceptron learns inputs -> outputs on all
the labels so far, and the learner drives the next round (the first round the expert drives).
The expert heads where the shortest way from the robot's position goes first
(``GoalDistance.waypoints``, for a disc of ``--margin`` half body diagonals, the body's own
half diagonal where that is not free), turning on the spot while the way lies more than half
a heading limit off, else driving the arc whose chord points at it. The learner sees exactly
what an evolved network sees (the training config's inputs, outputs, action mapping and
clearance rule), has no memory, and learns on the shipped config's training problem for
several scenario seeds plus structured-family worlds of the curriculum (whose seeds never
meet the benchmark's). Each round's learner is scored on the validation split; the test split
is never touched.

The learner is an upper-bound probe, not a planner: it is no NEAT genome, and imitation
averages the expert's actions over states that look alike (a memoryless learner cannot tell
them apart: the aliasing the evolved planners also face).
"""

from __future__ import annotations

import argparse
import dataclasses
import itertools
import json
import time
from collections.abc import Sequence
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from mentor_core.benchmark.contenders import Contender
from mentor_core.benchmark.control import Odometry, outputs_for
from mentor_core.benchmark.runner import run_contender
from mentor_core.benchmark.suite import build_suite
from mentor_core.controller.episodes import run_episodes
from mentor_core.controller.stage import Stage
from mentor_core.controller.turn_commitment import TurnCommitment
from mentor_core.navigation.goal_distance import GoalDistance
from mentor_core.navigation.shortest_path import VisibilityGraph
from mentor_core.sim.episode import Policy
from mentor_core.sim.families import FAMILIES
from mentor_core.sim.kinematics import wrap_angle
from mentor_core.sim.robots import RobotProfile, get_profile
from mentor_core.sim.world import Scenario
from mentor_core.training.config import load_config_file
from mentor_core.training.trainer import make_problem

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
CONFIGS = Path(__file__).resolve().parents[2] / "mentor_core/src/mentor_core/configs"
PAPER_LIMIT = 50.0  # s, the benchmark's and the training config's budget


class Expert:
    """The cost-to-go expert of the module docstring for robot ``i`` on ``scenarios[i]``."""

    def __init__(self, scenarios: Sequence[Scenario], profile: RobotProfile, margin: float):
        graphs: dict[int, tuple[VisibilityGraph, VisibilityGraph]] = {}
        self.ways: list[tuple[GoalDistance, GoalDistance]] = []
        hd = profile.half_diagonal
        for sc in scenarios:
            if id(sc.world) not in graphs:
                graphs[id(sc.world)] = (VisibilityGraph(sc.world, margin * hd),
                                        VisibilityGraph(sc.world, hd))  # fmt: skip
            wide, tight = graphs[id(sc.world)]
            self.ways.append((GoalDistance(wide, sc.goal, profile.goal_radius),
                              GoalDistance(tight, sc.goal, profile.goal_radius)))  # fmt: skip
        self.goals = np.array([sc.goal[:2] for sc in scenarios], dtype=np.float64)
        self.profile = profile

    def outputs(self, poses: FloatArray, robots: IntArray) -> FloatArray:
        """The expert's network outputs ``(m, n_outputs)`` at ``poses`` (true, map frame)."""
        target = np.empty((len(robots), 2))
        for row, r in enumerate(robots.tolist()):
            way = np.full(2, np.nan)
            for goal_distance in self.ways[r]:
                way = goal_distance.waypoints(poses[row, None, :2])[0]
                if np.isfinite(way).all():
                    break
            if not np.isfinite(way).all() or np.hypot(*(way - poses[row, :2])) < 1e-6:
                way = self.goals[r]  # inside an obstacle's margin, or on the corner itself
            target[row] = way
        h, p = self.profile.heading_change_max, self.profile
        delta = target - poses[:, :2]
        alpha = wrap_angle(np.arctan2(delta[:, 1], delta[:, 0]) - poses[:, 2])
        turning = np.abs(alpha) > 0.5 * h
        # on the spot at the smallest step, or the full step on the arc whose chord points
        # at the waypoint (its end heading turns by twice the bearing)
        dtheta = np.where(turning, np.clip(alpha, -h, h), 2.0 * alpha)
        return outputs_for(dtheta, np.where(turning, p.step_min, p.step_max), p)


class Perceptron:
    """Two tanh layers (or as many as ``hidden`` names) and sigmoid outputs, trained with Adam
    on the mean squared error; inputs standardised with the training data's mean and sd."""

    def __init__(self, n_in: int, n_out: int, hidden: Sequence[int], seed: int) -> None:
        rng = np.random.default_rng(seed)
        sizes = [n_in, *hidden, n_out]
        self.w = [rng.normal(0.0, 1.0 / np.sqrt(a), (a, b)) for a, b in itertools.pairwise(sizes)]
        self.b = [np.zeros(b) for b in sizes[1:]]
        self.mean, self.sd = np.zeros(n_in), np.ones(n_in)
        self.rng = rng

    def __call__(self, x: FloatArray) -> FloatArray:
        return self._forward((x - self.mean) / self.sd)[-1]

    def _forward(self, z: FloatArray) -> list[FloatArray]:
        acts = [z]
        for i, (w, b) in enumerate(zip(self.w, self.b, strict=True)):
            a = acts[-1] @ w + b
            acts.append(np.tanh(a) if i < len(self.w) - 1 else 1.0 / (1.0 + np.exp(-a)))
        return acts

    def fit(self, x: FloatArray, y: FloatArray, epochs: int, batch: int = 256,
            rate: float = 1e-3) -> float:  # fmt: skip
        """Train on ``(x, y)``; the final mean squared error."""
        self.mean, self.sd = x.mean(axis=0), x.std(axis=0) + 1e-9
        z = (x - self.mean) / self.sd
        params = self.w + self.b
        m1 = [np.zeros_like(q) for q in params]
        m2 = [np.zeros_like(q) for q in params]
        step = 0
        for _ in range(epochs):
            order = self.rng.permutation(len(z))
            for s in range(0, len(z), batch):
                idx = order[s : s + batch]
                acts = self._forward(z[idx])
                out = acts[-1]
                grad = 2.0 * (out - y[idx]) / len(idx) * out * (1.0 - out)
                gw: list[FloatArray] = []
                gb: list[FloatArray] = []
                for i in range(len(self.w) - 1, -1, -1):
                    gw.insert(0, acts[i].T @ grad)
                    gb.insert(0, grad.sum(axis=0))
                    if i:
                        grad = (grad @ self.w[i].T) * (1.0 - acts[i] ** 2)
                step += 1
                for q, g, a, v in zip(params, gw + gb, m1, m2, strict=True):
                    a *= 0.9
                    a += 0.1 * g
                    v *= 0.999
                    v += 0.001 * g * g
                    q -= rate * (a / (1 - 0.9**step)) / (np.sqrt(v / (1 - 0.999**step)) + 1e-8)
        return float(np.mean((self(x) - y) ** 2))


class History:
    """A learner's inputs with ``steps`` decisions of history (``--history``): the inputs of
    the previous ``steps`` decisions and the outputs taken then (zero outputs and the first
    inputs before the first decision), per robot."""

    def __init__(self, n_robots: int, n_inputs: int, n_outputs: int, steps: int) -> None:
        self.steps = steps
        self.inputs = np.full((steps, n_robots, n_inputs), np.nan)
        self.outputs = np.zeros((steps, n_robots, n_outputs))

    def features(self, inputs: FloatArray, robots: IntArray) -> FloatArray:
        """The learner's input rows for ``robots`` seeing ``inputs`` now."""
        if not self.steps:
            return inputs
        past = self.inputs[:, robots]
        past = np.where(np.isnan(past), inputs[None], past)
        return np.concatenate([inputs, *past, *self.outputs[:, robots]], axis=1)

    def update(self, robots: IntArray, inputs: FloatArray, outputs: FloatArray) -> None:
        """Remember this decision's inputs and outputs."""
        if self.steps:
            self.inputs[:, robots] = np.roll(self.inputs[:, robots], 1, axis=0)
            self.outputs[:, robots] = np.roll(self.outputs[:, robots], 1, axis=0)
            self.inputs[0, robots] = inputs
            self.outputs[0, robots] = outputs


def rollout(
    scenarios: Sequence[Scenario], profile: RobotProfile, expert: Expert,
    learner: Perceptron | None, steps: int, stages: Sequence[Stage] = (),
) -> tuple[FloatArray, FloatArray, float]:  # fmt: skip
    """Drive every scenario (the expert when ``learner`` is None) through the training
    problem's ``stages``; the inputs seen, the expert's outputs there, and the share of goals
    reached."""
    odometry = Odometry([sc.start for sc in scenarios])
    history = History(len(scenarios), profile.n_inputs, profile.n_outputs, steps)
    seen: list[FloatArray] = []
    labels: list[FloatArray] = []

    def policy(inputs: FloatArray, robots: IntArray) -> FloatArray:
        wanted = expert.outputs(odometry.poses[robots], robots)
        features = history.features(inputs, robots)
        seen.append(features)
        labels.append(wanted)
        out = wanted if learner is None else learner(features)
        odometry.advance(robots, out, inputs, profile)
        history.update(robots, inputs, out)
        return out

    batch = run_episodes(scenarios, profile, policy, time_budgets=PAPER_LIMIT, stages=stages)
    return np.concatenate(seen), np.concatenate(labels), float(np.mean(batch.reached))


def contender(
    name: str, profile: RobotProfile, learner: Perceptron | None, margin: float, steps: int = 0,
    stages: Sequence[Stage] = (),
) -> Contender:  # fmt: skip
    """The learner (with ``steps`` of history) or, for None, the expert, as a benchmark
    planner deciding through ``stages`` (the training problem's)."""

    def policy(scenarios: Sequence[Scenario], prof: RobotProfile) -> Policy:
        if learner is not None:
            history = History(len(scenarios), prof.n_inputs, prof.n_outputs, steps)

            def act(inputs: FloatArray, robots: IntArray) -> FloatArray:
                out = learner(history.features(inputs, robots))
                history.update(robots, inputs, out)
                return out

            return act
        expert = Expert(scenarios, prof, margin)
        odometry = Odometry([sc.start for sc in scenarios])

        def drive(inputs: FloatArray, robots: IntArray) -> FloatArray:
            out = expert.outputs(odometry.poses[robots], robots)
            odometry.advance(robots, out, inputs, prof)
            return out

        return drive

    return Contender(name, "baseline" if learner is None else "evolved", profile, policy,
                     stages=tuple(stages))  # fmt: skip


def main() -> None:
    """DAgger rounds, a line per round, and ``DIR/ceiling.json``."""
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--robot", choices=("ugv", "swarm"), default="ugv")
    p.add_argument("--config", type=Path, help="training config (default: the shipped paper one)")
    p.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2, 3, 4])
    p.add_argument("--family-pairs", type=int, default=5, help="per family and seed; 0: none")
    p.add_argument("--rounds", type=int, default=8)
    p.add_argument("--epochs", type=int, default=20)
    p.add_argument("--hidden", type=int, nargs="+", default=[64, 64])
    p.add_argument("--margin", type=float, default=1.5, help="expert's disc, half diagonals")
    p.add_argument(
        "--history",
        type=int,
        default=0,
        help="decisions of past inputs and outputs the learner also sees",
    )
    p.add_argument("--learner-seed", type=int, default=0, help="the perceptron's weights, order")
    p.add_argument("--pairs-per-family", type=int, default=20)
    p.add_argument("--out", type=Path, required=True)
    args = p.parse_args()
    config, _ = load_config_file(args.config or CONFIGS / f"train_{args.robot}_paper.yaml")
    scenarios: list[Scenario] = []
    profile = None
    stages: tuple[Stage, ...] = ()  # the config's: what an evolved network decides through
    for seed in args.seeds:
        problem = make_problem(dataclasses.replace(
            config, scenario_seed=seed, families=tuple(FAMILIES) if args.family_pairs else (),
            family_pairs=args.family_pairs or 1))  # fmt: skip
        scenarios += problem.scenarios
        profile = problem.profile
        # its view corridor and rotation shim (a turn commitment never ran here)
        stages = tuple(s for s in problem.stages if s.name != TurnCommitment.name)
    assert profile is not None
    suite = build_suite(get_profile(args.robot), "validation",
                        pairs_per_family=args.pairs_per_family)  # fmt: skip
    expert = Expert(scenarios, profile, args.margin)
    width = profile.n_inputs + args.history * (profile.n_inputs + profile.n_outputs)
    learner = Perceptron(width, profile.n_outputs, args.hidden, seed=args.learner_seed)
    rows = []
    began = time.perf_counter()
    scored = run_contender(suite, contender("expert", profile, None, args.margin, 0, stages))
    rows.append({"round": "expert", "train_success": None,
                 "validation": scored.scores["paper"]})  # fmt: skip
    overall = scored.scores["paper"]["overall"]
    print(f"expert: validation {overall['success']:.0%} / SPL {overall['spl']:.2f}", flush=True)
    xs: list[FloatArray] = []
    ys: list[FloatArray] = []
    for k in range(args.rounds):
        x, y, reached = rollout(
            scenarios, profile, expert, None if k == 0 else learner, args.history, stages
        )
        xs.append(x)
        ys.append(y)
        mse = learner.fit(np.concatenate(xs), np.concatenate(ys), args.epochs)
        scored = run_contender(
            suite, contender(f"round{k}", profile, learner, args.margin, args.history, stages)
        )
        overall = scored.scores["paper"]["overall"]
        rows.append({"round": k, "train_success": reached, "samples": int(sum(map(len, xs))),
                     "mse": mse, "validation": scored.scores["paper"]})  # fmt: skip
        print(f"round {k}: {'expert' if k == 0 else 'learner'} reached {reached:.0%} of "
              f"{len(scenarios)} training pairs; {sum(map(len, xs))} labels, mse {mse:.4f}; "
              f"learner on validation {overall['success']:.0%} / SPL {overall['spl']:.2f} "
              f"(collisions {overall['collision']:.0%}); {time.perf_counter() - began:.0f} s",
              flush=True)  # fmt: skip
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "ceiling.json").write_text(json.dumps(rows, indent=1), encoding="utf-8")


if __name__ == "__main__":
    main()
