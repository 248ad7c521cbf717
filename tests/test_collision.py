"""Body collisions: separating-axis verdicts, swept sampling, broad phase, backends."""

from __future__ import annotations

import numpy as np
import pytest

from mentor_core.sim.collision import (
    EVENT_COLLIDED,
    EVENT_NONE,
    EVENT_REACHED,
    default_sample_step,
    first_collisions,
    robot_collides,
    sample_counts,
    sweep_may_collide,
    swept_collision,
    swept_events,
    swept_samples,
)
from mentor_core.sim.kinematics import arc_samples
from mentor_core.sim.robots import body_corners, get_profile
from mentor_core.sim.sensors import HAVE_NUMBA, Backend
from mentor_core.sim.separation import separation_margin
from mentor_core.sim.world import World

UGV = get_profile("ugv")  # 0.30 x 0.25 m
BACKENDS: list[Backend] = ["numpy", "numba"] if HAVE_NUMBA else ["numpy"]
WORLD = World(size=10.0, obstacles=np.array([[5.0, 4.0, 6.0, 6.0], [1.0, 8.0, 2.0, 9.0]]))


def _random_world(seed: int) -> World:
    rng = np.random.default_rng(seed)
    boxes: list[np.ndarray] = []
    while len(boxes) < 15:
        lo = rng.uniform(0.5, 8.5, 2)
        box = np.r_[lo, lo + rng.uniform(0.2, 1.0, 2)]
        if all(box[0] >= b[2] or b[0] >= box[2] or box[1] >= b[3] or b[1] >= box[3]
               for b in boxes):
            boxes.append(box)
    return World(size=10.0, obstacles=np.array(boxes))


@pytest.mark.parametrize("backend", BACKENDS)
def test_static_hand_cases(backend: Backend) -> None:
    poses = np.array([
        [3.0, 5.0, 0.0],                # free
        [4.85, 5.0, 0.0],               # front face touching the box: free
        [4.85 + 1e-6, 5.0, 0.0],        # 1 um into the box
        [0.15, 2.0, 0.0],               # rear touching the wall x = 0: free
        [0.149, 2.0, 0.0],              # crossing it
        [5.5, 5.0, 1.0],                # centre inside the box
        [4.9, 3.9, np.pi / 4],          # rotated corner into the box's lower-left corner
        [4.8, 3.8, np.pi / 4],          # the same, clear of it
    ])
    expected = [False, False, True, False, True, True, True, False]
    np.testing.assert_array_equal(robot_collides(poses, UGV, WORLD, backend=backend), expected)
    margin = separation_margin(poses, UGV, WORLD)
    np.testing.assert_array_equal(margin < 0, expected)
    assert margin[1] == pytest.approx(0.0, abs=1e-12) and margin[3] == pytest.approx(0.0)


def test_verdict_matches_corner_containment_on_random_poses() -> None:
    world = _random_world(1)
    rng = np.random.default_rng(2)
    poses = np.c_[rng.uniform(0, 10, (3000, 2)), rng.uniform(-np.pi, np.pi, 3000)]
    hit = robot_collides(poses, UGV, world)
    corners = body_corners(UGV, poses)  # (n, 4, 2)
    b = world.obstacles
    cx, cy = corners[..., 0, None], corners[..., 1, None]
    corner_in_box = ((cx > b[:, 0]) & (cx < b[:, 2]) & (cy > b[:, 1]) & (cy < b[:, 3]))
    outside = (corners < 0).any(axis=(1, 2)) | (corners > 10).any(axis=(1, 2))
    # a body corner strictly inside a box, or outside the arena, is always a collision
    assert hit[corner_in_box.any(axis=(1, 2)) | outside].all()
    # a body whose circumscribed disc misses every box and wall never collides
    d = np.hypot(np.maximum(np.maximum(b[:, 0] - poses[:, 0, None], poses[:, 0, None] - b[:, 2]),
                            0),
                 np.maximum(np.maximum(b[:, 1] - poses[:, 1, None], poses[:, 1, None] - b[:, 3]),
                            0)).min(axis=1)
    wall = np.minimum(poses[:, :2], 10 - poses[:, :2]).min(axis=1)
    assert not hit[(d > UGV.half_diagonal) & (wall > UGV.half_diagonal)].any()
    assert 0.05 < hit.mean() < 0.95


