"""Running planners on a suite, and their scores.

    suite = build_suite(get_profile("ugv"), "validation", pairs_per_family=20)
    result = run_contender(suite, evolved("runs/x/best_genome.json", get_profile("ugv")))
    result.scores["paper"]["overall"]["success"]

Each family's pairs run as one :func:`mentor_core.controller.episodes.run_episodes` call (the
robots of one world step together), once, with the longer of the two time limits per pair; the
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
from mentor_core.controller.episodes import run_episodes

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


def run_family(suite: Suite, contender: Contender, family: str) -> Outcomes:
    """``contender`` on the pairs of ``family`` in ``suite`` (suite order), in one
    :func:`~mentor_core.controller.episodes.run_episodes` call with a fresh policy, so the
    outcomes do not depend on what ran before or beside it."""
    limits = limits_of(suite)
    budgets = np.maximum(limits["paper"], limits["scaled"])
    idx = [i for i, p in enumerate(suite.pairs) if p.family == family]
    if not idx:
        raise ValueError(f"the suite has no pairs of family {family!r}")
    scenarios = [suite.pairs[i].scenario for i in idx]
    batch = run_episodes(scenarios, contender.profile, contender.policy(scenarios),
                         time_budgets=budgets[idx], input_goals=contender.input_goals(scenarios),
                         stages=contender.stages)  # fmt: skip
    return outcomes(batch, contender.profile)


def family_line(suite: Suite, contender: Contender, family: str, part: Outcomes,
                seconds: float) -> str:  # fmt: skip
    """The progress line of one family's run: how many pairs it reached within the paper's
    limit (as the table counts them), and how many more later."""
    limits = limits_of(suite)
    idx = [i for i, p in enumerate(suite.pairs) if p.family == family]
    ok, _ = under_limit(part, limits["paper"][idx], contender.profile.control_period)
    done = int(np.count_nonzero(ok))
    late = int(np.count_nonzero(part.reached)) - done
    later = f", {late} more later" if late else ""
    return (f"{contender.name}: {family:<14} {done:>3}/{len(idx)} reached within "
            f"{PAPER_LIMIT:.0f} s{later} ({seconds:.1f} s)")  # fmt: skip


def contender_result(
    suite: Suite, contender: Contender, parts: Sequence[Outcomes], seconds: float
) -> ContenderResult:
    """The result of ``contender`` from its runs of ``suite.families`` (in that order)."""
    merged = _concatenate(parts)
    shortest = np.array([p.shortest for p in suite.pairs], dtype=np.float64)
    families = [p.family for p in suite.pairs]
    if families != [f for f in suite.families for g in families if g == f]:
        raise ValueError("the suite's pairs are not grouped by family in its order")
    scores = score_table(merged, families, shortest, limits_of(suite),
                         contender.profile.control_period)  # fmt: skip
    return ContenderResult(contender, merged, scores, seconds)


def run_contender(
    suite: Suite, contender: Contender, progress: Progress | None = None
) -> ContenderResult:
    """Run ``contender`` on every pair of ``suite``; ``progress`` gets a line per family."""
    parts: list[Outcomes] = []
    began = time.perf_counter()
    for family in suite.families:
        t0 = time.perf_counter()
        parts.append(run_family(suite, contender, family))
        if progress is not None:
            progress(family_line(suite, contender, family, parts[-1], time.perf_counter() - t0))
    return contender_result(suite, contender, parts, time.perf_counter() - began)


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
