"""The paper's numbered results (Table I, Figs. 7-18, Section IV-D), each checked on a study.

Every :class:`Claim` names where the paper makes it, what it says, and a check that reads one
config's runs of a :class:`~mentor_core.report.study.Study` and returns a :class:`Finding`: this
implementation's numbers (mean ± sample sd over the seeds) and a verdict, "holds", "fails",
"not shown" (no significant difference, or the seeds disagree) or "cannot be tested" (the
study lacks what it needs, or the paper's quantity has no counterpart here), with why. Where
the paper compares the single and dual stage, the check compares the seeds with the
Mann-Whitney U test (:mod:`mentor_core.report.significance`).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy import stats

from mentor_core.evolution.config import PAPER_TABLE_I
from mentor_core.report.runs import RunData
from mentor_core.report.significance import compare, directed_verdict, p_text
from mentor_core.report.study import Study, bench_success

#: the paper's range of the largest niche's share: UGV 25-35 %, Swarm-Robot at most 25 %
NICHE_RANGE = {"ugv": (0.25, 0.35), "swarm": (0.0, 0.25)}
#: generations left out before niche sizes are judged (the population starts as one species)
SETTLING = 5
ROBOT_NAMES = {"ugv": "UGV", "swarm": "Swarm-Robot"}


@dataclass(frozen=True)
class Finding:
    """One config's result for a claim: its numbers, the verdict and why."""

    text: str
    verdict: str
    why: str = ""


@dataclass(frozen=True)
class Claim:
    """One result of the paper and its check."""

    where: str
    robot: str
    paper: str
    check: Callable[[Study, str], Finding]


def _ms(values: Sequence[float], digits: int = 2, scale: float = 1.0, unit: str = "") -> str:
    """``mean ± sd`` (sample sd) of the finite values, or a dash."""
    v = np.asarray([x * scale for x in values if math.isfinite(x)], dtype=np.float64)
    if not v.size:
        return "-"
    if v.size == 1:
        return f"{v[0]:.{digits}f}{unit}"
    return f"{v.mean():.{digits}f} ± {v.std(ddof=1):.{digits}f}{unit}"


def _missing(study: Study, config: str, robot: str, *frameworks: str) -> Finding | None:
    lacking = [f for f in frameworks if len(study.group(config, robot, f)) < 2]
    if lacking:
        return Finding("-", "cannot be tested",
                       f"fewer than 2 finished {' and '.join(lacking)}-stage runs")  # fmt: skip
    return None


# ----------------------------------------------------------------- per-run numbers
def final_best_f(run: RunData) -> float:
    """The best performance F of the run's last generation."""
    return run.history[-1].best_F


def best_f_at(run: RunData, evaluations: int) -> float:
    """The best F found within the first ``evaluations`` genomes evaluated."""
    seen = [r.best_F for r in run.history if r.evaluations <= evaluations]
    return max(seen) if seen else math.nan


def stage_one_evaluations(run: RunData) -> int | None:
    """Evaluations at the end of a dual-stage run's first stage (None for single stage)."""
    first = [r.evaluations for r in run.history if r.stage == 0]
    return max(first) if first and len(first) < len(run.history) else None


def largest_shares(run: RunData) -> NDArray[np.float64]:
    """The largest niche's share per generation, from generation :data:`SETTLING` on."""
    return np.array([r.largest_niche_share for r in run.history[SETTLING:]], dtype=np.float64)


def final_population(run: RunData) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """(performance F, complexity) of the run's final population."""
    f = np.array([float(m["objectives"]["performance"]) for m in run.members])
    c = np.array([float(m["complexity"]) for m in run.members])
    return f, c


def rank_correlation(run: RunData) -> float:
    """Spearman's rho of complexity and F over the final population (NaN when either is
    constant)."""
    f, c = final_population(run)
    if np.ptp(f) == 0.0 or np.ptp(c) == 0.0:
        return math.nan
    return float(stats.spearmanr(c, f).statistic)


def most_complex_f(run: RunData) -> float:
    """F of the final population's most complex member (the best of them on ties)."""
    f, c = final_population(run)
    return float(f[c == c.max()].max())


