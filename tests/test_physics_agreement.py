"""The batched engine agrees with the pymunk reference physics.

Random worlds (the paper's DoE, :func:`mentor_core.sim.scenarios.sample_world`) and random poses:
equal range readings (to 1e-9 m, +inf equal +inf) and equal collision verdicts, static and
swept. Configurations within ``DEGENERATE`` of a touching one (a ray through a box corner, a
sensor on a box edge, a hit at exactly range max, a body touching a box or wall) are skipped:
there the two answers may differ by rounding, and a test that depends on luck would flake.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from profiles_support import rays_as_sensors

from mentor_core.sim.collision import (
    robot_collides,
    sample_counts,
    swept_collision,
    swept_samples,
)
from mentor_core.sim.robots import RobotProfile, get_profile
from mentor_core.sim.scenarios import sample_world
from mentor_core.sim.sensors import beam_frames, sensor_readings
from mentor_core.sim.separation import separation_margin
from mentor_core.sim.world import World

pymunk_world = pytest.importorskip(
    "mentor_core.sim.pymunk_world",
    reason="mentor_core.sim.pymunk_world (reference physics) is missing",
)

DEGENERATE = 1e-7  # m
RANGE_TOLERANCE = 1e-9  # m
POSES_PER_WORLD = 12


def _degenerate_rays(origins: np.ndarray, angles: np.ndarray, ranges: np.ndarray,
                     world: World, max_range: float) -> np.ndarray:
    """Rays whose reading jumps under a DEGENERATE nudge of the geometry."""
    b = world.obstacles
    s = world.size
    corners = np.concatenate([
        b[:, [0, 1]], b[:, [0, 3]], b[:, [2, 1]], b[:, [2, 3]],
        np.array([[0.0, 0.0], [0.0, s], [s, 0.0], [s, s]]),
    ])
    u = np.c_[np.cos(angles), np.sin(angles)]
    rel = corners[None, :, :] - origins[:, None, :]
    along = (rel * u[:, None, :]).sum(axis=2)
    across = np.abs(rel[..., 0] * u[:, None, 1] - rel[..., 1] * u[:, None, 0])
    through_corner = ((along > -DEGENERATE) & (across < DEGENERATE)).any(axis=1)
    x, y = origins[:, 0, None], origins[:, 1, None]
    near_x = (x > b[:, 0] - DEGENERATE) & (x < b[:, 2] + DEGENERATE)
    near_y = (y > b[:, 1] - DEGENERATE) & (y < b[:, 3] + DEGENERATE)
    deep_x = (x > b[:, 0] + DEGENERATE) & (x < b[:, 2] - DEGENERATE)
    deep_y = (y > b[:, 1] + DEGENERATE) & (y < b[:, 3] - DEGENERATE)
    on_edge = (near_x & near_y & ~(deep_x & deep_y)).any(axis=1)
    at_max = np.abs(ranges - max_range) < DEGENERATE
    return through_corner | on_edge | at_max


def _random_case(
    seed: int, profile: RobotProfile, overlap: bool = False
) -> tuple[World, np.ndarray]:
    rng = np.random.default_rng(seed)
    world = sample_world(profile.train_arena, rng)
    if overlap:  # every box gets a partner overlapping it, as the walls of a real layout
        world = _with_overlaps(world, rng)
    r = profile.half_diagonal
    xy = rng.uniform(r, world.size - r, (POSES_PER_WORLD, 2))
    return world, np.c_[xy, rng.uniform(-np.pi, np.pi, POSES_PER_WORLD)]


def _with_overlaps(world: World, rng: np.random.Generator) -> World:
    """``world`` plus, for each box, a box of the same size shifted by a random fraction
    (10-60 %) of its size, so the pair overlaps with positive area; clipped to the arena."""
    b = world.obstacles
    size = b[:, 2:] - b[:, :2]
    shift = size * rng.uniform(0.1, 0.6, size.shape) * rng.choice([-1.0, 1.0], size.shape)
    partner = np.clip(np.c_[b[:, :2] + shift, b[:, 2:] + shift], 0.0, world.size)
    return World(world.size, np.concatenate([b, partner]))


def _profile(robot: str) -> RobotProfile:
    """A shipped profile, or ``<name>-beam``: its sensors as 45 deg beams of 5 rays."""
    name, _, beam = robot.partition("-")
    profile = get_profile(name)
    # beams on every sensor (the shipped UGV has them on its front pair only)
    everywhere = dataclasses.replace(profile, beam_width=np.pi / 4, beam_rays=5, beam_sensors=None)
    return everywhere if beam else profile


@pytest.mark.parametrize("robot", ["ugv", "swarm", "ugv-beam"])
@settings(derandomize=True, max_examples=15, deadline=None)
@given(seed=st.integers(0, 2**32 - 1))
def test_ranges_agree(robot: str, seed: int) -> None:
    _check_ranges(robot, seed, overlap=False)


@pytest.mark.parametrize("robot", ["ugv", "swarm"])
@settings(derandomize=True, max_examples=8, deadline=None)
@given(seed=st.integers(0, 2**32 - 1))
def test_ranges_agree_on_overlapping_boxes(robot: str, seed: int) -> None:
    _check_ranges(robot, seed, overlap=True)


def _check_ranges(robot: str, seed: int, overlap: bool) -> None:
    profile = _profile(robot)
    world, poses = _random_case(seed, profile, overlap)
    reference = pymunk_world.PymunkWorld(world, profile)
    ours = sensor_readings(poses, profile, world)
    rays = beam_frames(poses, profile)  # (n, sensors, rays, 3)
    hits = sensor_readings(poses, rays_as_sensors(profile), world).reshape(rays.shape[:3])
    for i, pose in enumerate(poses):
        theirs = reference.ranges(pose)
        # a sensor is skipped when any of its rays is degenerate
        skip = _degenerate_rays(rays[i, ..., :2].reshape(-1, 2), rays[i, ..., 2].reshape(-1),
                                hits[i].reshape(-1), world, profile.sensor_range)
        keep = ~skip.reshape(rays.shape[1:3]).any(axis=1)
        np.testing.assert_array_equal(np.isinf(ours[i, keep]), np.isinf(theirs[keep]))
        finite = keep & np.isfinite(ours[i])
        np.testing.assert_allclose(ours[i, finite], theirs[finite], rtol=0,
                                   atol=RANGE_TOLERANCE)


@pytest.mark.parametrize("robot", ["ugv", "swarm"])
@settings(derandomize=True, max_examples=15, deadline=None)
@given(seed=st.integers(0, 2**32 - 1))
def test_collision_verdicts_agree(robot: str, seed: int) -> None:
    _check_collisions(robot, seed, overlap=False)


@pytest.mark.parametrize("robot", ["ugv", "swarm"])
@settings(derandomize=True, max_examples=8, deadline=None)
@given(seed=st.integers(0, 2**32 - 1))
def test_collision_verdicts_agree_on_overlapping_boxes(robot: str, seed: int) -> None:
    _check_collisions(robot, seed, overlap=True)


def _check_collisions(robot: str, seed: int, overlap: bool) -> None:
    profile = get_profile(robot)
    world, poses = _random_case(seed, profile, overlap)
    reference = pymunk_world.PymunkWorld(world, profile)
    rng = np.random.default_rng(seed)
    lim = profile.heading_change_max
    dth = rng.uniform(-lim, lim, len(poses))
    ds = rng.uniform(profile.step_min, profile.step_max, len(poses))
    static = robot_collides(poses, profile, world)
    swept = swept_collision(poses, dth, ds, profile, world)
    samples, offsets = swept_samples(poses, dth, ds, sample_counts(dth, ds, profile))
    margins = np.abs(separation_margin(samples, profile, world))
    for i, pose in enumerate(poses):
        if margins[offsets[i]] >= DEGENERATE:
            assert static[i] == reference.collides(pose)
        if margins[offsets[i]:offsets[i + 1]].min() >= DEGENERATE:
            assert swept[i] == reference.swept_collision(pose, dth[i], ds[i])


def test_overlapping_boxes_read_and_collide_as_their_union() -> None:
    """Two overlapping boxes read and collide exactly as the one box of their union, in both
    physics (rays entering at the shared corner region, bodies inside the overlap)."""
    union = World(10.0, np.array([[3.0, 3.0, 7.0, 5.0]]))
    pair = World(10.0, np.array([[3.0, 3.0, 5.5, 5.0], [4.5, 3.0, 7.0, 5.0]]))
    profile = get_profile("ugv")
    rng = np.random.default_rng(4)
    poses = np.c_[rng.uniform(0.3, 9.7, (200, 2)), rng.uniform(-np.pi, np.pi, 200)]
    np.testing.assert_array_equal(
        sensor_readings(poses, profile, pair), sensor_readings(poses, profile, union)
    )
    np.testing.assert_array_equal(
        robot_collides(poses, profile, pair), robot_collides(poses, profile, union)
    )
    ref_pair = pymunk_world.PymunkWorld(pair, profile)
    ref_union = pymunk_world.PymunkWorld(union, profile)
    for pose in poses[:60]:
        np.testing.assert_allclose(ref_pair.ranges(pose), ref_union.ranges(pose), atol=1e-9)
        assert ref_pair.collides(pose) == ref_union.collides(pose)
    assert robot_collides(poses, profile, pair).any()


def test_some_cases_are_interesting() -> None:
    """The random cases above do exercise hits, misses and collisions."""
    profile = get_profile("ugv")
    world, poses = _random_case(0, profile)
    rng = np.random.default_rng(1)
    many = np.c_[rng.uniform(0.2, 11.8, (400, 2)), rng.uniform(-np.pi, np.pi, 400)]
    readings = sensor_readings(many, profile, world)
    assert 0.1 < np.isinf(readings).mean() < 0.9
    hits = robot_collides(many, profile, world)
    assert 0.01 < hits.mean() < 0.9
    assert world.obstacles.shape[0] > 4 and poses.shape == (POSES_PER_WORLD, 3)