def test_backends_agree() -> None:
    if not HAVE_NUMBA:
        pytest.skip("numba is not importable")
    world = _random_world(4)
    rng = np.random.default_rng(5)
    n = 2000
    poses = np.c_[rng.uniform(0, 10, (n, 2)), rng.uniform(-np.pi, np.pi, n)]
    dth, ds = rng.uniform(-np.pi, np.pi, n), rng.uniform(0.1, 2.0, n)
    a = swept_collision(poses, dth, ds, UGV, world, backend="numba")
    b = swept_collision(poses, dth, ds, UGV, world, backend="numpy")
    np.testing.assert_array_equal(a, b)
    assert (a == -1).any() and (a == 0).any() and (a > 0).any()


def test_sample_counts_formula_and_bound() -> None:
    step = default_sample_step(UGV)
    assert step == pytest.approx(0.0625)
    counts = sample_counts([0.0, 0.0, np.pi, 0.01], [0.0, 2.0, 0.1, 0.0625], UGV)
    r = UGV.half_diagonal
    expected = [1, 32, max(np.ceil((0.1 + r * np.pi) / step), 16), 2]
    np.testing.assert_array_equal(counts, expected)
    # no body corner moves more than `step` between two samples
    rng = np.random.default_rng(0)
    dth, ds = rng.uniform(-np.pi, np.pi, 50), rng.uniform(0.1, 2.0, 50)
    for th, s, n in zip(dth, ds, sample_counts(dth, ds, UGV), strict=True):
        samples = arc_samples(np.array([[3.0, 3.0, 0.4]]), th, s, int(n))[0]
        corners = body_corners(UGV, samples)
        moves = np.hypot(*np.diff(corners, axis=0).transpose(2, 0, 1))
        assert moves.max() <= step + 1e-12
        assert np.abs(np.diff(np.unwrap(samples[:, 2]))).max() <= np.pi / 16 + 1e-12


def test_swept_samples_equal_arc_samples_bit_for_bit() -> None:
    rng = np.random.default_rng(7)
    poses = np.c_[rng.uniform(0, 10, (40, 2)), rng.uniform(-np.pi, np.pi, 40)]
    dth, ds = rng.uniform(-np.pi, np.pi, 40), rng.uniform(0.1, 2.0, 40)
    counts = sample_counts(dth, ds, UGV)
    flat, offsets = swept_samples(poses, dth, ds, counts)
    for i in range(40):
        ref = arc_samples(poses[i:i + 1], dth[i], ds[i], int(counts[i]))[0]
        np.testing.assert_array_equal(flat[offsets[i]:offsets[i + 1]], ref)


@pytest.mark.parametrize("backend", BACKENDS)
def test_swept_index_is_the_first_colliding_sample(backend: Backend) -> None:
    world = _random_world(8)
    rng = np.random.default_rng(9)
    n = 300
    poses = np.c_[rng.uniform(0, 10, (n, 2)), rng.uniform(-np.pi, np.pi, n)]
    dth, ds = rng.uniform(-np.pi, np.pi, n), rng.uniform(0.1, 2.0, n)
    got = swept_collision(poses, dth, ds, UGV, world, backend=backend)
    counts = sample_counts(dth, ds, UGV)
    for i in range(n):
        hits = robot_collides(arc_samples(poses[i:i + 1], dth[i], ds[i], int(counts[i]))[0],
                              UGV, world, backend=backend)
        assert got[i] == (int(np.argmax(hits)) if hits.any() else -1)


