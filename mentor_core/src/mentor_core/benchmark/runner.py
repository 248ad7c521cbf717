"""Running planners on a suite, and their scores.

    suite = build_suite(get_profile("ugv"), "validation", pairs_per_family=20)
    result = run_contender(suite, evolved("runs/x/best_genome.json", get_profile("ugv")))
    result.scores["paper"]["overall"]["success"]

Each family's pairs run as one :func:`mentor_core.sim.episode.run_episodes` call (the robots
of one world step together), once, with the longer of the two time limits per pair; the
scores under each limit follow (``mentor_core.benchmark.scores``).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from mentor_core.benchmark.contenders import Contender
from mentor_core.benchmark.scores import Outcomes, outcomes, score_table, under_limit
from mentor_core.benchmark.suite import PAPER_LIMIT, Suite
from mentor_core.sim.episode import run_episodes

#: the time limits scored: the paper's 50 s, and the limit scaled to the shortest path
LIMITS = ("paper", "scaled")
Progress = Callable[[str], None]


@dataclass(frozen=True)
class ContenderResult:
    """A contender's outcomes on a suite's pairs (in suite order), its scores
    ``{limit: {"overall" | family: {score: value}}}`` and the seconds the run took."""

    contender: Contender
    outcomes: Outcomes
    scores: dict[str, dict[str, dict[str, float]]]
    seconds: float


def limits_of(suite: Suite) -> dict[str, np.ndarray]:
    """Per-pair time limits (s) of each name in :data:`LIMITS`."""
    scaled = np.array([p.time_limit for p in suite.pairs], dtype=np.float64)
    return {"paper": np.full(len(suite.pairs), PAPER_LIMIT), "scaled": scaled}


def run_contender(
    suite: Suite, contender: Contender, progress: Progress | None = None
) -> ContenderResult:
    """Run ``contender`` on every pair of ``suite``; ``progress`` gets a line per family."""
    limits = limits_of(suite)
    budgets = np.maximum(limits["paper"], limits["scaled"])
    families = [p.family for p in suite.pairs]
    parts: list[Outcomes] = []
    began = time.perf_counter()
    for family in suite.families:
        idx = [i for i, f in enumerate(families) if f == family]
        scenarios = [suite.pairs[i].scenario for i in idx]
        t0 = time.perf_counter()
        batch = run_episodes(scenarios, contender.profile, contender.policy(scenarios),
                             time_budgets=budgets[idx],
                             input_goals=contender.input_goals(scenarios))  # fmt: skip
        parts.append(outcomes(batch, contender.profile))
        if progress is not None:  # counted as the table counts them: within the paper's limit
            ok, _ = under_limit(parts[-1], limits["paper"][idx], contender.profile.control_period)
            done, late = int(np.count_nonzero(ok)), int(np.count_nonzero(batch.reached) - ok.sum())
            later = f", {late} more later" if late else ""
            progress(f"{contender.name}: {family:<14} {done:>3}/{len(idx)} reached within "
                     f"{PAPER_LIMIT:.0f} s{later} ({time.perf_counter() - t0:.1f} s)")  # fmt: skip
    merged = _concatenate(parts)
    shortest = np.array([p.shortest for p in suite.pairs], dtype=np.float64)
    scores = score_table(merged, families, shortest, limits, contender.profile.control_period)
    return ContenderResult(contender, merged, scores, time.perf_counter() - began)


def run_all(
    suite: Suite, contenders: Sequence[Contender], progress: Progress | None = None
) -> list[ContenderResult]:
    """:func:`run_contender` of each contender in turn."""
    return [run_contender(suite, c, progress) for c in contenders]


def _concatenate(parts: Sequence[Outcomes]) -> Outcomes:
    return Outcomes(
        reached=np.concatenate([p.reached for p in parts]),
        collided=np.concatenate([p.collided for p in parts]),
        steps=np.concatenate([p.steps for p in parts]),
        time=np.concatenate([p.time for p in parts]),
        path_length=np.concatenate([p.path_length for p in parts]),
        final_distance=np.concatenate([p.final_distance for p in parts]),
        trajectories=tuple(t for p in parts for t in p.trajectories),
    )
