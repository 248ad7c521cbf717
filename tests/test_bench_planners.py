"""The benchmark's hand-written planners and scores (benchmark/control.py, reactive.py, bug.py,
oracle.py, scores.py): the baselines reach a goal in an empty world and stop before a wall,
the oracle's SPL is 1 in an empty world (within the step sizes), and a score under a time
limit is that of a run with that limit."""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest

from mentor_core.benchmark.bug import bug_policy
from mentor_core.benchmark.contenders import (
    Contender,
    behind_collision_guard,
    evolved,
    from_genome,
    hand_written,
    on_scan_map,
)
from mentor_core.benchmark.control import (
    Odometry,
    PointMemory,
    goal_polar,
    outputs_for,
    sees_all_round,
)
from mentor_core.benchmark.runner import run_contender
from mentor_core.benchmark.scores import outcomes, spl, under_limit
from mentor_core.benchmark.suite import build_suite, reference_profile
from mentor_core.controller.collision_guard import CollisionGuardStage
from mentor_core.controller.deployment import load_deployment
from mentor_core.controller.episodes import run_episodes
from mentor_core.files.genome_file import load_genome_and_metadata
from mentor_core.runtime.planner import deployed_genome, planner_profile
from mentor_core.sim.collision import default_sample_step
from mentor_core.sim.episode import Policy
from mentor_core.sim.kinematics import unicycle_arc
from mentor_core.sim.observation import actions_from_outputs, network_inputs
from mentor_core.sim.planner_settings import with_planner
from mentor_core.sim.robots import RobotProfile, get_profile
from mentor_core.sim.world import Scenario, World

ROBOTS = ["ugv", "swarm"]


def _pairs(world: World, profile: RobotProfile, n: int, facing: bool, seed: int = 0) -> list[
        Scenario]:
    """``n`` pairs in ``world`` at the unseen test's distances (at least a quarter of the
    arena), the start facing the goal or at a random heading."""
    rng = np.random.default_rng(seed)
    size = world.size
    found = []
    while len(found) < n:
        s, g = rng.uniform(0.15 * size, 0.85 * size, (2, 2))
        if math.dist(s, g) < size / 4:
            continue
        heading = math.atan2(g[1] - s[1], g[0] - s[0]) if facing else rng.uniform(-3.1, 3.1)
        found.append(Scenario(world, (s[0], s[1], heading), (g[0], g[1])))
    return found


@pytest.mark.parametrize("robot", ROBOTS)
@pytest.mark.parametrize("baseline", ["vfh", "bug"])
def test_baseline_reaches_the_goal_in_an_empty_world(robot: str, baseline: str) -> None:
    profile = reference_profile(get_profile(robot))
    scenarios = _pairs(World(profile.test_arena), profile, 6, facing=False)
    contender = hand_written(baseline, profile)
    batch = run_episodes(scenarios, profile, contender.policy(scenarios), time_budgets=50.0)
    assert batch.reached.all()


@pytest.mark.parametrize("robot", ROBOTS)
@pytest.mark.parametrize("baseline", ["vfh", "bug"])
@pytest.mark.parametrize("margin", [None, "reference"])
def test_baseline_stops_before_a_wall(robot: str, baseline: str, margin: str | None) -> None:
    """A wall across the whole arena between start and goal: the baseline drives up to it
    and never hits it, with the reference planner's clearance rule and without any (then
    only the baseline's own rule keeps it off)."""
    reference = reference_profile(get_profile(robot))
    profile = reference if margin else dataclasses.replace(reference, clearance_margin=None)
    size = profile.test_arena
    wall = (0.5 * size, 0.0, 0.52 * size, size)
    world = World(size, np.array([wall]))
    scenarios = [Scenario(world, (0.2 * size, y * size, 0.0), (0.8 * size, y * size))
                 for y in (0.3, 0.5, 0.7)]  # fmt: skip
    batch = run_episodes(scenarios, profile, hand_written(baseline, profile).policy(scenarios),
                         time_budgets=60.0)  # fmt: skip
    assert not batch.collided.any() and not batch.reached.any()
    # it did go up to the wall (within four body diagonals of it) before stopping short
    nearest = min(float(np.max(t[:, 0])) for t in batch.trajectories)
    assert wall[0] - nearest < 4 * profile.half_diagonal * 2


