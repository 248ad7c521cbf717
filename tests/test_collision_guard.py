"""The collision guard (the stage ``collision_guard`` of a deployment, as ``mentor-bench
--deployment shipped`` runs the UGV's; not in the paper): no arc into what the sensors read
lately, a step back when every arc ahead would hit, and nothing changed when the planner's arc
is free."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from mentor_core.controller.collision_guard import (
    BACKUP_SHARES,
    MEMORY,
    CollisionGuard,
    CollisionGuardStage,
    read_points,
)
from mentor_core.controller.deployment import Deployment, load_deployment
from mentor_core.controller.episodes import run_episodes
from mentor_core.controller.stage import Stage
from mentor_core.errors import ConfigError
from mentor_core.runtime.planner import GenomePlanner
from mentor_core.sim.collision import swept_collision
from mentor_core.sim.planner_settings import with_planner
from mentor_core.sim.robots import RobotProfile, get_profile
from mentor_core.sim.sensors import sensor_readings
from mentor_core.sim.world import Scenario, World

ROOT = Path(__file__).resolve().parents[1]
UGV_GENOME = ROOT / "bags" / "regression" / "ugv_reference_genome.json"
QUARTER = math.pi / 4
# a wall across the arena at x in [5, 5.2]
WALL = World(12.0, np.array([[5.0, 0.0, 5.2, 12.0]]))


def guarded() -> RobotProfile:
    """The planner's profile the guard is tested with (the guard itself is a stage)."""
    return with_planner(get_profile("ugv"), input_encoding="egocentric",
                        heading_change_max=QUARTER, step_max=0.5, step_min=0.02,
                        clearance_margin=0.2)  # fmt: skip


def guard_stages(on: bool = True) -> tuple[Stage, ...]:
    return (CollisionGuardStage(),) if on else ()


def test_read_points_lie_where_the_readings_hit() -> None:
    profile = guarded()
    pose = np.array([[4.0, 6.0, 0.0]])  # facing the wall, its front 0.85 m off it
    readings = sensor_readings(pose, profile, WALL)
    points = read_points(pose, readings, profile)[0]
    hits = np.isfinite(readings[0]) & (readings[0] < profile.sensor_range)
    beams = list(profile.beam_sensors or [])
    # a beam's reading on every ray of its cone, a single ray's once
    assert len(points) == sum(profile.beam_rays if i in beams else 1 for i in np.flatnonzero(hits))
    gaps = WALL.signed_distance(points)
    assert (gaps >= -1e-9).all()  # none inside an obstacle: a beam's hit is its nearest ray's
    front = points[: 2 * profile.beam_rays]  # the front pair's beams come first
    np.testing.assert_allclose(front[:, 0].max(), 5.0, atol=1e-9)  # the nearest ray: on the face
    singles = points[2 * profile.beam_rays :]
    np.testing.assert_allclose(gaps[2 * profile.beam_rays :], 0.0, atol=1e-9)  # on a surface
    assert len(singles) > 0
    # out-of-range and infinite readings are no points
    none = read_points(pose, np.full((1, profile.n_sensors), np.inf), profile)[0]
    assert none.shape == (0, 2)


def _vet(profile: RobotProfile, pose: list[float], dtheta: float, ds: float,
         world: World = WALL) -> tuple[float, float, CollisionGuard]:  # fmt: skip
    guard = CollisionGuard(1, profile, world.size)
    p = np.array([pose])
    readings = sensor_readings(p, profile, world)
    guard.observe([0], p, readings)
    dth, step = guard.vet([0], p, [dtheta], [ds], readings)
    return float(dth[0]), float(step[0]), guard


def test_a_free_arc_passes_unchanged() -> None:
    dth, ds, guard = _vet(guarded(), [3.0, 6.0, 0.0], 0.3, 0.5)  # 1.85 m short of the wall
    assert (dth, ds) == (0.3, 0.5)
    assert guard.changed == guard.backed == 0


def test_an_arc_into_what_was_read_becomes_the_nearest_free_one() -> None:
    profile = guarded()
    pose = [4.55, 3.0, 0.0]  # the front 0.3 m off the wall; the planner asks for 0.5 m on
    assert swept_collision(np.array([pose]), 0.0, 0.5, profile, WALL)[0] >= 0
    dth, ds, guard = _vet(profile, pose, 0.0, 0.5)
    assert guard.changed == 1 and guard.backed == 0
    assert swept_collision(np.array([pose]), dth, ds, profile, WALL)[0] < 0  # free indeed
    assert dth == 0.0 and 0.0 < ds < 0.3  # the nearest: the same heading, a shorter step


@pytest.mark.parametrize("heading, gap", [(0.0, 0.005), (0.0, 0.03), (-0.2, 0.02), (0.4, 0.01)])
def test_a_robot_wedged_before_a_wall_backs_up(heading: float, gap: float) -> None:
    # the shipped UGV planners' collisions: the smallest step, turning on the spot, a front
    # corner a few mm or cm off the wall, so that both turns would sweep a corner into it
    profile = guarded()
    c, s = math.cos(heading), math.sin(heading)
    corner = max(0.15 * c + 0.125 * s, 0.15 * c - 0.125 * s)  # the front corner nearest the wall
    pose = [5.0 - corner - gap, 3.0, heading]
    for turn in (QUARTER, -QUARTER):
        assert swept_collision(np.array([pose]), turn, 0.02, profile, WALL)[0] >= 0
    dth, ds, guard = _vet(profile, pose, QUARTER, 0.02)
    assert guard.backed == 1
    assert dth == 0.0 and ds == pytest.approx(-profile.length * BACKUP_SHARES[0])
    assert swept_collision(np.array([pose]), dth, ds, profile, WALL)[0] < 0


