"""Reference physics: hand-computed readings and collisions, several robots, determinism."""

from __future__ import annotations

import math

import numpy as np
import pytest
from profiles_support import UGV_STRAIGHT

from mentor_core.sim.pymunk_world import PymunkWorld
from mentor_core.sim.robots import get_profile
from mentor_core.sim.world import World

UGV = UGV_STRAIGHT  # 0.30 x 0.25 m, a pair on each edge facing straight out, range 4 m
SWARM = get_profile("swarm")
INF = math.inf


def test_readings_against_walls() -> None:
    pw = PymunkWorld(World(10.0), UGV)
    # front pair at x = 7.15 -> wall at 2.85 m; the rest see nothing within 4 m
    np.testing.assert_allclose(pw.ranges((7.0, 5.0, 0.0)), [2.85, 2.85] + [INF] * 6)
    # turned left: the front pair looks up from y = 8.15; the right pair (x = 5.125) looks
    # towards x = 10 at 4.875 m (> 4 m); the rear pair looks down 7.85 m
    r = pw.ranges((5.0, 8.0, math.pi / 2))
    np.testing.assert_allclose(r[:2], [1.85, 1.85], atol=1e-12)
    assert np.isinf(r[2:]).all()
    # nothing in range in the middle of a big empty arena
    assert np.isinf(PymunkWorld(World(20.0), UGV).ranges((10.0, 10.0, 0.3))).all()


def test_readings_against_an_obstacle() -> None:
    pw = PymunkWorld(World(10.0, np.array([[5.0, 4.0, 6.0, 6.0]])), UGV)
    r = pw.ranges((3.0, 5.0, 0.0))
    np.testing.assert_allclose(r, [1.85, 1.85, INF, INF, 2.85, 2.85, INF, INF])
    # swarm front-left ray at +45 deg from (1.04, 1.025) hits the box's lower face y = 1.4
    pw = PymunkWorld(World(5.0, np.array([[1.0, 1.4, 2.0, 2.0]])), SWARM)
    r = pw.ranges((1.0, 1.0, 0.0))
    assert r[2] == pytest.approx((1.4 - 1.025) * math.sqrt(2.0))
    assert np.isinf(r[:2]).all()


def test_collides_overlap_touch_and_outside() -> None:
    pw = PymunkWorld(World(10.0, np.array([[5.0, 4.0, 6.0, 6.0]])), UGV)
    assert not pw.collides((3.0, 5.0, 0.0))
    assert not pw.collides((4.85, 5.0, 0.0))  # front face touches x = 5
    assert pw.collides((4.86, 5.0, 0.0))
    assert pw.collides((5.5, 5.0, 1.0))  # centre inside the box
    assert not pw.collides((0.15, 5.0, 0.0))  # rear face on the wall x = 0
    assert pw.collides((0.14, 5.0, 0.0))
    assert pw.collides((-3.0, -3.0, 0.0))  # far outside the arena
    # at 45 deg the body reaches (0.15 + 0.125) / sqrt(2) = 0.194 m left of its centre
    assert pw.collides((0.19, 5.0, math.pi / 4))
    assert not pw.collides((0.2, 5.0, math.pi / 4))


def test_swept_collision_finds_the_first_sample() -> None:
    pw = PymunkWorld(World(10.0, np.array([[5.0, 4.0, 6.0, 6.0]])), UGV)
    # sample j at x = 3 + 0.1 j; front face 3.15 + 0.1 j passes 5 at j = 19
    assert pw.swept_collision((3.0, 5.0, 0.0), 0.0, 2.0, n_samples=20) == 19
    assert pw.swept_collision((3.0, 5.0, 0.0), 0.0, 1.0, n_samples=20) == -1
    assert pw.swept_collision((3.0, 5.0, math.pi), 0.0, 2.0) == -1
    assert pw.swept_collision((5.5, 5.0, 0.0), 0.0, 0.5) == 0
    # turning in place next to the wall: free at 0 and pi, the corner hits at pi / 4
    assert pw.swept_collision((0.16, 5.0, 0.0), math.pi, 0.0, n_samples=4) == 1
    assert not pw.collides((0.16, 5.0, math.pi))


def test_robots_see_and_hit_each_other_but_not_themselves() -> None:
    pw = PymunkWorld(World(10.0), UGV)
    pw.add_robot("a", (3.0, 5.0, 0.0))
    pw.add_robot("b", (3.0, 3.0, 0.0))
    assert pw.robot_names == ("a", "b")
    # a's right pair (y = 4.875) sees b's top face (y = 3.125)
    r = pw.ranges(pw.pose("a"), robot="a")
    np.testing.assert_allclose(r[6:], [1.75, 1.75])
    assert r[0] == pytest.approx(10.0 - 3.15) or np.isinf(r[0])
    assert not pw.collides(pw.pose("a"), robot="a")
    assert pw.collides(pw.pose("a"))  # a probe at a's pose overlaps a's body
    pw.set_pose("b", (3.0, 4.0, 0.0))
    np.testing.assert_allclose(pw.ranges(pw.pose("a"), robot="a")[6:], [0.75, 0.75])
    assert pw.collides((3.0, 4.2, 0.0), robot="a")  # would overlap b
    pw.remove_robot("b")
    assert np.isinf(pw.ranges(pw.pose("a"), robot="a")[6:]).all()
    with pytest.raises(ValueError, match="exists"):
        pw.add_robot("a", (1.0, 1.0, 0.0))
    with pytest.raises(KeyError, match="no robot 'b'"):
        pw.set_pose("b", (1.0, 1.0, 0.0))
    with pytest.raises(ValueError, match="finite"):
        pw.set_pose("a", (1.0, math.nan, 0.0))