def test_bug_hands_its_to_goal_mode_to_a_driver_and_takes_over_at_a_wall() -> None:
    """With a driver that always goes straight on at full step, Bug's hit rule stops it at a
    wall across the arena (no collision, no arrival) and its following keeps it off."""
    profile = reference_profile(get_profile("ugv"))
    size = profile.test_arena
    world = World(size, np.array([(0.5 * size, 0.0, 0.52 * size, size)]))
    scenarios = [Scenario(world, (0.2 * size, y * size, 0.0), (0.8 * size, y * size))
                 for y in (0.3, 0.7)]  # fmt: skip
    driven: list[int] = []

    def straight_on(inputs: np.ndarray, robots: np.ndarray) -> np.ndarray:
        driven.append(len(robots))
        return np.tile([0.5, 1.0], (len(robots), 1))

    policy = bug_policy(scenarios, profile, driver=straight_on)
    batch = run_episodes(scenarios, profile, policy, time_budgets=30.0)
    assert not batch.collided.any() and not batch.reached.any()
    assert driven and sum(driven) < int(batch.steps.sum())  # Bug drove some decisions too
    # in the open the driver is all there is: it reaches a goal straight ahead
    free = [Scenario(World(size), (0.2 * size, 0.5 * size, 0.0), (0.8 * size, 0.5 * size))]
    assert run_episodes(free, profile, bug_policy(free, profile, driver=straight_on),
                        time_budgets=30.0).reached.all()  # fmt: skip


@pytest.mark.parametrize("robot", ROBOTS)
def test_oracle_spl_is_one_in_an_empty_world(robot: str) -> None:
    """SPL = l / max(p, l) with l = |goal - start| - R: the path taken overshoots l only by
    the engine's sampling of the arriving arc (one sample spacing, 1/4 of the body's smaller
    side) when it starts facing the goal, and by at most ``ceil(pi / h)`` turns on the spot
    (``step_min`` each) more otherwise."""
    robot_profile = get_profile(robot)
    profile = reference_profile(robot_profile)
    world = World(profile.test_arena)
    spacing = default_sample_step(profile)
    turns = math.ceil(math.pi / profile.heading_change_max) * profile.step_min
    for facing, tolerance in ((True, spacing), (False, spacing + turns)):
        scenarios = _pairs(world, profile, 8, facing=facing, seed=1)
        batch = run_episodes(scenarios, profile, hand_written("oracle", profile).policy(
            scenarios), time_budgets=50.0)  # fmt: skip
        result = outcomes(batch, profile)
        assert result.reached.all()
        shortest = np.array([math.dist(s.start[:2], s.goal) - profile.goal_radius
                             for s in scenarios])  # fmt: skip
        assert np.all(result.path_length >= shortest - 1e-9)
        assert np.all(result.path_length - shortest <= tolerance + 1e-9)
        values = spl(result.reached, shortest, result.path_length)
        assert np.all(values >= shortest / (shortest + tolerance))
        if facing:
            assert values.mean() > 0.99


def test_odometry_is_the_true_pose() -> None:
    profile = reference_profile(get_profile("ugv"))
    world = World(12.0, np.array([[5.0, 0.0, 5.3, 7.0]]))
    scenarios = [Scenario(world, (2.0, 2.0, 0.3), (9.0, 2.0)),
                 Scenario(world, (2.0, 9.0, -2.0), (9.0, 6.0))]  # fmt: skip
    inner = hand_written("bug", profile).policy(scenarios)
    odometry = Odometry([s.start for s in scenarios])
    seen: list[np.ndarray] = []

    def policy(inputs: np.ndarray, robots: np.ndarray) -> np.ndarray:
        out = np.asarray(inner(inputs, robots))
        seen.append(odometry.poses.copy())
        odometry.advance(robots, out, inputs, profile)
        return out

    batch = run_episodes(scenarios, profile, policy, time_budgets=30.0)
    for t, poses in enumerate(seen):
        active = batch.steps > t
        assert np.allclose(poses[active], batch.trajectories[active, t], atol=1e-9)


