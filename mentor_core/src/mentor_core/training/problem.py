"""The path-planning problem: genomes in, objectives (performance F, experience gain G) out.

This is where evolution and simulation meet (pymoo's "problem"): every genome drives one robot
in every training scenario, all robots of a call step together in the batched engine, and each
genome gets

* F = sum_i F_i, paper eqs. (3)-(4) (``objectives.scenario_performance``); the final
  distance S_f of a failure is the straight one (the paper's) or, with
  ``goal_distance="geodesic"``, the shortest way round the obstacles (not in the paper); a
  success is credited with the time it left (the paper's) or, with
  ``success_credit="path"``, the efficiency of its path (``objectives.path_credit``, not in
  the paper), and
* G = total length of the Euclidean minimum spanning tree over the union of its experience
  points V = [U(t), A(t), U(t+1)], paper eqs. (5)-(8) (``experience.experience_gain``).

Evaluation is deterministic and each genome's numbers do not depend on which other genomes
share the call, so any split of the population over workers gives bit-identical results.
``evaluate(genomes, gains="best")`` computes G only for the genome of the highest F in the
call (the first of equals), NaN for the others: for generations that rank F alone (the second
stage of the dual framework, the single framework), where G would only fill the history.

With ``guide="waypoint"`` (not in the paper) every network sees, instead of its scenario's
goal, the direction of the shortest way round the obstacles at the distance still to go
(``navigation.waypoints``): it is trained to follow a global plan. F and G are unchanged.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from mentor_core.controller.episodes import run_episodes
from mentor_core.controller.stage import Stage
from mentor_core.evolution.batch_network import BatchNetwork
from mentor_core.evolution.genome import Genome
from mentor_core.navigation.goal_distance import GoalDistance
from mentor_core.navigation.guide import guide_config
from mentor_core.navigation.shortest_path import VisibilityGraph
from mentor_core.navigation.waypoints import WaypointGoals
from mentor_core.objectives.experience import experience_gains_packed
from mentor_core.objectives.performance import (
    credited_performance,
    path_credit,
    scenario_performance,
)
from mentor_core.sim.episode import EpisodeBatch
from mentor_core.sim.goal_frame import goal_frame_turns
from mentor_core.sim.robots import RobotProfile
from mentor_core.sim.world import Scenario
from mentor_core.training.gain_overlap import GainOverlap

OBJECTIVE_NAMES = ("performance", "experience_gain")
GoalDistanceKind = Literal["euclidean", "geodesic"]
TurnFrame = Literal["body", "goal"]
SuccessCredit = Literal["time", "path"]
Guide = Literal["none", "waypoint"]
#: which genomes of an ``evaluate`` call get their G: all, or the one of the highest F
GainScope = Literal["all", "best"]
# the geodesic S_f's footprint: a little inside the body's inscribed disc, so that a robot
# stopped against an obstacle still stands in the free space
_INSCRIBED_SHARE = 0.9


@dataclass(frozen=True)
class Evaluation:
    """What one call of :meth:`NavigationProblem.evaluate` measured, per genome.

    Attributes:
        objectives: (n_genomes, 2) float64: F (performance) and G (experience gain); G is
            NaN where it was not computed (``gains="best"``).
        success_rate: (n_genomes,) share of scenarios whose goal was reached.
        collision_rate: (n_genomes,) share of scenarios that ended in a collision.
        behaviour: (n_genomes, 2 n_scenarios) the robot's final position (x, y) in each
            scenario over its world's size: the behaviour novelty search compares
            (``objectives.novelty``; not in the paper).
    """

    objectives: NDArray[np.float64]
    success_rate: NDArray[np.float64]
    collision_rate: NDArray[np.float64]
    behaviour: NDArray[np.float64]


class NavigationProblem:
    """Evaluate planners (genomes) on a fixed list of scenarios in one world.

    ``time_budget`` (s) gives every scenario that budget T_tot; None keeps the paper's
    (:meth:`~mentor_core.sim.robots.RobotProfile.time_budget`). ``goal_distance``: S_f of
    paper eq. 4 is the straight distance to the goal ("euclidean", the paper's) or the
    shortest way round the obstacles into the goal's disc ("geodesic",
    :class:`~mentor_core.navigation.goal_distance.GoalDistance`, for a disc a little inside
    the body; where the final point is outside its free space, the straight distance). A
    robot stopped at a wall with its goal behind it is then as far from the goal as the way
    round, not as the wall's thickness. ``stages``: the controller's stages the networks
    decide through in training (:mod:`mentor_core.controller`; the config's
    ``TrainerConfig.trained_stages``; none in the paper).
    ``turn_frame="goal"``: the turn output names a heading relative to the goal
    (:func:`~mentor_core.sim.goal_frame.goal_frame_turns`; not in the paper).
    ``success_credit="path"``: a success's credit in F_i is the shortest path's length (the
    body's circumscribed disc into the goal radius, as the benchmark's SPL measures it) over
    the length driven, instead of ``T_rem / T_tot`` (not in the paper); where that disc has
    no path, the straight distance into the goal radius stands in for it.
    ``guide="waypoint"``: the networks see the shortest way's direction instead of the goal
    (module docstring), the way of the robot's default global plan
    (:func:`~mentor_core.navigation.guide.guide_config`), in the share ``guide_share`` of
    the scenarios (evenly spread; the others show the goal).
    """

    def __init__(
        self,
        profile: RobotProfile,
        scenarios: Sequence[Scenario],
        *,
        with_experience: bool = True,
        time_budget: float | None = None,
        goal_distance: GoalDistanceKind = "euclidean",
        stages: Sequence[Stage] = (),
        turn_frame: TurnFrame = "body",
        success_credit: SuccessCredit = "time",
        guide: Guide = "none",
        guide_share: float = 1.0,
    ) -> None:
        if not scenarios:
            raise ValueError("a NavigationProblem needs at least one scenario")
        if goal_distance not in ("euclidean", "geodesic"):
            raise ValueError(f"goal_distance must be euclidean or geodesic, not {goal_distance!r}")
        if success_credit not in ("time", "path"):
            raise ValueError(f"success_credit must be time or path, not {success_credit!r}")
        if guide not in ("none", "waypoint"):
            raise ValueError(f"guide must be none or waypoint, not {guide!r}")
        if not 0.0 < guide_share <= 1.0:
            raise ValueError(f"guide_share must be in (0, 1], got {guide_share}")
        if turn_frame not in ("body", "goal"):
            raise ValueError(f"turn_frame must be body or goal, not {turn_frame!r}")
        if turn_frame == "goal" and profile.input_encoding != "egocentric":
            raise ValueError("turn_frame goal needs the egocentric input encoding")
        self.profile = profile
        self.scenarios = tuple(scenarios)
        self.with_experience = with_experience
        # one T_tot for every scenario (s); None: the paper's per-scenario budget
        self.time_budget = time_budget
        self.goal_distance = goal_distance
        self.stages = tuple(stages)
        self.turn_frame = turn_frame
        self.success_credit = success_credit
        self.guide = guide
        # the goals the networks see, per robot of a simulate call; None: the scenarios'.
        # Scenario s is guided when floor((s + 1) share) > floor(s share): evenly spread
        n = len(self.scenarios)
        guided = np.floor(np.arange(1, n + 1) * guide_share) > np.floor(np.arange(n) * guide_share)
        self._input_goals = (
            WaypointGoals(self.scenarios, guide_config(profile), profile.goal_radius,
                          guided.tolist())
            if guide == "waypoint" else None
        )  # fmt: skip
        # the shortest paths' lengths (m) for the path credit, computed once
        self._shortest = (
            shortest_lengths(self.scenarios, profile) if success_credit == "path" else None
        )
        self._to_goal: tuple[GoalDistance, ...] = ()
        if goal_distance == "geodesic":
            radius = _INSCRIBED_SHARE * 0.5 * min(profile.length, profile.width)
            graphs: dict[int, VisibilityGraph] = {}  # one per world object, built once
            for sc in self.scenarios:
                if id(sc.world) not in graphs:
                    graphs[id(sc.world)] = VisibilityGraph(sc.world, radius)
            self._to_goal = tuple(
                GoalDistance(graphs[id(sc.world)], sc.goal, profile.goal_radius)
                for sc in self.scenarios
            )

    @property
    def n_inputs(self) -> int:
        """Network inputs (without the bias): the sensors, the goal inputs and the context."""
        return self.profile.n_inputs

    @property
    def n_outputs(self) -> int:
        """Network outputs: the two actions and the memory units."""
        return self.profile.n_outputs

    def simulate(self, genomes: Sequence[Genome]) -> EpisodeBatch:
        """Run every genome on every scenario; robot ``g * n_scenarios + s`` is (g, s).

        All genomes are compiled into one
        :class:`~mentor_core.evolution.batch_network.BatchNetwork`, so each decision evaluates
        every active robot's network in one batched call; a robot's outputs do not depend on
        which other robots share it.
        """
        if not genomes:
            raise ValueError("simulate needs at least one genome")
        n_scen = len(self.scenarios)
        network = BatchNetwork.from_genomes(genomes)
        n = n_scen * len(genomes)
        goal_frame = self.turn_frame == "goal"
        memory = network.new_memory(n)  # recurrent genomes' previous values, per robot

        def policy(inputs: NDArray[np.float64], robots: NDArray[np.int64]) -> NDArray[np.float64]:
            out = network.activate(inputs, robots // n_scen, memory=memory, slots=robots)
            if goal_frame:
                out = goal_frame_turns(out, inputs, self.profile)
            return out

        return run_episodes(
            list(self.scenarios) * len(genomes), self.profile, policy,
            time_budgets=self.time_budget, input_goals=self._input_goals, stages=self.stages,
        )  # fmt: skip

    def evaluate(
        self,
        genomes: Sequence[Genome],
        gains: GainScope = "all",
        overlap: GainOverlap | None = None,
    ) -> Evaluation:
        """Objectives (F, G) and outcome rates of each genome; G is 0 without experience.

        ``gains="best"``: G only for the genome of the highest F (the first of equals), NaN
        for the others (module docstring). ``overlap``: with ``gains="all"``, simulate in
        parts and compute the first parts' G on its background threads meanwhile
        (:mod:`~mentor_core.training.gain_overlap`); the numbers are the same."""
        if gains not in ("all", "best"):
            raise ValueError(f"gains must be 'all' or 'best', got {gains!r}")
        n_gen, n_scen = len(genomes), len(self.scenarios)
        objectives = np.zeros((n_gen, 2), dtype=np.float64)
        success = np.zeros(n_gen, dtype=np.float64)
        collision = np.zeros(n_gen, dtype=np.float64)
        behaviour = np.zeros((n_gen, 2 * n_scen), dtype=np.float64)
        all_gains = self.with_experience and gains == "all"
        parts = overlap.parts(n_gen, n_scen) if overlap is not None and all_gains else []
        if len(parts) < 2:  # one part: G after the simulation, on all threads
            overlap, parts = None, [(0, n_gen)]
        pending: list[tuple[int, int, Callable[[], NDArray[np.float64]]]] = []
        for lo, hi in parts if n_gen else []:
            batch = self.simulate(genomes[lo:hi])
            objectives[lo:hi, 0] = self.performance(batch).reshape(hi - lo, n_scen).sum(axis=1)
            success[lo:hi] = batch.reached.reshape(hi - lo, n_scen).mean(axis=1)
            collision[lo:hi] = batch.collided.reshape(hi - lo, n_scen).mean(axis=1)
            behaviour[lo:hi] = self.behaviour(batch)
            if not self.with_experience:
                continue
            # genome g's points are rows[at[g S]:at[(g + 1) S]] (genome-major robots)
            rows, at = batch.packed_experience()
            per_genome = at[::n_scen]
            if gains == "best":  # one part: the whole call's best
                g = int(np.argmax(objectives[:, 0]))
                objectives[:, 1] = np.nan
                objectives[g, 1] = experience_gains_packed(rows, per_genome[g : g + 2])[0]
            elif overlap is not None:
                pending.append((lo, hi, overlap.submit(rows, per_genome)))
            else:
                objectives[lo:hi, 1] = experience_gains_packed(rows, per_genome)
        for lo, hi, gathered in pending:
            objectives[lo:hi, 1] = gathered()
        return Evaluation(objectives, success, collision, behaviour)

    def performance(self, batch: EpisodeBatch) -> NDArray[np.float64]:
        """F_i of each robot of ``batch`` (genome-major over this problem's scenarios): paper
        eqs. 3-4, or with the path's credit (class docstring)."""
        if self._shortest is None:
            return scenario_performance(
                batch.reached,
                batch.time_budget - batch.time_used,
                batch.time_budget,
                self.final_distance(batch),
            )
        n_gen = len(batch.reached) // len(self.scenarios)
        credit = path_credit(np.tile(self._shortest, n_gen), batch.path_length(self.profile))
        return credited_performance(batch.reached, credit, self.final_distance(batch))

    def behaviour(self, batch: EpisodeBatch) -> NDArray[np.float64]:
        """Final positions of ``batch``'s robots over their world's size, (n_genomes, 2 S)."""
        n_scen = len(self.scenarios)
        sizes = np.array([sc.world.size for sc in self.scenarios])
        final = batch.final_position.reshape(-1, n_scen, 2) / sizes[None, :, None]
        return np.asarray(final.reshape(-1, 2 * n_scen), dtype=np.float64)

    def final_distance(self, batch: EpisodeBatch) -> NDArray[np.float64]:
        """S_f of each robot of ``batch`` (genome-major over this problem's scenarios), m."""
        if not self._to_goal:
            return batch.final_distance
        out = batch.final_distance.copy()
        n_scen = len(self.scenarios)
        robots = np.flatnonzero(~batch.reached)
        final = batch.final_position[robots]
        for s, to_goal in enumerate(self._to_goal):
            mine = robots % n_scen == s
            if mine.any():
                # into the disc, then its radius: equal to the straight distance in the open
                d = to_goal(final[mine]) + to_goal.goal_radius
                out[robots[mine]] = np.where(np.isfinite(d), d, out[robots[mine]])
        return out


def shortest_lengths(scenarios: Sequence[Scenario], profile: RobotProfile) -> NDArray[np.float64]:
    """Per scenario the length of the shortest path of the body's circumscribed disc into the
    goal radius (m; the benchmark's ``BenchPair.shortest``), the straight distance into the
    goal radius where there is none."""
    graphs: dict[int, VisibilityGraph] = {}  # one per world object, built once
    out = np.empty(len(scenarios), dtype=np.float64)
    for i, sc in enumerate(scenarios):
        if id(sc.world) not in graphs:
            graphs[id(sc.world)] = VisibilityGraph(sc.world, profile.half_diagonal)
        length = graphs[id(sc.world)].to_disc(sc.start, sc.goal, profile.goal_radius)
        straight = max(float(np.hypot(sc.goal[0] - sc.start[0], sc.goal[1] - sc.start[1]))
                       - profile.goal_radius, 0.0)  # fmt: skip
        out[i] = length if np.isfinite(length) else straight
    return out
