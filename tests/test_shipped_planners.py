"""The planners shipped in ``planners/`` (planners/README.md): each is the best genome of a
shipped paper-scale config's run, acts with that config's planner settings (so a change of the
config that leaves them stale fails here), is the file README.md lists by its sha256, and, as
the shipped deployment runs it (on its scan map, behind the rotation shim and the collision
guard), reaches goals in an empty world from any heading."""

from __future__ import annotations

import hashlib
import math
import re
from pathlib import Path

import numpy as np
import pytest

from mentor_core.benchmark.contenders import evolved
from mentor_core.controller.collision_guard import CollisionGuardStage
from mentor_core.controller.deployment import load_deployment
from mentor_core.controller.episodes import run_episodes
from mentor_core.controller.rotation_shim import RotationShim
from mentor_core.files.genome_file import load_genome_and_metadata
from mentor_core.runtime.planner import planner_profile
from mentor_core.sim.planner_settings import with_planner
from mentor_core.sim.robots import get_profile
from mentor_core.sim.world import Scenario, World
from mentor_core.training.config import shipped_config

PLANNERS = Path(__file__).resolve().parents[1] / "planners"
NAME = re.compile(r"(?P<robot>ugv|swarm)-paper-(?P<framework>single|dual)-s(?P<seed>\d+)\.json")
FILES = sorted(PLANNERS.glob("*.json"))


def test_the_headline_planners_are_shipped() -> None:
    names = {f.name for f in FILES}
    for seed in (1, 2, 3):
        assert f"ugv-paper-dual-s{seed}.json" in names
        assert f"ugv-paper-single-s{seed}.json" in names
        assert f"swarm-paper-dual-s{seed}.json" in names
    assert all(NAME.fullmatch(name) for name in names), names


@pytest.mark.parametrize("path", FILES, ids=[f.name for f in FILES])
def test_a_shipped_planner_acts_with_its_shipped_config_settings(path: Path) -> None:
    match = NAME.fullmatch(path.name)
    assert match is not None
    robot = get_profile(match["robot"])
    _, metadata = load_genome_and_metadata(path)
    assert metadata["robot"] == match["robot"]
    assert metadata["framework"] == match["framework"]
    assert metadata["seed"] == int(match["seed"])
    settings = shipped_config(match["robot"]).planner_settings()
    expected = with_planner(robot, **settings)
    actual = planner_profile(robot, metadata, path)
    for key in settings:
        want, got = getattr(expected, key), getattr(actual, key)
        if isinstance(want, float):
            assert got == pytest.approx(want, abs=1e-12), key
        else:
            assert got == want, key


def test_the_readme_lists_each_shipped_planner_by_its_sha256() -> None:
    listed = dict(re.findall(r"`([a-z]+-paper-[a-z]+-s\d+\.json)` \| `([0-9a-f]{64})`",
                             (PLANNERS / "README.md").read_text()))  # fmt: skip
    assert set(listed) == {f.name for f in FILES}
    for path in FILES:
        assert hashlib.sha256(path.read_bytes()).hexdigest() == listed[path.name], path.name


@pytest.mark.parametrize("robot_name", ["ugv", "swarm"])
def test_a_shipped_planner_as_deployed_reaches_goals_in_an_empty_world(robot_name: str) -> None:
    robot = get_profile(robot_name)
    path = PLANNERS / f"{robot_name}-paper-dual-s1.json"
    shipped, _ = load_deployment("shipped", robot_name)
    contender = evolved(path, robot, deployment=shipped)
    assert contender.name == str(path)  # the label stays: no prefix for the deployment
    assert RotationShim(threshold_deg=45.0) in contender.stages
    assert CollisionGuardStage(memory=3) in contender.stages and contender.guide is not None
    size = robot.test_arena
    world = World(size)
    rng = np.random.default_rng(0)
    scenarios = []
    while len(scenarios) < 6:
        start, goal = rng.uniform(0.15 * size, 0.85 * size, (2, 2))
        if math.dist(start, goal) >= size / 4:
            heading = rng.uniform(-math.pi, math.pi)
            scenarios.append(Scenario(world, (start[0], start[1], heading), tuple(goal)))
    batch = run_episodes(scenarios, contender.profile, contender.policy(scenarios),
                         time_budgets=50.0, input_goals=contender.input_goals(scenarios),
                         stages=contender.stages)  # fmt: skip
    assert batch.reached.all() and not batch.collided.any()