def front_size(run: RunData) -> int:
    """Points on the Pareto front of F and G (the dual stage's first stage)."""
    return len(run.pareto_front)


# ----------------------------------------------------------------- the checks
def _table_one(study: Study, config: str) -> Finding:
    runs = [r for (c, _, _), group in study.runs.items() if c == config for r in group]
    if not runs:
        return Finding("-", "cannot be tested", "no runs of this config")
    departures: set[str] = set()
    for run in runs:
        evo = run.config.get("evolution")
        if not isinstance(evo, dict):
            return Finding("-", "cannot be tested", f"{run.path}: config.yaml gives no evolution")
        mutation, table = evo["mutation"], PAPER_TABLE_I[run.robot]
        expected = {
            "genomes": (evo["population_size"], 100),
            "iterations": (run.generations, 50),
            "elitism": (evo["elitism"], 0.02),
            "crossover": (evo["crossover_rate"], 0.85),
            "weight mutation": (mutation["weight_rate"], table["weight"]),
            "node addition": (mutation["node_rate"], table["node_add"]),
            "edge addition": (mutation["edge_rate"], table["edge_add"]),
        }
        departures |= {f"{k} {got}" for k, (got, want) in expected.items()
                       if not math.isclose(float(got), want)}  # fmt: skip
    if departures:
        return Finding("differs: " + ", ".join(sorted(departures)), "fails",
                       "this config departs from Table I on purpose (its comments say why)")
    return Finding("Table I's values, both robots", "holds")


def _pareto(robot: str) -> Callable[[Study, str], Finding]:
    def check(study: Study, config: str) -> Finding:
        missing = _missing(study, config, robot, "dual")
        if missing:
            return missing
        runs = study.group(config, robot, "dual")
        sizes = [front_size(r) for r in runs]
        traded = sum(s >= 2 for s in sizes)
        text = f"front of {_ms(sizes, 1)} points; a trade-off in {traded} of {len(runs)} seeds"
        verdict = "holds" if traded == len(runs) else "not shown"
        return Finding(text, verdict, "a front of 2 or more points trades F against G")

    return check


def _dual_against_single(
    robot: str, measure: Callable[[RunData], float], what: str, dual_higher: bool
) -> Callable[[Study, str], Finding]:
    """The check that the dual stage's runs measure higher (``dual_higher``) or lower than
    the single stage's."""

    def check(study: Study, config: str) -> Finding:
        missing = _missing(study, config, robot, "single", "dual")
        if missing:
            return missing
        dual = [measure(r) for r in study.group(config, robot, "dual")]
        single = [measure(r) for r in study.group(config, robot, "single")]
        c = compare(dual, single)
        text = f"{what}: dual {_ms(dual)}, single {_ms(single)} ({p_text(c)})"
        return Finding(text, directed_verdict(c, a_higher=dual_higher))

    return check


def _early_rate(robot: str) -> Callable[[Study, str], Finding]:
    def check(study: Study, config: str) -> Finding:
        missing = _missing(study, config, robot, "single", "dual")
        if missing:
            return missing
        duals = study.group(config, robot, "dual")
        budget = stage_one_evaluations(duals[0])
        if budget is None:
            return Finding("-", "cannot be tested", "the dual runs have one stage")
        dual = [best_f_at(r, budget) for r in duals]
        single = [best_f_at(r, budget) for r in study.group(config, robot, "single")]
        c = compare(dual, single)
        text = (f"best F after {budget} evaluations (stage 1): dual {_ms(dual)}, single "
                f"{_ms(single)} ({p_text(c)})")  # fmt: skip
        return Finding(text, directed_verdict(c, a_higher=True))

    return check


def _niches(robot: str, framework: str) -> Callable[[Study, str], Finding]:
    low, high = NICHE_RANGE[robot]

    def check(study: Study, config: str) -> Finding:
        runs = study.group(config, robot, framework)
        if not runs:
            return Finding("-", "cannot be tested", f"no {framework}-stage runs")
        medians = [float(np.median(largest_shares(r))) for r in runs]
        within = [float(np.mean((s >= low) & (s <= high))) for r in runs
                  for s in [largest_shares(r)]]  # fmt: skip
        text = (f"largest niche (generation {SETTLING} on): median {_ms(medians, 0, 100, ' %')}; "
                f"within the paper's range in {_ms(within, 0, 100, ' %')} of generations")
        inside = low <= float(np.mean(medians)) <= high
        return Finding(text, "holds" if inside else "fails",
                       f"the paper: {_range_text(robot)}; holds when the seeds' mean median "
                       "lies there")

    return check


