"""Following a global plan: the goal the network sees (carrot, final goal, replans), and a
dead end where the plain planner fails and the planner with a global plan reaches the goal."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from mentor_core.files.genome_file import load_genome_and_metadata
from mentor_core.navigation.grid import world_grid
from mentor_core.navigation.guide import (
    GuideConfig,
    PathGuide,
    guide_config,
    guided_goals,
    world_guides,
)
from mentor_core.runtime.planner import planner_profile
from mentor_core.sim.robots import get_profile
from mentor_core.sim.world import Scenario, World
from mentor_core.training.assessment import assess

ROOT = Path(__file__).resolve().parents[1]
UGV_GENOME = ROOT / "bags" / "regression" / "ugv_reference_genome.json"
CONFIG = GuideConfig(lookahead=1.0, replan_distance=1.5, radius=0.2, margin=0.1, resolution=0.05)
# a U open towards the start, its back wall between start and goal: a dead end
DEAD_END = World(
    12.0, np.array([[7.0, 3.5, 7.3, 8.5], [4.5, 3.5, 7.3, 3.8], [4.5, 8.2, 7.3, 8.5]])
)
OPEN = World(12.0, np.zeros((0, 4)))


def _guide(world: World = OPEN) -> PathGuide:
    guide = PathGuide(CONFIG)
    guide.set_map(world_grid(world, CONFIG.resolution))
    return guide


def test_the_carrot_lies_a_lookahead_along_the_plan_then_the_goal() -> None:
    guide = _guide()
    # the network sees the carrot's direction at the distance still to go: here the goal
    assert guide.target((1.0, 1.0), (9.0, 1.0)) == pytest.approx((9.0, 1.0))
    assert guide.carrot == pytest.approx((2.0, 1.0))
    assert guide.revision == 1 and guide.path is not None
    aim = guide.target((5.0, 1.2), (9.0, 1.0))
    assert guide.carrot == pytest.approx((6.0, 1.0))
    assert math.dist((5.0, 1.2), aim) == pytest.approx(4.0)  # 4 m to go along the path
    np.testing.assert_allclose(np.subtract(aim, (5.0, 1.2)) / 4.0, (0.98058, -0.19612), 1e-4)
    # within a lookahead of the path's end: the final goal itself
    assert guide.target((8.2, 1.0), (9.0, 1.0)) == (9.0, 1.0) and guide.carrot is None
    assert guide.revision == 1  # no replan on the way


def test_without_a_map_or_a_path_the_goal_is_the_final_goal() -> None:
    assert PathGuide(CONFIG).target((1.0, 1.0), (9.0, 1.0)) == (9.0, 1.0)


def test_round_the_dead_end_the_carrot_is_in_sight() -> None:
    guide = _guide(DEAD_END)
    start, goal = (3.0, 6.0), (10.0, 6.0)
    aim = guide.target(start, goal)
    carrot = guide.carrot
    # not into the U (its mouth faces the start) but up round its arm: the carrot lies
    # before the mouth, in sight, and the network is told to head up, not east
    assert carrot is not None and carrot[0] < 4.5 and carrot[1] > 6.5
    assert math.dist(carrot, start) <= CONFIG.lookahead + 1e-9
    assert guide.planner is not None and guide.planner.visible(start, carrot)
    heading = math.atan2(aim[1] - start[1], aim[0] - start[0])
    assert math.radians(45) < heading < math.radians(90)
    assert guide.path is not None
    assert guide.path[:, 1].min() < 3.5 or guide.path[:, 1].max() > 8.5


def test_a_given_path_is_followed_until_the_goal_changes() -> None:
    guide = PathGuide(CONFIG)
    guide.set_path([(0.0, 0.0), (0.0, 5.0), (5.0, 5.0)])  # before any goal: adopted by it
    guide.target((0.1, 1.0), (5.0, 5.0))
    assert guide.carrot == pytest.approx((0.0, 2.0))
    # strayed far from it: with no map the given path stays
    guide.target((2.0, 2.0), (5.0, 5.0))
    assert guide.carrot == pytest.approx((0.0, 3.0))
    # a new goal drops the given path: no map, so straight to the goal
    assert guide.target((0.1, 1.0), (1.0, 9.0)) == (1.0, 9.0)
    assert guide.path is None


def test_straying_from_the_path_plans_again_from_where_the_robot_is() -> None:
    guide = _guide()
    guide.target((1.0, 1.0), (9.0, 1.0))
    guide.target((4.0, 4.0), (9.0, 1.0))  # 3 m off the path
    assert guide.revision == 2
    assert guide.path is not None and guide.path[0] == pytest.approx((4.0, 4.0))
    assert guide.carrot is not None
    assert math.dist(guide.carrot, (4.0, 4.0)) == pytest.approx(CONFIG.lookahead)


def test_a_goal_with_no_plan_is_steered_to_directly_and_not_planned_again() -> None:
    closed = World(12.0, np.array([[8.0, 0.0, 8.2, 12.0]]))  # the goal's side is cut off
    guide = _guide(closed)
    calls = 0
    plan = guide.planner.plan  # type: ignore[union-attr]

    def counting(start: object, goal: object) -> object:
        nonlocal calls
        calls += 1
        return plan(start, goal)  # type: ignore[arg-type]

    guide.planner.plan = counting  # type: ignore[union-attr, method-assign]
    for x in (1.0, 2.0, 3.0):
        assert guide.target((x, 1.0), (10.0, 1.0)) == (10.0, 1.0)
    assert calls == 1


def test_guide_defaults_scale_with_the_robot() -> None:
    ugv, swarm = guide_config(get_profile("ugv")), guide_config(get_profile("swarm"))
    assert ugv.lookahead == 2.0 and ugv.radius == get_profile("ugv").half_diagonal
    assert ugv.resolution == 0.048 and swarm.resolution == 0.012
    assert swarm.lookahead == pytest.approx(2 * get_profile("swarm").goal_radius)
    with pytest.raises(ValueError, match="lookahead"):
        guide_config(get_profile("ugv"), lookahead=0.0)
    # a hard disc unless a clearance cost is asked; the least margin within the margin
    assert ugv.clearance_cost == 0.0 and ugv.hard_inflation == ugv.inflation
    costly = guide_config(get_profile("ugv"), least_margin=0.1, clearance_cost=1.0)
    assert costly.planner(world_grid(World(4.0, np.zeros((0, 4))), 0.1)).preferred == (
        pytest.approx(costly.inflation))
    assert costly.hard_inflation == pytest.approx(costly.radius + 0.1)
    with pytest.raises(ValueError, match="least_margin"):
        guide_config(get_profile("ugv"), least_margin=0.3)
    with pytest.raises(ValueError, match="clearance_cost"):
        guide_config(get_profile("ugv"), clearance_cost=-1.0)


def test_in_a_dead_end_the_plain_planner_fails_and_the_global_plan_reaches_the_goal() -> None:
    genome, metadata = load_genome_and_metadata(UGV_GENOME)
    profile = planner_profile(get_profile("ugv"), metadata)
    scenarios = [
        Scenario(DEAD_END, (2.0, 6.0, 0.0), (10.0, 6.0)),
        Scenario(DEAD_END, (1.0, 5.0, 0.5), (10.5, 6.5)),
    ]
    plain = assess(genome, profile, scenarios)
    assert not any(r.reached for r in plain.results)  # stuck in the U
    config = guide_config(profile)
    guides = world_guides(DEAD_END, config, len(scenarios))
    guided = assess(
        genome, profile, scenarios, input_goals=guided_goals(guides, [s.goal for s in scenarios])
    )
    assert all(r.reached for r in guided.results)
    # the robots went round the U: past its arms' ends, above or below it
    for r in guided.results:
        y = r.trajectory[:, 1]
        assert y.min() < 3.5 or y.max() > 8.5
