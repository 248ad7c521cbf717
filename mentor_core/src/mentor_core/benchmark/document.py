"""The benchmark's result file: JSON, format ``mentor-bench``, version 1.

Top level: ``robot``, ``split``, ``families``, ``pairs_per_family``, ``arena`` (m),
``goal_radius`` (m), ``control_period`` (s), ``paper_limit`` (s), ``scaled_limit`` (the
formula, text), ``reference`` (the reference planner's limits), ``worlds`` (name -> its boxes
``[xmin, ymin, xmax, ymax]``, m), ``pairs`` (family, seed, index, world, start ``[x, y,
theta]``, goal ``[x, y]``, ``shortest`` m, ``time_limit`` s) and ``contenders``: per planner
its ``name``, ``kind`` (evolved, baseline, oracle), ``source`` (genome file), ``settings``
(its action limits and input encoding), ``seconds``, ``scores`` (``{"paper" | "scaled":
{"overall" | family: {success, collision, timeout, time_to_goal, spl}}}``, rates in [0, 1],
time in s, NaN written as null) and ``results`` per pair (``reached``, ``collided``,
``steps``, ``time`` s, ``path_length`` m, ``final_distance`` m, ``trajectory`` ``[[x, y],
...]`` rounded to the millimetre). A pair's episode runs to the longer of its two limits, so
``reached`` and ``collided`` are within that one; ``scores["paper"]`` counts those whose
``steps`` are at most ``ceil(paper_limit / settings.control_period)``, its own period.
Optional: ``baseline_choice`` (``source``, the file of the run it comes from, its ``split``,
and ``choice``: ``{family | "overall": {"success" | "spl": baseline name}}``), the variants
that set the head to head's second bars (``mentor-bench --baselines-chosen-on``).
"""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from mentor_core.benchmark.runner import LIMITS, ContenderResult
from mentor_core.benchmark.scores import SCORE_KEYS
from mentor_core.benchmark.suite import PAPER_LIMIT, Suite
from mentor_core.controller.stage import Stage
from mentor_core.errors import FileFormatError, is_version
from mentor_core.sim.robots import RobotProfile

BENCH_FORMAT = "mentor-bench"
BENCH_VERSION = 1
SCALED_FORMULA = "2 l / v + (pi / h) dt"
_TOP_KEYS = ("robot", "split", "families", "worlds", "pairs", "contenders", "goal_radius",
             "arena")  # fmt: skip
_CONTENDER_KEYS = ("name", "kind", "scores", "results")
_RESULT_KEYS = ("reached", "collided", "time", "trajectory")


def settings(profile: RobotProfile, stages: Sequence[Stage] = ()) -> dict[str, Any]:
    """A planner's action limits and input encoding, as plain values (rad, m, s), and the
    settings of its stages (:meth:`~mentor_core.controller.stage.Stage.record`)."""
    recorded: dict[str, Any] = {}
    for stage in stages:
        recorded.update(stage.record())
    return {
        "input_encoding": profile.input_encoding,
        "heading_change_max": profile.heading_change_max,
        "step_min": profile.step_min,
        "step_max": profile.step_max,
        "clearance_margin": profile.clearance_margin,
        "feedback_action": profile.feedback_action,
        "memory_units": profile.memory_units,
        **({} if profile.proximity_scale is None
           else {"proximity_scale": profile.proximity_scale}),
        "control_period": profile.control_period,
        **recorded,
    }


def _number(x: float) -> float | None:
    return None if math.isnan(x) else float(x)


def bench_document(
    suite: Suite, results: Sequence[ContenderResult], pairs_per_family: int
) -> dict[str, Any]:
    """The JSON document of a benchmark run (module docstring)."""
    worlds: dict[str, list[list[float]]] = {}
    for p in suite.pairs:
        worlds.setdefault(p.scenario.world.name, p.scenario.world.obstacles.tolist())
    first = suite.pairs[0].scenario.world
    return {
        "format": BENCH_FORMAT,
        "version": BENCH_VERSION,
        "robot": suite.robot,
        "split": suite.split,
        "families": list(suite.families),
        "pairs_per_family": pairs_per_family,
        "arena": first.size,
        "goal_radius": suite.reference.goal_radius,
        "control_period": suite.reference.control_period,
        "paper_limit": PAPER_LIMIT,
        "scaled_limit": SCALED_FORMULA,
        "reference": settings(suite.reference),
        "worlds": worlds,
        "pairs": [
            {"family": p.family, "seed": p.seed, "index": p.index,
             "world": p.scenario.world.name, "start": list(p.scenario.start),
             "goal": list(p.scenario.goal), "shortest": p.shortest,
             "time_limit": p.time_limit}
            for p in suite.pairs
        ],
        "contenders": [_contender(r) for r in results],
    }