def _range_text(robot: str) -> str:
    low, high = NICHE_RANGE[robot]
    return f"{low * 100:.0f}-{high * 100:.0f} %" if low > 0 else f"at most {high * 100:.0f} %"


def _complexity_sign(robot: str, framework: str) -> Callable[[Study, str], Finding]:
    def check(study: Study, config: str) -> Finding:
        runs = study.group(config, robot, framework)
        if not runs:
            return Finding("-", "cannot be tested", f"no {framework}-stage runs")
        rho = [rank_correlation(r) for r in runs]
        finite = [x for x in rho if math.isfinite(x)]
        negative = sum(x < 0 for x in finite)
        text = (f"Spearman rho(complexity, F), {framework} stage: {_ms(rho)}; negative in "
                f"{negative} of {len(runs)} seeds")  # fmt: skip
        if not finite:
            return Finding(text, "cannot be tested", "complexity or F constant in every run")
        verdict = "holds" if negative == len(runs) else "fails" if negative == 0 else "not shown"
        return Finding(text, verdict, "holds when every seed agrees")

    return check


def _variance_by_complexity(study: Study, config: str) -> Finding:
    runs = [*study.group(config, "swarm", "dual"), *study.group(config, "swarm", "single")]
    if not runs:
        return Finding("-", "cannot be tested", "no Swarm-Robot runs")
    ratios = []
    for run in runs:
        f, c = final_population(run)
        simple = c <= np.median(c)
        if simple.all() or not simple.any():
            continue
        ratios.append(float(np.std(f[simple]) / max(float(np.std(f[~simple])), 1e-12)))
    if not ratios:
        return Finding("-", "cannot be tested", "complexity constant in every final population")
    wider = sum(r > 1.0 for r in ratios)
    text = (f"sd of F, simpler half over more complex half: {_ms(ratios)}; wider in {wider} "
            f"of {len(ratios)} runs")  # fmt: skip
    verdict = "holds" if wider == len(ratios) else "fails" if wider == 0 else "not shown"
    return Finding(text, verdict, "both frameworks' runs; holds when every run agrees")


def _lower_gain(study: Study, config: str) -> Finding:
    gains = {
        robot: [float(np.max(r.pareto_points[:, 1])) for r in study.group(config, robot, "dual")]
        for robot in ("ugv", "swarm")
    }
    c = compare(gains["swarm"], gains["ugv"])
    text = (f"largest G of stage 1: Swarm-Robot {_ms(gains['swarm'], 0)}, UGV "
            f"{_ms(gains['ugv'], 0)} ({p_text(c)})")
    return Finding(text, directed_verdict(c, a_higher=False),
                   "G is the MST length in each robot's own experience space")


def _higher_objective(study: Study, config: str) -> Finding:
    per_scenario = {}
    for robot in ("ugv", "swarm"):
        runs = study.group(config, robot, "dual")
        per_scenario[robot] = [final_best_f(r) / _scenarios(r) for r in runs]
    c = compare(per_scenario["swarm"], per_scenario["ugv"])
    text = (f"final best F per training scenario (dual): Swarm-Robot "
            f"{_ms(per_scenario['swarm'])}, UGV {_ms(per_scenario['ugv'])} ({p_text(c)})")
    return Finding(text, directed_verdict(c, a_higher=True), "F sums over the training "
                   "scenarios, whose count differs by robot and config: compared per scenario")


def _scenarios(run: RunData) -> int:
    return int(run.config.get("n_scenarios") or 1)


