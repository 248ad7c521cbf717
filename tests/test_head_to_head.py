"""Head to head (report/head_to_head.py): each evolved planner against the best baseline
variant per family, as issue 15 asks a user to see at a glance."""

from __future__ import annotations

from typing import Any

import pytest
from bench_doc_support import bench_doc

from mentor_core.report.head_to_head import baseline_choice, head_to_head, head_to_head_markdown


def _contender(name: str, kind: str, scores: dict[str, tuple[float, float]]) -> dict[str, Any]:
    per = {f: {"success": s, "spl": p} for f, (s, p) in scores.items()}
    return {"name": name, "kind": kind, "scores": {"paper": per, "scaled": per}}


def _doc() -> dict[str, Any]:
    return {
        "families": ["rooms", "forest"],
        "contenders": [
            _contender("dual-s1", "evolved", {"rooms": (0.9, 0.6), "forest": (1.0, 0.7),
                                              "overall": (0.95, 0.65)}),
            _contender("dual-s2", "evolved", {"rooms": (0.8, 0.7), "forest": (0.9, 0.9),
                                              "overall": (0.85, 0.8)}),
            _contender("lone", "evolved", {"rooms": (0.5, 0.4), "forest": (0.5, 0.4),
                                           "overall": (0.5, 0.4)}),
            _contender("vfh", "baseline", {"rooms": (0.7, 0.65), "forest": (1.0, 0.95),
                                           "overall": (0.85, 0.8)}),
            _contender("mapped-bug", "baseline", {"rooms": (0.85, 0.5), "forest": (0.95, 0.8),
                                                  "overall": (0.9, 0.65)}),
            # the oracle sets no bar: it knows the map
            _contender("oracle", "oracle", {"rooms": (1.0, 0.99), "forest": (1.0, 0.99),
                                            "overall": (1.0, 0.99)}),
        ],
    }


def test_each_family_is_met_by_the_best_baseline_on_each_score() -> None:
    versus = head_to_head(_doc())
    assert list(versus) == ["dual", "lone"]  # seeds pooled; a lone planner on its own
    rooms, forest, overall = versus["dual"]
    assert (rooms.family, forest.family, overall.family) == ("rooms", "forest", "overall")
    # the seeds' mean: success 0.85, SPL 0.65 in the rooms
    assert (rooms.success, rooms.spl) == pytest.approx((0.85, 0.65))
    # best success and best SPL come from different baselines
    assert (rooms.best_success, rooms.best_success_by) == (0.85, "mapped-bug")
    assert (rooms.best_spl, rooms.best_spl_by) == (0.65, "vfh")
    assert rooms.success_margin == pytest.approx(0.0) and rooms.spl_margin == pytest.approx(0.0)
    assert rooms.level_on_success and rooms.level_on_spl and not rooms.beats
    # forest: 0.95 against vfh's 1.0; SPL 0.8 against 0.95
    assert forest.best_success_by == "vfh" and forest.success_margin == pytest.approx(-0.05)
    assert not forest.level_on_success and not forest.level_on_spl
    # overall: success 0.9 ties mapped-bug's; SPL 0.725 trails vfh's 0.8
    assert overall.level_on_success and overall.best_success_by == "mapped-bug"
    assert overall.spl_margin == pytest.approx(0.725 - 0.8)
    lone = versus["lone"][0]
    assert lone.success == 0.5 and lone.success_margin == pytest.approx(-0.35)


def test_a_planner_above_both_bars_beats_the_baseline() -> None:
    doc = _doc()
    doc["contenders"][0]["scores"]["paper"]["forest"] = {"success": 1.0, "spl": 1.0}
    doc["contenders"][1]["scores"]["paper"]["forest"] = {"success": 1.0, "spl": 1.0}
    forest = head_to_head(doc)["dual"][1]
    # ties on success (1.0 against vfh's 1.0) is not a win: beats needs both strictly above
    assert forest.level_on_success and not forest.beats
    doc["contenders"][3]["scores"]["paper"]["forest"] = {"success": 0.9, "spl": 0.95}
    assert head_to_head(doc)["dual"][1].beats