@pytest.mark.parametrize(
    "pose, dtheta, ds",
    [([3.0, 6.0, 0.0], 0.3, 0.5), ([4.55, 3.0, 0.0], 0.0, 0.5), ([4.845, 3.0, 0.0], QUARTER, 0.02),
     ([4.8, 9.0, 0.4], -QUARTER, 0.02)],
)
def test_without_an_arena_the_guard_decides_as_in_it_wherever_odometry_puts_the_robot(
    pose: list[float], dtheta: float, ds: float
) -> None:
    # the planner node's guard knows no arena: poses in an odometry frame far from the map's
    # origin, only what was read as obstacles; away from the arena's border that is the same
    profile = guarded()
    in_arena = _vet(profile, pose, dtheta, ds)
    guard = CollisionGuard(1, profile)
    readings = sensor_readings(np.array([pose]), profile, WALL)
    odom = np.array([[pose[0] - 250.0, pose[1] + 40.5, pose[2]]])
    guard.observe([0], odom, readings)
    dth, step = guard.vet([0], odom, [dtheta], [ds], readings)
    assert (float(dth[0]), float(step[0])) == pytest.approx(in_arena[:2], abs=1e-12)
    assert (guard.changed, guard.backed) == (in_arena[2].changed, in_arena[2].backed)


def test_a_genome_planner_behind_the_guard_backs_out_of_a_wedge() -> None:
    # the reference UGV genome, a few mm before a wall it faces: its own decision (a turn on
    # the smallest step) sweeps a corner into the wall; behind the guard (as the planner node
    # runs it: a deployment with the stage collision_guard) it backs up instead, and forgets
    # what it read on reset
    plain = GenomePlanner.load(UGV_GENOME, "ugv")
    safe = GenomePlanner.load(UGV_GENOME, "ugv", Deployment(stages={"collision_guard": {}}))
    profile = safe.profile
    assert profile == plain.profile
    assert safe.stages == (CollisionGuardStage(),) and plain.stages == ()
    pose = np.array([5.0 - 0.5 * profile.length - 0.005, 3.0, 0.0])
    readings = sensor_readings(pose[None], profile, WALL)[0]
    own = plain.decide(readings, pose, (3.0, 9.0))
    assert swept_collision(pose[None], *own, profile, WALL)[0] >= 0
    dth, ds = safe.decide(readings, pose, (3.0, 9.0))
    assert dth == 0.0 and ds < 0.0
    assert swept_collision(pose[None], dth, ds, profile, WALL)[0] < 0
    assert safe.command(readings, pose, (3.0, 9.0))[0] < 0.0  # linear.x: backwards
    plain.reset()
    safe.reset()
    nothing = np.full(profile.n_sensors, np.inf)
    assert safe.decide(nothing, pose, (3.0, 9.0)) == plain.decide(nothing, pose, (3.0, 9.0))


def test_without_readings_the_guard_lets_the_planner_drive() -> None:
    profile = guarded()
    guard = CollisionGuard(1, profile, 12.0)
    p = np.array([[6.0, 6.0, 0.0]])
    nothing = np.full((1, profile.n_sensors), np.inf)
    guard.observe([0], p, nothing)
    dth, ds = guard.vet([0], p, [0.2], [0.5], nothing)
    assert (dth[0], ds[0]) == (0.2, 0.5)


def test_a_planner_that_drives_at_a_wall_collides_without_the_guard_and_not_with_it() -> None:
    # the policy always asks for the longest step straight on: the clearance rule shortens it
    # before the wall, down to its floor, the smallest step, on which the robot creeps on
    def policy(inputs: np.ndarray, robots: np.ndarray) -> np.ndarray:
        return np.tile([0.5, 1.0], (len(robots), 1))

    scenario = Scenario(WALL, (3.0, 3.0, 0.2), (3.0, 9.0))

    def run(on: bool):  # type: ignore[no-untyped-def]
        return run_episodes([scenario], guarded(), policy, time_budgets=[20.0],
                            stages=guard_stages(on))  # fmt: skip

    plain, with_guard = run(False), run(True)
    assert plain.collided[0]
    assert not with_guard.collided[0]
    assert with_guard.steps[0] > plain.steps[0]
    # steps back count in the path length, as distance driven
    assert (with_guard.path_length(guarded())[0]
            == pytest.approx(np.abs(with_guard.experience[0][:, 8 + 1]).sum()))  # fmt: skip


@pytest.mark.parametrize("memory", ["yes", 0, 1.5, True])
def test_the_memory_must_be_a_whole_number_of_decisions(memory: object) -> None:
    with pytest.raises(ConfigError, match="memory"):
        CollisionGuardStage(memory=memory)  # type: ignore[arg-type]
    with pytest.raises(ConfigError, match=r"stages\.collision_guard\.memory"):
        load_deployment("none", "ugv", [f"stages.collision_guard.memory={memory}"])
    assert CollisionGuardStage().memory == MEMORY


def test_no_guard_unless_a_deployment_names_one() -> None:
    none, _ = load_deployment("none", "ugv")
    assert none.build() == ()
    shipped, _ = load_deployment("shipped", "ugv")
    assert CollisionGuardStage() in shipped.build()
    dropped, _ = load_deployment("shipped", "ugv", ["stages.collision_guard=null"])
    assert not any(isinstance(s, CollisionGuardStage) for s in dropped.build())