def _unseen_setting(study: Study, config: str) -> Finding:
    parts, ok = [], True
    for robot, side in (("ugv", 12.0), ("swarm", 4.0)):
        data = study.unseen.get(robot)
        if data is None:
            continue
        parts.append(f"{ROBOT_NAMES[robot]}: {data.world_size:g} m, {len(data.starts)} pairs, "
                     f"goal within {data.goal_radius:.2g} m, {data.time_limit:g} s")  # fmt: skip
        ok &= (data.world_size, len(data.starts), data.goal_radius, data.time_limit) == (
            side, 10, 1.0, 50.0)
    if not parts:
        return Finding("-", "cannot be tested", "no evaluation on the unseen bags")
    return Finding("; ".join(parts), "holds" if ok else "fails",
                   "the bags' own worlds (bags/unseen), the same for every config; a goal "
                   "radius other than 1 m is the robot file's (the Swarm-Robot's scales with "
                   "its 4 m world)")


def _unseen(
    robot: str, most: float | None, least: float | None
) -> Callable[[Study, str], Finding]:
    def check(study: Study, config: str) -> Finding:
        rates = {fw: [r.summary["success_rate"] for r in study.unseen_runs(config, robot, fw)]
                 for fw in ("single", "dual")}  # fmt: skip
        if not all(rates.values()):
            return Finding("-", "cannot be tested", "no evaluation on the unseen bags")
        pairs = len(study.unseen[robot].starts)
        text = "; ".join(f"{fw} {_ms(v, 1, pairs)} of {pairs}" for fw, v in rates.items())
        means = [float(np.mean(v)) for v in rates.values()]
        ok = all((most is None or m <= most) and (least is None or m >= least) for m in means)
        bound = f"at most {most:.0%}" if most is not None else f"at least {least:.0%}"
        return Finding(text, "holds" if ok else "fails", f"holds when both means are {bound}")

    return check


def _unseen_dual_vs_single(robot: str) -> Callable[[Study, str], Finding]:
    def check(study: Study, config: str) -> Finding:
        parts, verdicts = [], []
        for source, values in _unseen_and_bench(study, config, robot).items():
            c = compare(values["dual"], values["single"])
            parts.append(f"{source}: dual {_ms(values['dual'], 0, 100, ' %')}, single "
                         f"{_ms(values['single'], 0, 100, ' %')} ({p_text(c)})")  # fmt: skip
            verdicts.append(directed_verdict(c, a_higher=True))
        if not parts:
            return Finding("-", "cannot be tested", "no unseen evaluation")
        # the paper says "better or as good": only a significant loss fails it
        verdict = "fails" if "fails" in verdicts else "holds"
        return Finding("; ".join(parts), verdict, "dual at least as good: fails only on a "
                                                  "significant loss")  # fmt: skip

    return check


def _unseen_and_bench(study: Study, config: str, robot: str) -> dict[str, dict[str, list[float]]]:
    out: dict[str, dict[str, list[float]]] = {}
    runs = {fw: study.unseen_runs(config, robot, fw) for fw in ("single", "dual")}
    if all(runs.values()):
        out["bags"] = {fw: [r.summary["success_rate"] for r in v] for fw, v in runs.items()}
    values = {fw: bench_success(study.bench.get(robot), config, fw) for fw in ("single", "dual")}
    if all(len(v) >= 2 for v in values.values()):
        out["test split, deployed"] = values
    return out


def _speed_and_survival(study: Study, config: str) -> Finding:
    runs = {fw: study.unseen_runs(config, "swarm", fw) for fw in ("single", "dual")}
    if not all(runs.values()):
        return Finding("-", "cannot be tested", "no evaluation on the unseen bags")
    time = {fw: [r.summary["mean_time_reached"] for r in v] for fw, v in runs.items()}
    alive = {fw: [r.summary["survivability"] for r in v] for fw, v in runs.items()}
    faster = compare(time["dual"], time["single"])
    safer = compare(alive["single"], alive["dual"])
    text = (f"time to goal: dual {_ms(time['dual'], 1, unit=' s')}, single "
            f"{_ms(time['single'], 1, unit=' s')} ({p_text(faster)}); survivability: single "
            f"{_ms(alive['single'], 0, 100, ' %')}, dual {_ms(alive['dual'], 0, 100, ' %')} "
            f"({p_text(safer)})")  # fmt: skip
    verdicts = {directed_verdict(faster, a_higher=False), directed_verdict(safer, a_higher=True)}
    verdict = "holds" if verdicts == {"holds"} else "fails" if "fails" in verdicts else "not shown"
    return Finding(text, verdict, "both halves must hold")


