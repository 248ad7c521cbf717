"""Where SPL goes (report/path_efficiency.py): SPL is success times the path efficiency; an
evolved planner's paths and the best baseline's, compared on the pairs both reached, with the
median path and the share of detours telling a little longer everywhere from a few much
longer."""

from __future__ import annotations

import math

import numpy as np
import pytest
from bench_doc_support import bench_doc

from mentor_core.report.path_efficiency import (
    efficiency_markdown,
    paired_efficiency,
    path_efficiency,
)


def test_spl_is_success_times_the_path_efficiency() -> None:
    # three reached pairs: along the shortest path, twice it, 1.25 times it; one failed
    success = np.array([True, True, True, False])
    terms = np.array([1.0, 0.5, 0.8, 0.0])
    e = path_efficiency(success, terms)
    assert e.reached == 3
    assert e.efficiency == pytest.approx((1.0 + 0.5 + 0.8) / 3)
    assert success.mean() * e.efficiency == pytest.approx(terms.mean())  # SPL
    assert e.median_ratio == pytest.approx(1.25)
    assert e.detour_share == pytest.approx(1 / 3)  # 1.25 itself is no detour: only the 2


def test_no_pair_reached_has_no_efficiency() -> None:
    e = path_efficiency([False, False], [0.0, 0.0])
    assert e.reached == 0 and math.isnan(e.efficiency) and math.isnan(e.median_ratio)


def test_paths_are_compared_on_the_pairs_both_reached() -> None:
    n = 20  # pairs 0-9 rooms, 10-19 forest, each 2 m
    # rooms: seed 1 reaches all along the shortest path, seed 2 the first five; the baseline
    # the first five along 1.25 times it. Forest: seed 1 every path 1.1 times the shortest,
    # seed 2 one at 3 times and the rest along it; the baseline all along it.
    s1 = [(True, 2.0)] * 10 + [(True, 2.2)] * 10
    s2 = [(True, 2.0)] * 5 + [(False, 9.0)] * 5 + [(True, 6.0)] + [(True, 2.0)] * 9
    bug = [(True, 2.5)] * 5 + [(False, 9.0)] * 5 + [(True, 2.0)] * 10
    # a second baseline, below the first on SPL in both families: not the bar
    slow = [(False, 9.0)] * 10 + [(True, 2.5)] * 10
    doc = bench_doc({"dual-s1": s1, "dual-s2": s2, "bug": bug, "bug-slow": slow}, n)
    rooms, forest, overall = paired_efficiency(doc)["dual"]
    assert (rooms.baseline, forest.baseline) == ("bug", "bug")
    # rooms: the baseline's five pairs, for each seed; its paths are the longer ones here
    assert rooms.mine.reached == rooms.theirs.reached == 10
    assert (rooms.mine.efficiency, rooms.mine.median_ratio) == (1.0, 1.0)
    assert rooms.theirs.efficiency == pytest.approx(0.8)
    assert rooms.theirs.median_ratio == pytest.approx(1.25)
    # forest: nine at 1.0, ten at 1.1, one at 3.0 -> median 1.1, one detour in twenty
    assert forest.mine.reached == 20
    assert forest.mine.median_ratio == pytest.approx(1.1)
    assert forest.mine.detour_share == pytest.approx(1 / 20)
    assert forest.mine.efficiency == pytest.approx((9 + 10 / 1.1 + 1 / 3) / 20)
    assert forest.theirs.efficiency == 1.0 and forest.theirs.detour_share == 0.0
    assert overall.mine.reached == 30
    md = "\n".join(efficiency_markdown(doc))
    assert "| family | pairs both reached | `dual` | baseline of the highest SPL |" in md
    assert "| rooms | 10 | 1.00 · 1.00 · 0 % | 0.80 · 1.25 · 0 % (bug) |" in md
    assert (f"| forest | 20 | {forest.mine.efficiency:.2f} · 1.10 · 5 % | "
            "1.00 · 1.00 · 0 % (bug) |") in md  # fmt: skip


def test_without_per_pair_results_or_a_baseline_there_is_nothing_to_compare() -> None:
    doc = bench_doc({"dual-s1": [(True, 2.0)] * 4, "bug": [(True, 2.0)] * 4}, 4)
    assert len(paired_efficiency(doc)["dual-s1"]) == 3
    assert paired_efficiency(bench_doc({"dual-s1": [(True, 2.0)] * 4}, 4)) == {}
    for c in doc["contenders"]:
        c["results"] = [{"reached": True} for _ in c["results"]]  # an older document's
    assert paired_efficiency(doc) == {} and efficiency_markdown(doc) == []
