"""The path-planning problem: genomes in, objectives (performance F, experience gain G) out.

This is where evolution and simulation meet (pymoo's "problem"): every genome drives one robot
in every training scenario, all robots of a call step together in the batched engine, and each
genome gets

* F = sum_i F_i, paper eqs. (3)-(4) (``objectives.scenario_performance``), and
* G = total length of the Euclidean minimum spanning tree over the union of its experience
  points V = [U(t), A(t), U(t+1)], paper eqs. (5)-(8) (``experience.experience_gain``).

Evaluation is deterministic and each genome's numbers do not depend on which other genomes
share the call, so any split of the population over workers gives bit-identical results.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from mentor_core.evolution.batch_network import BatchNetwork
from mentor_core.evolution.genome import Genome
from mentor_core.objectives.experience import experience_gains
from mentor_core.objectives.performance import scenario_performance
from mentor_core.sim.episode import EpisodeBatch, run_episodes
from mentor_core.sim.robots import RobotProfile
from mentor_core.sim.world import Scenario

OBJECTIVE_NAMES = ("performance", "experience_gain")


@dataclass(frozen=True)
class Evaluation:
    """What one call of :meth:`NavigationProblem.evaluate` measured, per genome.

    Attributes:
        objectives: (n_genomes, 2) float64: F (performance) and G (experience gain).
        success_rate: (n_genomes,) share of scenarios whose goal was reached.
        collision_rate: (n_genomes,) share of scenarios that ended in a collision.
    """

    objectives: NDArray[np.float64]
    success_rate: NDArray[np.float64]
    collision_rate: NDArray[np.float64]


class NavigationProblem:
    """Evaluate planners (genomes) on a fixed list of scenarios in one world.

    ``time_budget`` (s) gives every scenario that budget T_tot; None keeps the paper's
    (:meth:`~mentor_core.sim.robots.RobotProfile.time_budget`).
    """

    def __init__(
        self,
        profile: RobotProfile,
        scenarios: Sequence[Scenario],
        *,
        with_experience: bool = True,
        time_budget: float | None = None,
    ) -> None:
        if not scenarios:
            raise ValueError("a NavigationProblem needs at least one scenario")
        self.profile = profile
        self.scenarios = tuple(scenarios)
        self.with_experience = with_experience
        # one T_tot for every scenario (s); None: the paper's per-scenario budget
        self.time_budget = time_budget

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

        def policy(inputs: NDArray[np.float64], robots: NDArray[np.int64]) -> NDArray[np.float64]:
            return network.activate(inputs, robots // n_scen)

        return run_episodes(
            list(self.scenarios) * len(genomes), self.profile, policy,
            time_budgets=self.time_budget,
        )  # fmt: skip

    def evaluate(self, genomes: Sequence[Genome]) -> Evaluation:
        """Objectives (F, G) and outcome rates of each genome; G is 0 without experience."""
        n_gen, n_scen = len(genomes), len(self.scenarios)
        if n_gen == 0:
            empty = np.zeros(0, dtype=np.float64)
            return Evaluation(np.zeros((0, 2), dtype=np.float64), empty, empty)
        batch = self.simulate(genomes)
        per_scenario = scenario_performance(
            batch.reached,
            batch.time_budget - batch.time_used,
            batch.time_budget,
            batch.final_distance,
        ).reshape(n_gen, n_scen)
        objectives = np.zeros((n_gen, 2), dtype=np.float64)
        objectives[:, 0] = per_scenario.sum(axis=1)
        if self.with_experience:
            points = [
                np.concatenate(batch.experience[g * n_scen : (g + 1) * n_scen], axis=0)
                for g in range(n_gen)
            ]
            objectives[:, 1] = experience_gains(points)
        return Evaluation(
            objectives=objectives,
            success_rate=batch.reached.reshape(n_gen, n_scen).mean(axis=1),
            collision_rate=batch.collided.reshape(n_gen, n_scen).mean(axis=1),
        )