CLAIMS: tuple[Claim, ...] = (
    Claim("Table I", "both", "100 genomes, 50 iterations, elitism 2 %, crossover 0.85, weight "
          "mutation 0.25, node addition 0.05 (UGV) / 0.08, edge addition 0.03 / 0.5",
          _table_one),
    Claim("Fig. 7", "ugv", "the dual stage's Pareto front shows a significant trade-off "
          "between performance F and experience gain G", _pareto("ugv")),
    Claim("Fig. 8", "ugv", "the single stage eventually outperforms the dual stage",
          _dual_against_single("ugv", final_best_f, "final best F", dual_higher=False)),
    Claim("Fig. 8", "ugv", "the dual stage's performance rises faster at first",
          _early_rate("ugv")),
    Claim("Fig. 9", "ugv", "dual stage: the largest niche holds 25-35 % of the population",
          _niches("ugv", "dual")),
    Claim("Fig. 10", "ugv", "single stage: the largest niche holds 25-35 % of the population",
          _niches("ugv", "single")),
    Claim("Figs. 11-12", "ugv", "on average, less complex networks perform slightly better",
          _complexity_sign("ugv", "dual")),
    Claim("Figs. 11-12", "ugv", "the dual stage's most complex network outperforms the single "
          "stage's", _dual_against_single("ugv", most_complex_f, "F of the most complex network",
                                          dual_higher=True)),
    Claim("Fig. 13", "swarm", "the dual stage's Pareto front shows a significant trade-off "
          "between F and G", _pareto("swarm")),
    Claim("Fig. 13", "both", "the Swarm-Robot's experience gain is lower than the UGV's "
          "(fewer sensors)", _lower_gain),
    Claim("Fig. 14", "swarm", "the dual stage outperforms the single stage",
          _dual_against_single("swarm", final_best_f, "final best F", dual_higher=True)),
    Claim("Fig. 15", "swarm", "dual stage: the largest niche holds at most 25 %",
          _niches("swarm", "dual")),
    Claim("Fig. 16", "swarm", "single stage: the largest niche holds at most 25 %",
          _niches("swarm", "single")),
    Claim("Fig. 17", "swarm", "dual stage: performance falls with complexity",
          _complexity_sign("swarm", "dual")),
    Claim("Figs. 17-18", "swarm", "less complex networks vary more in performance",
          _variance_by_complexity),
    Claim("Sec. IV-C", "both", "the Swarm-Robot converges to a higher objective than the UGV",
          _higher_objective),
    Claim("Sec. IV-D", "both", "the unseen test: 12 m x 12 m (UGV) and 4 m x 4 m worlds, 10 "
          "start/goal pairs, the goal reached within 1 m, 50 s", _unseen_setting),
    Claim("Sec. IV-D", "ugv", "unseen worlds: both fail (single 0 of 10, dual 1 of 10)",
          _unseen("ugv", most=0.2, least=None)),
    Claim("Sec. IV-D", "swarm", "unseen worlds: both reach the goal in several of 10",
          _unseen("swarm", most=None, least=0.2)),
    Claim("Sec. IV-D", "swarm", "unseen worlds: the dual stage reaches the goal faster, the "
          "single stage survives more often", _speed_and_survival),
    Claim("Sec. IV-D, V", "ugv", "unseen worlds: the dual stage does as well as or better than "
          "the single stage", _unseen_dual_vs_single("ugv")),
    Claim("Sec. IV-D, V", "swarm", "unseen worlds: the dual stage does as well as or better "
          "than the single stage", _unseen_dual_vs_single("swarm")),
)

__all__ = [
    "CLAIMS",
    "NICHE_RANGE",
    "ROBOT_NAMES",
    "SETTLING",
    "Claim",
    "Finding",
    "best_f_at",
    "final_best_f",
    "final_population",
    "front_size",
    "largest_shares",
    "most_complex_f",
    "rank_correlation",
    "stage_one_evaluations",
]