def _contender(result: ContenderResult) -> dict[str, Any]:
    c, o = result.contender, result.outcomes
    return {
        "name": c.name,
        "kind": c.kind,
        "source": c.source,
        "settings": settings(c.profile, c.stages),
        # the scan map's guide (m), for planners on one
        **({} if c.guide is None else {"scan_map": {
            "lookahead": c.guide.lookahead, "replan_distance": c.guide.replan_distance,
            "margin": c.guide.margin, "least_margin": c.guide.least_margin,
            "clearance_cost": c.guide.clearance_cost, "resolution": c.guide.resolution}}),
        "seconds": result.seconds,
        "scores": {limit: {group: {k: _number(v) for k, v in row.items()}
                           for group, row in table.items()}
                   for limit, table in result.scores.items()},
        "results": [
            {"reached": bool(o.reached[i]), "collided": bool(o.collided[i]),
             "steps": int(o.steps[i]), "time": float(o.time[i]),
             "path_length": float(o.path_length[i]),
             "final_distance": float(o.final_distance[i]),
             "trajectory": [[round(float(x), 3), round(float(y), 3)]
                            for x, y in o.trajectories[i][:, :2]]}
            for i in range(len(o.reached))
        ],
    }


def load_bench(path: str | Path) -> dict[str, Any]:
    """Read and check a benchmark result file; FileFormatError naming the file and the
    fault (missing, not JSON, another format or version, a key missing, lists that do not
    match)."""
    source = Path(path)
    try:
        doc = json.loads(source.read_text(encoding="utf-8"))
    except OSError as err:
        raise FileFormatError(source, f"cannot read benchmark file ({err.strerror})") from None
    except (json.JSONDecodeError, UnicodeDecodeError) as err:
        raise FileFormatError(source, f"not valid JSON ({err})") from None
    if not isinstance(doc, dict) or doc.get("format") != BENCH_FORMAT:
        found = doc.get("format") if isinstance(doc, dict) else None
        raise FileFormatError(source, f"format is {found!r}, not {BENCH_FORMAT!r}")
    if not is_version(doc.get("version"), BENCH_VERSION):
        raise FileFormatError(source, f"version {doc.get('version')!r} is not supported")
    for key in _TOP_KEYS:
        if key not in doc:
            raise FileFormatError(source, f"missing key {key!r}")
    pairs, families = doc["pairs"], doc["families"]
    if not isinstance(pairs, list) or not isinstance(families, list) or not isinstance(
            doc["worlds"], dict) or not isinstance(doc["contenders"], list):
        raise FileFormatError(source, "pairs, families and contenders must be lists, worlds "
                                      "a mapping")  # fmt: skip
    for i, p in enumerate(pairs):
        if not isinstance(p, dict) or p.get("world") not in doc["worlds"] or p.get(
                "family") not in families:
            raise FileFormatError(source, f"pairs[{i}] names no listed world or family")
    for j, c in enumerate(doc["contenders"]):
        if not isinstance(c, dict) or any(k not in c for k in _CONTENDER_KEYS):
            raise FileFormatError(source, f"contenders[{j}] lacks one of "
                                          f"{', '.join(_CONTENDER_KEYS)}")  # fmt: skip
        results = c["results"]
        if not isinstance(results, list) or len(results) != len(pairs) or any(
                not isinstance(r, dict) or any(k not in r for k in _RESULT_KEYS)
                for r in results):
            raise FileFormatError(source, f"contenders[{j}] must have one result per pair")
        for limit in LIMITS:
            table = c["scores"].get(limit) if isinstance(c["scores"], dict) else None
            if not isinstance(table, dict) or any(
                    not isinstance(table.get(g), dict)
                    or any(k not in table[g] for k in SCORE_KEYS)
                    for g in ["overall", *families]):
                raise FileFormatError(source, f"contenders[{j}] lacks the {limit!r} scores")
    chosen = doc.get("baseline_choice")
    if chosen is not None and not (
            isinstance(chosen, dict) and isinstance(chosen.get("choice"), dict)
            and all(isinstance(v, dict) and all(isinstance(v.get(k), str)
                                                for k in ("success", "spl"))
                    for v in chosen["choice"].values())):  # fmt: skip
        raise FileFormatError(source, "baseline_choice must map each family to the names of "
                                      "its success and SPL baselines")  # fmt: skip
    return doc
