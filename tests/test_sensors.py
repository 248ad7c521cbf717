"""Ray casts against boxes and walls: hand cases, backends bit-equal, sensor placement."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from profiles_support import UGV_STRAIGHT, rays_as_sensors, single_rays

from mentor_core.sim.robots import get_profile
from mentor_core.sim.scenarios import sample_world
from mentor_core.sim.sensors import (
    HAVE_NUMBA,
    Backend,
    beam_frames,
    cast_rays,
    sensor_frames,
    sensor_readings,
)
from mentor_core.sim.world import World

BOX = np.array([[3.0, 0.5, 4.0, 1.5]])
BACKENDS = ["numpy", "numba"] if HAVE_NUMBA else ["numpy"]


@pytest.mark.parametrize("backend", BACKENDS)
def test_hand_cases(backend: Backend) -> None:
    origins = np.array([[1.0, 1.0], [1.0, 1.0], [1.0, 1.0], [3.5, 1.0], [1.0, 1.0], [4.0, 1.0]])
    angles = np.array([0.0, np.pi, np.pi / 4, 0.0, np.arctan2(0.5, 2.0), 0.0])
    d = cast_rays(origins, angles, BOX, 10.0, 8.0, backend=backend)
    expected = [
        2.0,  # straight onto the box face
        1.0,  # back onto the wall x = 0
        np.hypot(9.0, 9.0) if np.hypot(9.0, 9.0) <= 8.0 else np.inf,  # corner, beyond range
        0.0,  # origin inside the box
        np.hypot(2.0, 0.5),  # grazing the top-left corner counts as a hit
        0.0,  # origin on the box edge
    ]
    np.testing.assert_allclose(d, expected, rtol=0, atol=1e-12)


@pytest.mark.parametrize("backend", BACKENDS)
def test_out_of_range_is_inf(backend: Backend) -> None:
    origins = [[1.0, 1.0], [1.0, 1.0]]
    d = cast_rays(origins, [0.0, np.pi / 2], BOX, 10.0, 1.5, backend=backend)
    assert np.isinf(d).all() and (d > 0).all()


def test_backends_agree_bit_for_bit() -> None:
    if not HAVE_NUMBA:
        pytest.skip("numba is not importable")
    rng = np.random.default_rng(3)
    lo = rng.uniform(0.0, 9.0, (25, 2))
    boxes = np.c_[lo, lo + rng.uniform(0.1, 1.0, (25, 2))]
    origins = rng.uniform(0.0, 10.0, (4000, 2))
    angles = rng.uniform(-np.pi, np.pi, 4000)
    angles[:8] = [0.0, np.pi, np.pi / 2, -np.pi / 2, 0.0, 0.0, np.pi, np.pi]  # axis rays
    origins[4:8] = boxes[0, :2]  # on a box corner
    for max_range in (0.5, 4.0, 20.0):
        a = cast_rays(origins, angles, boxes, 10.0, max_range, backend="numba")
        b = cast_rays(origins, angles, boxes, 10.0, max_range, backend="numpy")
        np.testing.assert_array_equal(a, b)
        assert 0.0 < np.isinf(a).mean() < 1.0 or max_range == 20.0


def test_hit_point_lies_on_a_box_or_wall() -> None:
    rng = np.random.default_rng(5)
    lo = rng.uniform(1.0, 8.0, (10, 2))
    boxes = np.c_[lo, lo + 0.7]
    origins = rng.uniform(0.0, 10.0, (500, 2))
    angles = rng.uniform(-np.pi, np.pi, 500)
    d = cast_rays(origins, angles, boxes, 10.0, 50.0)
    hit = origins + d[:, None] * np.c_[np.cos(angles), np.sin(angles)]
    on_wall = (np.abs(hit) < 1e-9) | (np.abs(hit - 10.0) < 1e-9)
    x, y = hit[:, 0, None], hit[:, 1, None]
    in_box = (x >= boxes[:, 0] - 1e-9) & (x <= boxes[:, 2] + 1e-9)
    in_box &= (y >= boxes[:, 1] - 1e-9) & (y <= boxes[:, 3] + 1e-9)
    assert (on_wall.any(axis=1) | in_box.any(axis=1)).all()
    # nothing closer: the point 1e-6 m before the hit is free of every box
    before = origins + np.maximum(d - 1e-6, 0)[:, None] * np.c_[np.cos(angles), np.sin(angles)]
    bx, by = before[:, 0, None], before[:, 1, None]
    inside = (bx > boxes[:, 0]) & (bx < boxes[:, 2]) & (by > boxes[:, 1]) & (by < boxes[:, 3])
    assert not inside[d > 1e-6].any()


def test_shape_mismatch_raises() -> None:
    with pytest.raises(ValueError, match="origins"):
        cast_rays(np.zeros((3, 2)), np.zeros(2), BOX, 10.0, 4.0)


def test_sensor_frames_follow_the_body() -> None:
    ugv = get_profile("ugv")
    frames = sensor_frames(np.array([[5.0, 5.0, np.pi / 2]]), ugv)[0]
    # front-right mount (0.15, -0.0375), facing -22.5 deg, of a robot facing +y sits at
    # (5.0375, 5.15) and faces 67.5 deg
    np.testing.assert_allclose(frames[0], [5.0375, 5.15, np.pi / 2 - np.pi / 8], atol=1e-12)


@pytest.mark.parametrize("backend", BACKENDS)
def test_sensor_readings_in_an_empty_arena(backend: Backend) -> None:
    ugv = UGV_STRAIGHT
    world = World(size=8.0)
    r = sensor_readings(np.array([[5.0, 5.0, 0.0], [4.0, 4.0, 0.0]]), ugv, world,
                        backend=backend)
    # robot 0 facing +x: front 8 - 5.15, left 8 - 5.125, rear 4.85 (> 4 m range), right 4.875
    np.testing.assert_allclose(r[0], [2.85, 2.85, 2.875, 2.875, np.inf, np.inf, np.inf, np.inf])
    np.testing.assert_allclose(r[1], [3.85, 3.85, 3.875, 3.875] * 2)  # centred: all in range
    assert r.shape == (2, ugv.n_sensors)


def test_sensor_readings_see_a_box() -> None:
    ugv = UGV_STRAIGHT
    world = World(size=12.0, obstacles=np.array([[6.0, 4.0, 7.0, 6.0]]))
    pose = np.array([[5.0, 5.0, 0.0]])
    r = sensor_readings(pose, ugv, world)
    np.testing.assert_allclose(r[0, :2], [0.85, 0.85])
    np.testing.assert_array_equal(r, sensor_readings(pose, ugv, world, backend="numpy"))


@pytest.mark.parametrize("backend", BACKENDS)
def test_a_beam_reads_its_nearest_ray(backend: Backend) -> None:
    # a post at 45 deg off the front: the straight-out ray misses it, a 90 deg beam sees it
    world = World(size=12.0, obstacles=np.array([[6.0, 6.0, 6.4, 6.4]]))
    ray = dataclasses.replace(UGV_STRAIGHT, sensors=UGV_STRAIGHT.sensors[1:2])  # (0.15, 0.0375)
    beam = dataclasses.replace(ray, beam_width=np.pi / 2, beam_rays=3)  # -45, 0, +45 deg
    pose = np.array([[5.0, 5.0, 0.0]])
    assert np.isinf(sensor_readings(pose, ray, world, backend=backend)).all()
    got = sensor_readings(pose, beam, world, backend=backend)
    # the +45 deg ray from (5.15, 5.0375) meets the post's lower face y = 6 at x = 6.1125
    assert got[0, 0] == pytest.approx((6.0 - 5.0375) * np.sqrt(2.0), abs=1e-12)
    frames = beam_frames(pose, beam)
    assert frames.shape == (1, 1, 3, 3)
    np.testing.assert_allclose(frames[0, 0, :, 2], [-np.pi / 4, 0.0, np.pi / 4])


def test_beam_readings_are_the_minimum_of_their_rays_on_both_backends() -> None:
    rng = np.random.default_rng(5)
    ugv = dataclasses.replace(get_profile("ugv"), beam_width=np.radians(40.0), beam_rays=4)
    world = sample_world(12.0, rng)
    poses = np.c_[rng.uniform(1.0, 11.0, (50, 2)), rng.uniform(-np.pi, np.pi, 50)]
    got = sensor_readings(poses, ugv, world)
    np.testing.assert_array_equal(got, sensor_readings(poses, ugv, world, backend="numpy"))
    # every ray as a single-ray sensor of its own: the same directions, bit for bit
    each = sensor_readings(poses, rays_as_sensors(ugv), world)
    each = each.reshape(50, ugv.n_sensors, ugv.beam_rays)
    np.testing.assert_array_equal(got, each.min(axis=2))
    # and, to rounding, rays cast along beam_frames' angles
    frames = beam_frames(poses, ugv)
    cast = cast_rays(frames[..., :2].reshape(-1, 2), frames[..., 2].reshape(-1),
                     world.obstacles, world.size, ugv.sensor_range).reshape(frames.shape[:3])
    np.testing.assert_allclose(got, cast.min(axis=2), rtol=0, atol=1e-12)


@pytest.mark.skipif(not HAVE_NUMBA, reason="numba not importable")
@pytest.mark.parametrize("robot", ["ugv", "swarm"])
def test_fused_readings_kernel_equals_the_numpy_backend(robot: str) -> None:
    """The one-pass kernel (mounts, culling, rays, range cut in one loop) gives the numpy
    backend's readings bit for bit: axis-aligned headings (rays parallel to the slabs), robots
    overlapping boxes, readings beyond the range, single rays and beams."""
    rng = np.random.default_rng(11)
    profile = get_profile(robot)
    size = profile.train_arena
    world = sample_world(size, rng)
    n = 3000
    poses = np.c_[rng.uniform(0.0, size, (n, 2)), rng.uniform(-np.pi, np.pi, n)]
    poses[: n // 4, 2] = rng.choice([0.0, np.pi / 2, np.pi, -np.pi / 2], n // 4)
    # as shipped (the UGV: beams on its front pair), and beams on every sensor
    for variant in (profile, dataclasses.replace(profile, beam_width=np.radians(45.0),
                                                 beam_rays=5, beam_sensors=None)):
        got = sensor_readings(poses, variant, world, backend="numba")
        np.testing.assert_array_equal(got, sensor_readings(poses, variant, world,
                                                           backend="numpy"))
        assert np.isinf(got).any() and (got == 0.0).any() and np.isfinite(got).any()


@pytest.mark.parametrize("backend", BACKENDS)
def test_only_the_beam_sensors_read_beams(backend: Backend) -> None:
    """The shipped UGV: the front pair reads 45 deg beams, the other six read single rays,
    exactly as a profile of single rays does; a beam reads no farther than its middle ray."""
    rng = np.random.default_rng(8)
    ugv = get_profile("ugv")
    world = sample_world(12.0, rng)
    poses = np.c_[rng.uniform(1.0, 11.0, (400, 2)), rng.uniform(-np.pi, np.pi, 400)]
    got = sensor_readings(poses, ugv, world, backend=backend)
    rays = sensor_readings(poses, single_rays(ugv), world, backend=backend)
    np.testing.assert_array_equal(got[:, 2:], rays[:, 2:])
    assert (got[:, :2] <= rays[:, :2]).all() and (got[:, :2] < rays[:, :2]).any()