def test_outputs_and_goal_inputs_read_back() -> None:
    profile = reference_profile(get_profile("ugv"))
    dtheta = np.array([-1.0, -0.2, 0.0, 0.5, 2.0])
    ds = np.array([0.0, 0.1, 0.3, 0.5, 9.0])
    plain = dataclasses.replace(profile, clearance_margin=None)
    got_dtheta, got_ds = actions_from_outputs(outputs_for(dtheta, ds, plain), plain)
    h = profile.heading_change_max
    assert np.allclose(got_dtheta, np.clip(dtheta, -h, h))
    assert np.allclose(got_ds, np.clip(ds, profile.step_min, profile.step_max))
    poses = np.array([[1.0, 1.0, 0.4], [5.0, 2.0, -2.5], [3.0, 3.0, 3.0]])
    goals = np.array([[4.0, 5.0], [1.0, 1.0], [3.2, 3.1]])
    ranges = np.full((3, profile.n_sensors), np.inf)
    true_distance = np.hypot(*(goals - poses[:, :2]).T)
    true_bearing = np.arctan2(goals[:, 1] - poses[:, 1], goals[:, 0] - poses[:, 0]) - poses[:, 2]
    for encoding in ("egocentric", "paper"):
        p = with_planner(profile, input_encoding=encoding)
        bearing, distance = goal_polar(network_inputs(ranges, poses, goals, p), p)
        far = true_distance > p.goal_radius
        assert np.allclose(distance[far], true_distance[far])
        assert np.allclose(np.exp(1j * bearing), np.exp(1j * true_bearing))


def test_spl_formula() -> None:
    success = np.array([True, True, False, True])
    shortest = np.array([10.0, 10.0, 10.0, 0.0])
    taken = np.array([12.5, 9.0, 3.0, 0.0])
    assert spl(success, shortest, taken).tolist() == [0.8, 1.0, 0.0, 1.0]


def _straight(scenarios: list[Scenario], profile: RobotProfile) -> Policy:
    """Drives straight on at full step: collides, at different times per pair."""
    def policy(inputs: np.ndarray, robots: np.ndarray) -> np.ndarray:
        return np.tile([0.5, 1.0], (len(robots), 1))

    return policy


@pytest.mark.parametrize("baseline", ["vfh", "bug", "straight"])
def test_a_score_under_a_limit_is_a_run_with_that_limit(baseline: str) -> None:
    """Reached, collided and timed out at various times, cut at various limits."""
    profile = reference_profile(get_profile("ugv"))
    world = World(12.0, np.array([[5.0, 2.0, 5.3, 10.0], [8.0, 0.0, 8.3, 6.0]]))
    scenarios = [Scenario(world, (x, y, 0.0), (10.5, 10.5 - y)) for x, y in
                 ((1.0, 1.0), (1.5, 6.0), (2.0, 10.5), (3.5, 4.0), (6.5, 1.0), (6.5, 10.0))]
    contender = (hand_written(baseline, profile) if baseline != "straight"
                 else Contender("straight", "baseline", profile, _straight))  # fmt: skip
    long_run = outcomes(run_episodes(scenarios, profile, contender.policy(scenarios),
                                     time_budgets=80.0), profile)  # fmt: skip
    if baseline == "straight":
        assert long_run.collided.all() and len(set(long_run.steps.tolist())) > 2
    else:
        assert long_run.reached.sum() >= 3 and len(set(long_run.steps.tolist())) > 3
    for limit in (5.0, 12.0, 25.5, 40.0):
        direct = run_episodes(scenarios, profile, contender.policy(scenarios),
                              time_budgets=limit)  # fmt: skip
        success, collision = under_limit(long_run, np.full(len(scenarios), limit), 1.0)
        assert success.tolist() == direct.reached.tolist()
        assert collision.tolist() == direct.collided.tolist()


