"""Head to head: each evolved planner against the best baseline, family by family.

Issue 15 asks that a user see at a glance whether the evolved planner beats the classic one in
each family. For each evolved planner of a ``mentor-bench`` document (over its seeds, their
mean, where it is labelled ``<name>-s<seed>``) and each family, this finds the best baseline
on success and, separately, the best on SPL (Anderson et al. 2018), among every baseline
variant the document holds (plain, guarded, on a scan map, at the shipped limits; the oracle
is not a baseline), and the margins. Picking the best variant per family and column is a
higher bar than any one baseline; it is the bar the headline tables of
``benchmarks/RESULTS.md`` use.

Each margin comes with a 95 % interval of a paired, family-stratified bootstrap over the
pairs (:mod:`~mentor_core.report.bootstrap`; the evolved planner's per-pair value the mean
over its seeds, the baseline's that of the variant named), so that a user can tell a margin
that another draw of pairs could undo from one it would not.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from mentor_core.benchmark.scores import decisions_allowed, spl
from mentor_core.report.bootstrap import paired_interval
from mentor_core.report.seed_groups import evolved_planners, seed_groups

#: margins closer to 0 than this are ties: a mean of seeds' rates k/n carries rounding error
TIE = 1e-9


@dataclass(frozen=True)
class FamilyMatch:
    """One evolved planner against the best baselines in one family (or ``overall``).

    Rates are fractions in [0, 1], SPL in [0, 1]; an evolved planner's are the mean over its
    seeds. ``best_success_by`` and ``best_spl_by`` name the baselines that set each bar (the
    first in the document's order where several tie)."""

    family: str
    success: float
    spl: float
    best_success: float
    best_success_by: str
    best_spl: float
    best_spl_by: str
    #: 95 % intervals of the margins (fraction, SPL; NaN where the document lacks per-pair data)
    success_interval: tuple[float, float] = (math.nan, math.nan)
    spl_interval: tuple[float, float] = (math.nan, math.nan)

    @property
    def success_margin(self) -> float:
        """The planner's success less the best baseline's (fraction; > 0: it leads)."""
        return self.success - self.best_success

    @property
    def spl_margin(self) -> float:
        """The planner's SPL less the best baseline's (> 0: it leads)."""
        return self.spl - self.best_spl

    @property
    def level_on_success(self) -> bool:
        """Success at least the best baseline's (leads or ties)."""
        return self.success_margin > -TIE

    @property
    def level_on_spl(self) -> bool:
        """SPL at least the best baseline's (leads or ties)."""
        return self.spl_margin > -TIE

    @property
    def beats(self) -> bool:
        """Above the best baseline on both success and SPL."""
        return self.success_margin > TIE and self.spl_margin > TIE

    @property
    def success_verdict(self) -> str:
        """``leads`` or ``trails`` where the success margin's interval excludes 0, else
        ``level`` (``-`` without an interval)."""
        return _verdict(self.success_interval)

    @property
    def spl_verdict(self) -> str:
        """As :attr:`success_verdict`, for SPL."""
        return _verdict(self.spl_interval)


def _verdict(interval: tuple[float, float]) -> str:
    lo, hi = interval
    if not (math.isfinite(lo) and math.isfinite(hi)):
        return "-"
    return "leads" if lo > TIE else "trails" if hi < -TIE else "level"


def _score(contender: Mapping[str, Any], limit: str, family: str, key: str) -> float:
    value = contender["scores"][limit][family][key]
    return math.nan if value is None else float(value)


def _mean(values: list[float]) -> float:
    """The mean of the finite values (NaN where none is)."""
    finite = [v for v in values if math.isfinite(v)]
    return float(np.mean(finite)) if finite else math.nan


def _best(baselines: list[Mapping[str, Any]], limit: str, family: str,
          key: str) -> tuple[float, str]:
    values = [_score(b, limit, family, key) for b in baselines]
    finite = [i for i, v in enumerate(values) if math.isfinite(v)]
    if not finite:
        return math.nan, "-"
    i = max(finite, key=lambda j: values[j])  # max keeps the first of equal values
    return values[i], str(baselines[i]["name"])


def per_pair(doc: Mapping[str, Any], contender: Mapping[str, Any],
             limit: str) -> dict[str, NDArray[np.float64]] | None:  # fmt: skip
    """A contender's per-pair success (1 or 0) and SPL term under ``limit``, as its scores
    count them (``benchmark.scores``); None where its results lack what they need or do not
    add up to its scores (a document of an older version)."""
    try:
        period = float(contender["settings"]["control_period"])
        if limit == "paper":
            limits = np.full(len(doc["pairs"]), float(doc["paper_limit"]))
        else:
            limits = np.array([float(p["time_limit"]) for p in doc["pairs"]])
        results = contender["results"]
        reached = np.array([bool(r["reached"]) for r in results])
        steps = np.array([int(r["steps"]) for r in results])
        taken = np.array([float(r["path_length"]) for r in results])
        shortest = np.array([float(p["shortest"]) for p in doc["pairs"]])
    except (KeyError, TypeError, ValueError):
        return None
    ok = reached & (steps <= decisions_allowed(limits, period))
    values = {"success": ok.astype(np.float64), "spl": spl(ok, shortest, taken)}
    families = _families(doc)
    for family in doc["families"]:
        for key, v in values.items():
            if abs(float(v[families == family].mean()) - _score(contender, limit, family,
                                                                  key)) > 1e-9:
                return None
    return values


def _families(doc: Mapping[str, Any]) -> NDArray[np.str_]:
    """The family of each pair of ``doc``."""
    return np.array([p["family"] for p in doc["pairs"]])


def _interval(doc: Mapping[str, Any], families: NDArray[np.str_] | None,
              mine: dict[str, NDArray[np.float64]] | None,
              theirs: dict[str, NDArray[np.float64]] | None, family: str,
              key: str) -> tuple[float, float]:  # fmt: skip
    """The interval of the margin of ``mine`` (the seeds' per-pair mean) over ``theirs`` in
    ``family`` (``overall``: stratified by family); NaN where either lacks per-pair data."""
    if families is None or mine is None or theirs is None:
        return math.nan, math.nan
    diff = mine[key] - theirs[key]
    chosen = doc["families"] if family == "overall" else [family]
    return paired_interval([diff[families == f] for f in chosen])


#: ``{family | "overall": {"success" | "spl": baseline name}}``: the variant that sets each bar
Choice = Mapping[str, Mapping[str, str]]


def baseline_choice(doc: Mapping[str, Any], limit: str = "paper") -> dict[str, dict[str, str]]:
    """The best baseline variant of a ``mentor-bench`` document in each family and
    ``overall``, on success and on SPL (the first of equals): run on the validation split,
    the bars a test run's head to head may take instead of its own best (:func:`head_to_head`,
    ``choice``), free of the winner's bias of picking the best on the pairs that are scored.
    ValueError when the document holds no baseline."""
    baselines = [c for c in doc["contenders"] if c["kind"] == "baseline"]
    if not baselines:
        raise ValueError("the document holds no baseline to choose from")
    return {family: {key: _best(baselines, limit, family, key)[1] for key in ("success", "spl")}
            for family in [*doc["families"], "overall"]}  # fmt: skip


def head_to_head(
    doc: Mapping[str, Any], limit: str = "paper", choice: Choice | None = None
) -> dict[str, list[FamilyMatch]]:
    """Each evolved planner of a ``mentor-bench`` document (``benchmark.document``) against
    the best baseline per family and ``overall``, under ``limit`` (``paper``: 50 s, or
    ``scaled``), or with ``choice`` (:func:`baseline_choice` of another run) against the
    variant it names. Keys: the seed group's name (``<name>`` of ``<name>-s<seed>``,
    several seeds) or the contender's name. Empty when the document holds no baseline.
    ValueError when ``choice`` names a family or a baseline the document lacks."""
    contenders = doc["contenders"]
    baselines = [c for c in contenders if c["kind"] == "baseline"]
    if not baselines:
        return {}
    by_name = {str(b["name"]): b for b in baselines}

    def bar(family: str, key: str) -> tuple[float, str]:
        if choice is None:
            return _best(baselines, limit, family, key)
        name = choice.get(family, {}).get(key)
        if name not in by_name:
            raise ValueError(f"the baseline choice names {name!r} for {family} {key}, which "
                             "this run lacks")  # fmt: skip
        return _score(by_name[name], limit, family, key), name

    planners = evolved_planners(contenders)
    pairs = {str(c["name"]): per_pair(doc, c, limit) for c in contenders}
    families = _families(doc) if "pairs" in doc else None  # None: no per-pair data at all
    out: dict[str, list[FamilyMatch]] = {}
    for name, idx in planners.items():
        seeds = [pairs[str(contenders[i]["name"])] for i in idx]
        # the seeds' per-pair mean, once a planner (None when a seed lacks per-pair data)
        mine = None if any(v is None for v in seeds) else {
            key: np.mean([v[key] for v in seeds if v is not None], axis=0)
            for key in ("success", "spl")}  # fmt: skip
        rows = []
        for family in [*doc["families"], "overall"]:
            mean = {key: _mean([_score(contenders[i], limit, family, key) for i in idx])
                    for key in ("success", "spl")}  # fmt: skip
            best_success, success_by = bar(family, "success")
            best_spl, spl_by = bar(family, "spl")
            rows.append(FamilyMatch(
                family, mean["success"], mean["spl"], best_success, success_by, best_spl,
                spl_by,
                _interval(doc, families, mine, pairs.get(success_by), family, "success"),
                _interval(doc, families, mine, pairs.get(spl_by), family, "spl"),
            ))  # fmt: skip
        out[name] = rows
    return out


def _value(x: float, percent: bool) -> str:
    if not math.isfinite(x):
        return "-"
    return f"{100 * x:.1f} %" if percent else f"{x:.2f}"


def _margin(value: float, interval: tuple[float, float], scale: float, digits: int) -> str:
    if not math.isfinite(value):
        return "-"
    word = "leads" if value > TIE else "trails" if value < -TIE else "ties"
    value = 0.0 if word == "ties" else value
    lo, hi = (0.0 if abs(x) < TIE else x for x in interval)  # no "-0.0" of rounding error
    within = (f" ({scale * lo:+.{digits}f} to {scale * hi:+.{digits}f})"
              if math.isfinite(lo) and math.isfinite(hi) else "")  # fmt: skip
    return f"{scale * value:+.{digits}f} {word}{within}"


def head_to_head_markdown(
    doc: Mapping[str, Any], limit: str = "paper", choice: Choice | None = None
) -> list[str]:
    """Markdown lines: a table per evolved planner of :func:`head_to_head` (with ``choice``:
    against the variants it names), each followed by a line counting the families where it
    leads or ties on success, on SPL, and beats on both. No lines when the document has no
    evolved planner or no baseline."""
    md: list[str] = []
    groups = seed_groups(doc["contenders"])
    bar = "best baseline" if choice is None else "chosen baseline"
    for name, rows in head_to_head(doc, limit, choice).items():
        seeds = len(groups.get(name, ()))
        who = f"`{name}`" + (f" (mean of {seeds} seeds)" if seeds else "")
        md += [f"| family | {who}: success / SPL | {bar}: success | "
               f"{bar}: SPL | success (points) | SPL |",
               "|---|---|---|---|---|---|"]
        for r in rows:
            label = f"**{r.family}**" if r.family == "overall" else r.family
            md.append(f"| {label} | {_value(r.success, True)} / {_value(r.spl, False)} | "
                      f"{_value(r.best_success, True)} ({r.best_success_by}) | "
                      f"{_value(r.best_spl, False)} ({r.best_spl_by}) | "
                      f"{_margin(r.success_margin, r.success_interval, 100.0, 1)} | "
                      f"{_margin(r.spl_margin, r.spl_interval, 1.0, 3)} |")
        families = [r for r in rows if r.family != "overall"]
        n = len(families)
        on_success = sum(r.level_on_success for r in families)
        on_spl = sum(r.level_on_spl for r in families)
        md += ["", f"{who} leads or ties the {bar} on success in {on_success} of {n} "
               f"families, on SPL in {on_spl} of {n}, and beats it on both in "
               f"{sum(r.beats for r in families)} of {n}." + _settled(families), ""]
    return md


def _settled(rows: list[FamilyMatch]) -> str:
    """The sentence on the margins whose 95 % interval excludes 0 ('' without intervals)."""
    if not rows or any(r.success_verdict == "-" or r.spl_verdict == "-" for r in rows):
        return ""
    count = {(key, word): sum(getattr(r, f"{key}_verdict") == word for r in rows)
             for key in ("success", "spl") for word in ("leads", "trails")}  # fmt: skip
    return (f" Beyond the 95 % interval beside each margin it leads on success in "
            f"{count['success', 'leads']} and trails in {count['success', 'trails']}; on SPL "
            f"it leads in {count['spl', 'leads']} and trails in {count['spl', 'trails']}; "
            f"the other margins are within what another draw of pairs could undo.")
