"""Test on unseen environments (paper section IV-D).

Each planner runs once on each start/goal pair. As in the paper's test, an episode ends when
the robot comes within the goal radius (1 m for the UGV, scaled for the Swarm-Robot), when the
time limit (50 s) runs out, or on a collision. Survivability is the share of episodes that did
not end in a collision.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from mentor_core.controller.episodes import run_episodes
from mentor_core.controller.stage import Stage
from mentor_core.evolution.genome import Genome
from mentor_core.evolution.network import FeedForwardNetwork
from mentor_core.sim.episode import InputGoals
from mentor_core.sim.robots import RobotProfile
from mentor_core.sim.world import Scenario

TEST_TIME_LIMIT = 50.0  # s, the paper's cap on an unseen-environment episode


@dataclass(frozen=True)
class ScenarioResult:
    """How one episode ended; ``time`` in s, ``final_distance`` to the goal in m."""

    scenario: int
    reached: bool
    collided: bool
    timed_out: bool
    time: float
    final_distance: float
    trajectory: NDArray[np.float64]  # (steps + 1, 3) poses (x, y, theta)

    @property
    def outcome(self) -> str:
        """How it ended, as the simulator's end event: reached, collided or timed_out."""
        return "reached" if self.reached else "collided" if self.collided else "timed_out"


@dataclass(frozen=True)
class Assessment:
    """The results of one planner on a list of scenarios, with the paper's summary rates."""

    results: tuple[ScenarioResult, ...]

    @property
    def success_rate(self) -> float:
        """Share of episodes that reached the goal."""
        return float(np.mean([r.reached for r in self.results])) if self.results else 0.0

    @property
    def collision_rate(self) -> float:
        """Share of episodes that ended in a collision."""
        return float(np.mean([r.collided for r in self.results])) if self.results else 0.0

    @property
    def survivability(self) -> float:
        """Share of episodes without a collision."""
        return 1.0 - self.collision_rate

    @property
    def mean_time_reached(self) -> float:
        """Mean time of the episodes that reached the goal (NaN if none did)."""
        times = [r.time for r in self.results if r.reached]
        return float(np.mean(times)) if times else float("nan")

    def summary(self) -> dict[str, float]:
        """The summary rates as a dict (for tables and JSON)."""
        return {
            "success_rate": self.success_rate,
            "collision_rate": self.collision_rate,
            "survivability": self.survivability,
            "mean_time_reached": self.mean_time_reached,
        }


def check_compatible(genome: Genome, profile: RobotProfile) -> None:
    """Raise ValueError unless the genome's inputs/outputs fit the robot profile."""
    fault = profile.network_mismatch(genome.n_inputs, genome.n_outputs)
    if fault:
        raise ValueError(fault)


def assess(
    genome: Genome,
    profile: RobotProfile,
    scenarios: Sequence[Scenario],
    time_limit: float = TEST_TIME_LIMIT,
    input_goals: InputGoals | None = None,
    numbers: Sequence[int] | None = None,
    stages: Sequence[Stage] = (),
) -> Assessment:
    """Run ``genome`` once on each scenario with a fixed time limit (s); ``input_goals``
    gives the goal each network sees (a carrot along a global path,
    :func:`mentor_core.navigation.guide.guided_goals`), None: the scenario's goal;
    ``numbers`` are the scenarios' numbers in their source (default 0, 1, ...), as the
    results report them; ``stages``: the controller's stages its decisions pass."""
    check_compatible(genome, profile)
    policy = FeedForwardNetwork.from_genome(genome).episode_policy(len(scenarios))
    budgets = np.full(len(scenarios), float(time_limit))
    batch = run_episodes(
        list(scenarios), profile, policy, time_budgets=budgets, input_goals=input_goals,
        stages=stages,
    )
    ids = list(range(len(scenarios))) if numbers is None else [int(n) for n in numbers]
    results = tuple(
        ScenarioResult(
            scenario=ids[i],
            reached=bool(batch.reached[i]),
            collided=bool(batch.collided[i]),
            timed_out=bool(batch.timed_out[i]),
            time=float(batch.time_used[i]),
            final_distance=float(batch.final_distance[i]),
            trajectory=batch.trajectories[i, : int(batch.steps[i]) + 1].copy(),
        )
        for i in range(len(scenarios))
    )
    return Assessment(results)