def test_queries_are_deterministic_and_history_free() -> None:
    world = World(10.0, np.array([[2.0, 2.0, 3.0, 7.0], [6.0, 1.0, 8.0, 3.0]]))
    rng = np.random.default_rng(5)
    poses = np.column_stack([rng.uniform(0.5, 9.5, (40, 2)), rng.uniform(-3, 3, 40)])
    first = PymunkWorld(world, UGV)
    readings = np.array([first.ranges(p) for p in poses])
    hits = [first.collides(p) for p in poses]
    second = PymunkWorld(world, UGV)
    second.add_robot("x", (9.0, 9.0, 0.0))
    second.remove_robot("x")
    assert [second.collides(p) for p in poses[::-1]][::-1] == hits
    np.testing.assert_array_equal(np.array([second.ranges(p) for p in poses]), readings)
    assert 0 < sum(hits) < len(hits)


def test_robots_of_two_profiles_share_a_world() -> None:
    pw = PymunkWorld(World(10.0), UGV)
    pw.add_robot("ugv", (3.0, 5.0, 0.0))
    pw.add_robot("bot", (3.5, 5.0, math.pi), SWARM)  # faces the UGV's front face
    assert pw.profile_of("bot") is SWARM and pw.profile_of("ugv") is UGV
    r = pw.ranges(pw.pose("bot"), robot="bot")
    assert r.shape == (3,)
    # the Swarm-Robot's centre sensor at x = 3.46 sees the UGV's front face at x = 3.15
    assert r[1] == pytest.approx(0.31)
    # its small body fits where the UGV's would not
    assert not pw.collides((3.5, 5.0, math.pi), robot="bot")
    assert pw.collides((3.5, 5.0, math.pi), profile=UGV)
    assert pw.collides((3.5, 5.0, math.pi), profile=SWARM)  # a free probe overlaps the bot


def test_drive_follows_the_arc_and_stops_at_the_first_event() -> None:
    world = World(10.0, np.array([[5.0, 4.0, 6.0, 6.0]]))
    pw = PymunkWorld(world, UGV)
    pw.add_robot("a", (1.0, 1.0, 0.0))
    move = pw.drive("a", math.pi / 2, 1.0)
    assert not move.collided and not move.reached and move.fraction == 1.0
    r = 1.0 / (math.pi / 2)  # quarter circle of length 1 m
    np.testing.assert_allclose(move.pose, (1.0 + r, 1.0 + r, math.pi / 2), atol=1e-12)
    assert pw.pose("a") == move.pose
    # straight at the box: stops on the last free sample before the front face reaches x = 5
    pw.set_pose("a", (3.0, 5.0, 0.0))
    move = pw.drive("a", 0.0, 2.0)
    assert move.collided and not move.reached
    assert move.pose[0] <= 4.85 and not pw.collides(move.pose, robot="a")
    # a goal on the way: stops at the first sample within the radius
    pw.set_pose("a", (1.0, 8.0, 0.0))
    move = pw.drive("a", 0.0, 2.0, goal=(3.5, 8.0), goal_radius=1.0)
    assert move.reached and 0.0 < move.fraction < 1.0
    assert math.hypot(move.pose[0] - 3.5, move.pose[1] - 8.0) <= 1.0
    with pytest.raises(ValueError, match="not finite"):
        pw.drive("a", math.nan, 1.0)


def test_drive_agrees_with_the_batched_engine() -> None:
    from mentor_core.sim.engine import BatchEngine
    from mentor_core.sim.scenarios import sample_world

    world = sample_world(12.0, np.random.default_rng(2))
    rng = np.random.default_rng(9)
    engine = BatchEngine(world, UGV, backend="numpy")
    starts, goals = [], []
    while len(starts) < 30:
        p = (rng.uniform(0.5, 11.5), rng.uniform(0.5, 11.5), rng.uniform(-3.0, 3.0))
        if not PymunkWorld(world, UGV).collides(p):
            starts.append(p)
            goals.append((rng.uniform(0.5, 11.5), rng.uniform(0.5, 11.5)))
    engine.reset(starts, goals)
    dtheta = rng.uniform(-math.pi, math.pi, 30)
    ds = rng.uniform(0.1, 2.0, 30)
    result = engine.step(dtheta, ds, np.ones(30, dtype=bool))
    for i in range(30):
        pw = PymunkWorld(world, UGV)
        pw.add_robot("r", starts[i])
        move = pw.drive("r", float(dtheta[i]), float(ds[i]), goals[i])
        assert (move.collided, move.reached) == (result.collided[i], result.reached[i])
        assert move.fraction == pytest.approx(result.fraction[i])
        np.testing.assert_allclose(move.pose, engine.poses[i], atol=1e-12)
    assert result.collided.any() and not result.collided.all()
