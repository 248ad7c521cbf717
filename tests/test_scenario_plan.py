"""Scenario sources (world file, scenario bag, ROS map, training DoE), the world as the map
the simulator publishes, and who runs what when."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from mentor_core.errors import ConfigError, FileFormatError
from mentor_core.files.bags import write_scenario_bag
from mentor_core.navigation.grid import world_grid
from mentor_core.navigation.map_file import save_map
from mentor_core.runtime.scenario_plan import (
    MAP_SCENARIOS,
    ScenarioPlan,
    ScenarioSource,
    load_scenario_source,
    source_map,
)
from mentor_core.sim.robots import get_profile
from mentor_core.sim.world import Scenario, World, save_world

UGV = get_profile("ugv")
SWARM = get_profile("swarm")


@pytest.fixture
def world() -> World:
    return World(5.0, np.array([[2.0, 2.0, 3.0, 3.0]]), name="box")


@pytest.fixture
def scenarios(world: World) -> list[Scenario]:
    return [
        Scenario(world, (0.5, 0.5, 0.0), (4.5, 4.5)),
        Scenario(world, (2.0, 1.9, 0.0), (4.5, 0.5)),  # centre outside, UGV body in the box
        Scenario(world, (4.5, 0.5, 1.0), (0.5, 4.5)),
    ]


def test_sources(tmp_path: Path, world: World, scenarios: list[Scenario]) -> None:
    save_world(tmp_path / "w.yaml", world, scenarios)
    src = load_scenario_source(world_file=tmp_path / "w.yaml")
    assert src.world == world and list(src.scenarios) == scenarios
    assert src.origin == str(tmp_path / "w.yaml")
    write_scenario_bag(tmp_path / "bag", world, scenarios, "ugv")
    src = load_scenario_source(scenario_bag=tmp_path / "bag")
    assert src.world == world and len(src.scenarios) == 3
    src = load_scenario_source(profile=SWARM, seed=4)
    assert len(src.scenarios) == SWARM.train_scenarios and "seed 4" in src.origin
    assert src.world.size == SWARM.train_arena


def test_bad_sources(tmp_path: Path, world: World) -> None:
    with pytest.raises(ConfigError, match="only one of"):
        load_scenario_source("a.yaml", "b")
    with pytest.raises(ConfigError, match="only one of"):
        load_scenario_source(scenario_bag="b", map_yaml="m.yaml")
    with pytest.raises(FileFormatError, match=r"m\.yaml: no such file"):
        load_scenario_source(map_yaml=tmp_path / "m.yaml", profile=SWARM)
    with pytest.raises(ConfigError):
        load_scenario_source()
    with pytest.raises(FileFormatError, match=r"missing\.yaml"):
        load_scenario_source(world_file=tmp_path / "missing.yaml")
    save_world(tmp_path / "empty.yaml", world)
    with pytest.raises(FileFormatError, match="no scenarios"):
        load_scenario_source(world_file=tmp_path / "empty.yaml")
    (tmp_path / "inside.yaml").write_text(
        "format: mentor-world\nversion: 1\nsize: 5.0\nobstacles: [[1, 1, 2, 2]]\n"
        "scenarios:\n  - {start: [1.5, 1.5, 0.0], goal: [4, 4]}\n"
    )
    with pytest.raises(FileFormatError, match=r"inside\.yaml: scenarios\[0\]: start .* inside"):
        load_scenario_source(world_file=tmp_path / "inside.yaml")
    with pytest.raises(FileFormatError, match="no such bag"):
        load_scenario_source(scenario_bag=tmp_path / "nobag")


def test_a_map_is_a_source_and_the_world_is_published_on_its_cells(
    tmp_path: Path, world: World, scenarios: list[Scenario]
) -> None:
    save_map(tmp_path / "m.yaml", world_grid(world, 0.25))
    src = load_scenario_source(map_yaml=tmp_path / "m.yaml", profile=SWARM, seed=2)
    assert len(src.scenarios) == MAP_SCENARIOS and "seed 2" in src.origin
    assert src.map_resolution == 0.25 and src.world.size == world.size
    assert src == load_scenario_source(map_yaml=tmp_path / "m.yaml", profile=SWARM, seed=2)
    assert source_map(src, 0.1) == world_grid(world, 0.25)  # the map's own cells
    # a world file naming the map: its scenarios on the map's world
    (tmp_path / "w.yaml").write_text(
        "format: mentor-world\nversion: 1\nmap: m.yaml\n"
        "scenarios: [{start: [4.5, 0.5, 1.0], goal: [0.5, 4.5]}]\n"
    )
    named = load_scenario_source(world_file=tmp_path / "w.yaml")
    assert named.world.obstacles.tolist() == src.world.obstacles.tolist()
    assert named.map_resolution == 0.25
    plain = ScenarioSource(world, tuple(scenarios), "w.yaml")
    assert source_map(plain, 0.1) == world_grid(world, 0.1)


def test_plan_skips_what_a_robot_cannot_start(world: World, scenarios: list[Scenario]) -> None:
    src = ScenarioSource(world, tuple(scenarios), "w.yaml")
    plan = ScenarioPlan(src, [("a", UGV), ("b", SWARM)], time_limit=50.0)
    assert plan.runnable == ((0, 2), (0, 1, 2))
    assert len(plan.skipped) == 1 and plan.skipped[0].startswith("scenario 1 skipped for a (ugv)")
    first = plan.setups(0)
    assert [(s.name, s.scenario) for s in first] == [("a", 0), ("b", 1)]
    assert all(s.time_budget == 50.0 for s in first)
    assert [(s.name, s.scenario) for s in plan.setups(1)] == [("a", 0), ("b", 0)]
    assert plan.setups(0)[1].start == scenarios[1].start


def test_plan_fails_when_a_robot_can_start_nowhere(
    world: World, scenarios: list[Scenario]
) -> None:
    src = ScenarioSource(world, (scenarios[1],), "w.yaml")
    with pytest.raises(FileFormatError, match=r"w\.yaml: no scenario can start robot a \(ugv\)"):
        ScenarioPlan(src, [("a", UGV)])
    with pytest.raises(ConfigError):
        ScenarioPlan(src, [])


def test_robots_of_another_profile_get_missions_of_their_own_scale() -> None:
    """Failed before: a Swarm-Robot beside a UGV was sent on the UGV's 12 m missions."""
    source = load_scenario_source(profile=UGV, seed=3)
    plan = ScenarioPlan(source, [("ugv_0", UGV), ("swarm_0", SWARM)])
    ugv, swarm = plan.missions
    assert ugv == source.scenarios and len(swarm) == len(ugv)
    reach = [np.hypot(s.goal[0] - s.start[0], s.goal[1] - s.start[1]) for s in swarm]
    assert max(reach) <= SWARM.uncapped_distance
    assert all(s.world is source.world for s in swarm)  # one world, shared
    assert plan.setups(0)[1].goal in [s.goal for s in swarm]
    again = ScenarioPlan(load_scenario_source(profile=UGV, seed=3),
                         [("ugv_0", UGV), ("swarm_0", SWARM)])  # fmt: skip
    assert again.missions[1] == swarm  # drawn from the seed


def test_scenarios_of_a_file_are_every_robots(tmp_path: Path, world: World,
                                              scenarios: list[Scenario]) -> None:  # fmt: skip
    save_world(tmp_path / "w.yaml", world, scenarios)
    source = load_scenario_source(world_file=tmp_path / "w.yaml")
    plan = ScenarioPlan(source, [("a", SWARM), ("b", UGV)])
    assert plan.missions[0] == plan.missions[1] == source.scenarios