def test_point_memory_keeps_what_was_seen_in_the_body_frame() -> None:
    swarm, ugv = get_profile("swarm"), get_profile("ugv")
    assert sees_all_round(ugv) and not sees_all_round(swarm)
    assert PointMemory(2, ugv, 10).depth == 1
    memory = PointMemory(1, swarm, 3)
    pose = np.array([[1.0, 2.0, 0.5]])
    seen = np.array([[[0.3, -0.1], [0.5, 0.0], [np.nan, np.nan]]])
    first = memory.add_and_get(np.array([0]), pose, seen)
    assert np.allclose(first[0, -3:][:2], seen[0, :2])
    # move on an arc: the points keep their place in the map, so in the body frame they are
    # where the new pose's inverse puts them
    moved = unicycle_arc(pose, np.array([0.4]), np.array([0.2]))
    later = memory.add_and_get(np.array([0]), moved, np.full((1, 3, 2), np.nan))
    old = later[0, -6:-3][:2]
    c, s = np.cos(pose[0, 2]), np.sin(pose[0, 2])
    world = pose[0, :2] + seen[0, :2] @ np.array([[c, s], [-s, c]])
    dx = world - moved[0, :2]
    c2, s2 = np.cos(moved[0, 2]), np.sin(moved[0, 2])
    assert np.allclose(old, np.column_stack([c2 * dx[:, 0] + s2 * dx[:, 1],
                                             -s2 * dx[:, 0] + c2 * dx[:, 1]]))


def test_a_genome_in_memory_runs_as_its_file() -> None:
    path = Path(__file__).resolve().parents[1] / "bags/regression/ugv_reference_genome.json"
    robot = get_profile("ugv")
    suite = build_suite(robot, "validation", ["traps"], pairs_per_family=3)
    genome, metadata = load_genome_and_metadata(path)
    profile = planner_profile(robot, metadata)
    a = run_contender(suite, evolved(path, robot)).outcomes
    b = run_contender(suite, from_genome(genome, profile, "in memory")).outcomes
    assert np.array_equal(a.steps, b.steps) and np.array_equal(a.reached, b.reached)
    with pytest.raises(ValueError, match="inputs"):
        from_genome(genome, get_profile("swarm"), "wrong robot")


def test_a_genome_in_memory_runs_as_its_file_as_deployed() -> None:
    """``evolved(path, robot, name, deployment)``: the genome with the deployment's profile
    and stages on its scan map, named ``name`` (no prefix); a baseline behind the guard and on
    its scan map is named for each."""
    path = Path(__file__).resolve().parents[1] / "bags/regression/ugv_reference_genome.json"
    robot = get_profile("ugv")
    suite = build_suite(robot, "validation", ["traps"], pairs_per_family=3)
    deployment, _ = load_deployment("shipped", "ugv")
    genome, deployed = deployed_genome(path, "ugv", deployment)
    file = evolved(path, robot, "ref", deployment)
    memory = on_scan_map(from_genome(genome, deployed.profile, "ref", str(path), deployed.stages),
                         deployed.guide, rename=False)  # fmt: skip
    assert deployed.guide is not None and file.guide == deployed.guide
    assert file.name == memory.name == "ref"
    assert [s.name for s in file.stages] == ["rotation_shim", "collision_guard"]
    assert file.profile.control_period == 0.5  # twice per trained period (1 s)
    a, b = run_contender(suite, file).outcomes, run_contender(suite, memory).outcomes
    assert np.array_equal(a.steps, b.steps) and np.array_equal(a.reached, b.reached)
    assert np.array_equal(a.path_length, b.path_length)
    # as trained (no deployment): the plain genome, no stages, on no map
    plain = evolved(path, robot)
    assert plain.stages == () and plain.guide is None and plain.name == str(path)
    vfh = hand_written("vfh", reference_profile(robot))
    guarded = on_scan_map(behind_collision_guard(vfh, CollisionGuardStage()), deployed.guide)
    assert guarded.name == "mapped-guard-vfh" and guarded.stages == (CollisionGuardStage(),)
