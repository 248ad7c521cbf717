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


def evolved_planners(contenders: Sequence[Mapping[str, Any]]) -> dict[str, list[int]]:
    """Indices of each evolved planner: its :func:`seed_groups` group under ``<name>``, then
    every other evolved contender alone under its own name."""
    groups = seed_groups(contenders)
    grouped = {i for idx in groups.values() for i in idx}
    return groups | {str(c["name"]): [i] for i, c in enumerate(contenders)
                     if c["kind"] == "evolved" and i not in grouped}  # fmt: skip
