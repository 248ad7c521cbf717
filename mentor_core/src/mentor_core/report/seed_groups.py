"""Evolved planners over their seeds: ``mentor-bench`` contenders labelled ``<name>-s<seed>``
(``mentor-bench --label``) are one planner trained with several seeds, reported as the mean
and spread of the seeds (``report.bench``, ``report.head_to_head``)."""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from typing import Any

_SEEDED = re.compile(r"^(?P<name>.+)-s(?P<seed>\d+)$")


def seed_groups(contenders: Sequence[Mapping[str, Any]]) -> dict[str, list[int]]:
    """Indices of the evolved contenders named ``<name>-s<seed>``, by name, for names with
    at least two seeds (in first-seen order)."""
    groups: dict[str, list[int]] = {}
    for i, c in enumerate(contenders):
        match = _SEEDED.match(str(c["name"]))
        if c["kind"] == "evolved" and match:
            groups.setdefault(match["name"], []).append(i)
    return {name: idx for name, idx in groups.items() if len(idx) > 1}