def test_the_markdown_names_the_bars_and_counts_the_families() -> None:
    md = "\n".join(head_to_head_markdown(_doc()))
    assert ("| rooms | 85.0 % / 0.65 | 85.0 % (mapped-bug) | 0.65 (vfh) | +0.0 ties | "
            "+0.000 ties |") in md
    assert "| forest | 95.0 % / 0.80 | 100.0 % (vfh) | 0.95 (vfh) | -5.0 trails |" in md
    assert ("`dual` (mean of 2 seeds) leads or ties the best baseline on success in 1 of 2 "
            "families, on SPL in 1 of 2, and beats it on both in 0 of 2.") in md
    assert "`lone` leads or ties the best baseline on success in 0 of 2" in md


def test_no_baseline_no_head_to_head() -> None:
    doc = _doc()
    doc["contenders"] = [c for c in doc["contenders"] if c["kind"] != "baseline"]
    assert head_to_head(doc) == {} and head_to_head_markdown(doc) == []


def test_a_missing_score_is_skipped_not_counted_as_a_best() -> None:
    doc = _doc()
    doc["contenders"][3]["scores"]["paper"]["rooms"] = {"success": None, "spl": None}
    rooms = head_to_head(doc)["dual"][0]
    assert rooms.best_success_by == rooms.best_spl_by == "mapped-bug"


def test_a_family_without_scores_shows_a_dash() -> None:
    doc = _doc()
    for i in (0, 1):  # neither seed scored in the rooms
        doc["contenders"][i]["scores"]["paper"]["rooms"] = {"success": None, "spl": None}
    rooms = head_to_head(doc)["dual"][0]
    assert not rooms.level_on_success and not rooms.beats
    assert "| rooms | - / - | 85.0 % (mapped-bug) | 0.65 (vfh) | - | - |" in "\n".join(
        head_to_head_markdown(doc))


def test_margins_carry_a_paired_bootstrap_interval() -> None:
    n = 20
    # rooms: the planner reaches every pair, the baseline none; forest: both reach all,
    # the planner along paths 1.25 times the shortest, the baseline along the shortest
    mine = [(True, 2.0)] * (n // 2) + [(True, 2.5)] * (n // 2)
    bug = [(False, 9.0)] * (n // 2) + [(True, 2.0)] * (n // 2)
    doc = bench_doc({"dual-s1": mine, "dual-s2": mine, "bug": bug}, n)
    rooms, forest, overall = head_to_head(doc)["dual"]
    assert rooms.success_interval == (1.0, 1.0) and rooms.success_verdict == "leads"
    assert forest.success_interval == (0.0, 0.0) and forest.success_verdict == "level"
    assert forest.spl_interval == pytest.approx((-0.2, -0.2)) and forest.spl_verdict == "trails"
    assert overall.success_interval == (0.5, 0.5)  # stratified: each family keeps its pairs
    md = "\n".join(head_to_head_markdown(doc))
    assert "+100.0 leads (+100.0 to +100.0)" in md and "-0.200 trails (-0.200 to -0.200)" in md
    assert "leads on success in 1 and trails in 0; on SPL it leads in 1 and trails in 1" in md


def test_without_per_pair_results_the_margins_have_no_interval() -> None:
    rooms = head_to_head(_doc())["dual"][0]
    assert rooms.success_verdict == "-" and rooms.spl_verdict == "-"
    md = "\n".join(head_to_head_markdown(_doc()))
    assert " to " not in md and "Beyond the 95 %" not in md


def test_a_choice_from_another_run_sets_the_bars() -> None:
    doc = _doc()
    choice = baseline_choice(doc)
    assert choice["rooms"] == {"success": "mapped-bug", "spl": "vfh"}
    assert choice["forest"] == {"success": "vfh", "spl": "vfh"}
    # another run chose vfh everywhere: its rooms bar is vfh's 0.7, not the best 0.85
    everywhere = {f: {"success": "vfh", "spl": "vfh"} for f in ["rooms", "forest", "overall"]}
    rooms = head_to_head(doc, choice=everywhere)["dual"][0]
    assert (rooms.best_success, rooms.best_success_by) == (0.7, "vfh")
    assert rooms.success_margin == pytest.approx(0.15)
    md = "\n".join(head_to_head_markdown(doc, choice=everywhere))
    assert "chosen baseline: success" in md and "leads or ties the chosen baseline" in md
    with pytest.raises(ValueError, match="'astar' for rooms success"):
        head_to_head(doc, choice={**everywhere, "rooms": {"success": "astar", "spl": "vfh"}})
    with pytest.raises(ValueError, match="no baseline"):
        baseline_choice({"families": [], "contenders": []})
