"""A small ``mentor-bench`` document whose contenders' scores add up from their per-pair
results, for the report's tests (head to head, path efficiency)."""

from __future__ import annotations

from typing import Any

import numpy as np


def bench_doc(outcomes: dict[str, list[tuple[bool, float]]], n: int = 20) -> dict[str, Any]:
    """Per contender a (reached, path length m) per pair; pairs of 2 m, half rooms then half
    forest; names starting with ``bug`` are baselines, the others evolved."""
    families = ["rooms", "forest"]
    pairs = [{"family": families[i * 2 // n], "shortest": 2.0, "time_limit": 12.0}
             for i in range(n)]  # fmt: skip
    contenders = []
    for name, runs in outcomes.items():
        results = [{"reached": r, "steps": 10, "path_length": p} for r, p in runs]
        per = {}
        for fam in [*families, "overall"]:
            idx = [i for i, q in enumerate(pairs) if fam in ("overall", q["family"])]
            per[fam] = {"success": float(np.mean([runs[i][0] for i in idx])),
                        "spl": float(np.mean([2.0 / max(runs[i][1], 2.0) if runs[i][0] else 0.0
                                              for i in idx]))}  # fmt: skip
        kind = "baseline" if name.startswith("bug") else "evolved"
        contenders.append({"name": name, "kind": kind, "settings": {"control_period": 0.5},
                           "scores": {"paper": per, "scaled": per}, "results": results})
    return {"families": families, "pairs": pairs, "paper_limit": 50.0,
            "contenders": contenders}
