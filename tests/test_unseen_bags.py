"""bags/unseen: the committed unseen test environments are what the generator script writes."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import numpy as np
import pytest

from mentor_core.files.bags import read_scenario_bag
from mentor_core.sim.robots import get_profile
from mentor_core.sim.scenarios import training_scenarios

ROOT = Path(__file__).resolve().parents[1]
UNSEEN = ROOT / "bags" / "unseen"


def _generator():  # type: ignore[no-untyped-def]
    spec = importlib.util.spec_from_file_location(
        "make_unseen_bags", ROOT / "scripts" / "make_unseen_bags.py"
    )
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module


@pytest.mark.parametrize(("robot", "size"), [("ugv", 12.0), ("swarm", 4.0)])
def test_unseen_bag_is_the_papers_test_setup(robot: str, size: float) -> None:
    world, scenarios, profile_name, meta = read_scenario_bag(UNSEEN / robot)
    assert profile_name == robot and world.size == size
    assert len(scenarios) == 10 and meta["generator"] == "scripts/make_unseen_bags.py"
    profile = get_profile(robot)
    for sc in scenarios:
        d = float(np.hypot(sc.goal[0] - sc.start[0], sc.goal[1] - sc.start[1]))
        assert d >= size / 4 and d > profile.goal_radius  # no pair starts at its goal
    # unlike the training DoE: not one of its obstacles
    train = training_scenarios(profile, seed=0, n=1)[0].world
    assert not any((train.obstacles == box).all(axis=1).any() for box in world.obstacles)


def test_committed_bags_equal_a_fresh_generation(tmp_path: Path) -> None:
    assert _generator().main(["--out", str(tmp_path)]) == 0
    for robot in ("ugv", "swarm"):
        committed = read_scenario_bag(UNSEEN / robot)
        fresh = read_scenario_bag(tmp_path / robot)
        assert committed[0] == fresh[0]
        assert [(s.start, s.goal) for s in committed[1]] == [(s.start, s.goal) for s in fresh[1]]