def test_broad_phase_is_conservative() -> None:
    world = _random_world(10)
    rng = np.random.default_rng(11)
    n = 3000
    poses = np.c_[rng.uniform(0, 10, (n, 2)), rng.uniform(-np.pi, np.pi, n)]
    dth, ds = rng.uniform(-np.pi, np.pi, n), rng.uniform(0.1, 2.0, n)
    may = sweep_may_collide(poses, dth, ds, UGV, world)
    flat, offsets = swept_samples(poses, dth, ds, sample_counts(dth, ds, UGV))
    every = first_collisions(flat, offsets, UGV, world)
    assert (every[~may] == -1).all()
    assert 0.05 < (~may).mean() < 0.95  # it does prune, and it does not pass everything
    # both backends agree exactly, also on discs that (up to rounding) touch a box or a wall
    np.testing.assert_array_equal(
        may, sweep_may_collide(poses, dth, ds, UGV, world, backend="numpy")
    )
    box = world.obstacles[0]
    reach = UGV.half_diagonal + 1e-9
    edge = np.array([[box[2] + reach, 0.5 * (box[1] + box[3]), 0.0],
                     [reach, 5.0, 0.0], [10.0 - reach, 5.0, 0.0]])  # fmt: skip
    np.testing.assert_array_equal(
        sweep_may_collide(edge, np.zeros(3), np.zeros(3), UGV, world, backend="numba"),
        sweep_may_collide(edge, np.zeros(3), np.zeros(3), UGV, world, backend="numpy"),
    )


def test_straight_into_a_wall() -> None:
    pose = np.array([[9.0, 2.0, 0.0]])  # front at 9.15; the wall x = 10 is 0.85 m ahead
    idx = swept_collision(pose, [0.0], [2.0], UGV, WORLD)
    samples = arc_samples(pose, 0.0, 2.0, int(sample_counts(0.0, 2.0, UGV)))[0]
    assert idx[0] > 0
    assert samples[idx[0], 0] + 0.15 > 10.0 >= samples[idx[0] - 1, 0] + 0.15


@pytest.mark.skipif(not HAVE_NUMBA, reason="numba not importable")
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_swept_events_backends_agree_bit_for_bit(seed: int) -> None:
    """The compiled kernel (one robot at a time, stopping at the first event) gives the numpy
    path's events, stop samples and end poses exactly, with every kind of ending present."""
    world = _random_world(seed)
    rng = np.random.default_rng(seed)
    n = 4000
    poses = np.c_[rng.uniform(0.0, 10.0, (n, 2)), rng.uniform(-np.pi, np.pi, n)]
    dth = rng.uniform(-np.pi, np.pi, n)
    ds = rng.uniform(0.0, 2.0, n)
    goals = poses[:, :2] + rng.normal(0.0, 1.5, (n, 2))
    counts = sample_counts(dth, ds, UGV)
    fast = swept_events(poses, dth, ds, counts, goals, UGV, world, backend="numba")
    ref = swept_events(poses, dth, ds, counts, goals, UGV, world, backend="numpy")
    for got, want in zip(fast, ref, strict=True):
        np.testing.assert_array_equal(got, want)
    event, stop, end = ref
    assert {EVENT_NONE, EVENT_REACHED, EVENT_COLLIDED} <= set(event.tolist())
    # the definition: collisions stop a sample early, the others where the event happened
    hit = swept_collision(poses, dth, ds, UGV, world)
    collided = event == EVENT_COLLIDED
    np.testing.assert_array_equal(collided, (hit >= 0) & (event != EVENT_REACHED))
    np.testing.assert_array_equal(stop[collided], np.maximum(hit[collided] - 1, 0))
    np.testing.assert_array_equal(stop[event == EVENT_NONE], counts[event == EVENT_NONE])
    reached = event == EVENT_REACHED
    assert (np.hypot(*(end[reached, :2] - goals[reached]).T) <= UGV.goal_radius).all()
