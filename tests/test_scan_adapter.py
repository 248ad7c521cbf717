"""A robot's sensors read off any laser scan (mentor_core.sim.scan_adapter), and the simulated
lidar that makes such scans (mentor_core.sim.lidar).

Exact on hand-made scans (flat walls, REP-117 values, mounts off the centre, upside down), and
against the simulator's own readings: a 720-ray scan (increment da = 0.5 deg) from the body
centre in a training world. The tolerance there is the angular resolution's: a flat surface is
read within ``r da`` at range ``r`` (in fact exactly), but a ray grazing an edge within one
increment, or a sensor beside the lidar looking past a near obstacle that hides the view from
the lidar (parallax), can read otherwise; so the test asserts

* single-ray sensors: at least 97 % of readings within ``r da + 1e-5`` m of the profile's
  (measured: 97.5 % UGV, 99.3 % Swarm-Robot, 120 poses each);
* beam sensors (the UGV's front pair): never farther than the profile's 5-ray reading plus
  ``r da`` in 99 % of readings (the derived reading is the nearest in the whole beam, which the
  5 rays only sample);
* never a phantom: no reading is nearer than the true nearest obstacle within the sensor's
  field widened by 2 increments (less the sampling error of that reference and 1e-5 m of
  float32 rounding).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from mentor_core.sim.lidar import LidarSpec, lidar_scan
from mentor_core.sim.pymunk_world import PymunkWorld
from mentor_core.sim.robots import RobotProfile, get_profile
from mentor_core.sim.scan_adapter import (
    LaserScanData,
    LidarMount,
    MountedScan,
    fields_of_view,
    readings_from_scan,
)
from mentor_core.sim.scenarios import training_scenarios
from mentor_core.sim.sensors import sensor_frames
from mentor_core.sim.transforms import Transform2D
from mentor_core.sim.world import World

UGV = get_profile("ugv")
SWARM = get_profile("swarm")
N_RAYS = 360


def _wall_scan(wall_x: float, n: int = N_RAYS, range_max: float = 10.0) -> LaserScanData:
    """A full-circle scan from the body centre of a wall ``x = wall_x`` (float64 ranges)."""
    inc = 2 * math.pi / n
    angles = -math.pi + inc * np.arange(n)
    with np.errstate(divide="ignore"):
        r = np.where(np.cos(angles) > 0, wall_x / np.cos(angles), np.inf)
    r = np.where(r <= range_max, r, np.inf)
    return LaserScanData(-math.pi, inc, 0.0, range_max, r)


def test_a_flat_wall_is_read_exactly_by_beams_and_single_rays() -> None:
    got = readings_from_scan(_wall_scan(1.0), LidarMount(), UGV)
    want = np.full(8, np.inf)
    want[0] = want[1] = 1.0 - 0.15  # the beams' straight-ahead edge meets the wall square on
    want[2] = want[7] = (1.0 - 0.0375) / math.cos(math.radians(67.5))  # 2.515 m, in range
    np.testing.assert_allclose(got.readings, want, rtol=0, atol=1e-12)
    assert got.covered.all() and got.uncovered == ()


def test_rep117_values() -> None:
    n = 720
    inc = 2 * math.pi / n
    k0 = n // 2  # the ray straight ahead (angle 0)

    def reading(value: float, range_min: float = 0.0, range_max: float = 1.0) -> float:
        r = np.full(n, np.inf)
        r[k0] = value
        scan = LaserScanData(-math.pi, inc, range_min, range_max, r)
        return float(readings_from_scan(scan, LidarMount(), SWARM).readings[1])

    # the swarm's front sensor sits at (0.04, 0) facing ahead: a return at 0.5 m reads 0.46 m
    assert reading(0.5) == pytest.approx(0.46, abs=1e-12)
    assert reading(-math.inf, range_min=0.5) == pytest.approx(0.46, abs=1e-12)  # too near
    assert math.isinf(reading(math.nan))  # no measurement
    assert math.isinf(reading(math.inf))  # nothing within range_max
    assert math.isinf(reading(0.3, range_min=0.5))  # invalid: below range_min
    assert math.isinf(reading(1.2, range_max=1.0))  # invalid: beyond range_max
    assert math.isinf(reading(0.9, range_max=1.0))  # a return beyond the sensor's 0.6 m


def test_invalid_ranges_are_unknown_never_free() -> None:
    """NaN, 0.0 below range_min and ranges beyond range_max are no return; a sensor that then
    reads nothing is unknown, not free; infinities are valid (REP-117); issue 56, point 2."""
    n = 360
    inc = 2 * math.pi / n

    def read(ranges: np.ndarray, range_min: float = 0.12) -> tuple[tuple[int, ...], float]:
        got = readings_from_scan(LaserScanData(-math.pi, inc, range_min, 3.5, ranges),
                                 LidarMount(), UGV)  # fmt: skip
        return got.unknown_sensors, got.valid_share

    every = tuple(range(UGV.n_sensors))
    assert read(np.full(n, np.nan)) == (every, 0.0)
    assert read(np.zeros(n)) == (every, 0.0)  # 0.0, below range_min: no measurement
    assert read(np.full(n, np.inf)) == ((), 1.0)  # nothing within range_max: free
    alternating = np.where(np.arange(n) % 2 == 0, np.inf, -np.inf)
    assert read(alternating) == ((), 1.0)  # -inf: an object too near, read at range_min
    dropout = _wall_scan(1.0, n, range_max=3.5).ranges.copy()
    dropout[:90] = np.nan  # the rear quarter (angles -180 to -90 deg) reads nothing valid
    unknown, share = read(dropout)
    assert share == pytest.approx(0.75)
    assert unknown and 0 not in unknown and 1 not in unknown  # the front still sees the wall


def test_the_lidars_mount_is_taken_into_account() -> None:
    world = World(6.0)  # flat walls: every single ray reads exactly what the simulator reads
    pose = (2.0, 2.5, 0.4)
    physics = PymunkWorld(world, UGV)
    physics.add_robot("r", pose)
    truth = physics.ranges(pose, robot="r")
    single = UGV.ray_counts == 1
    # the lidar at the centre, off the centre and turned, and upside down
    for mount in (Transform2D(), Transform2D(0.1, -0.05, 0.0), Transform2D(-0.08, 0.04, 2.5)):
        spec = LidarSpec(N_RAYS, range_max=8.0, mount=mount)
        scan = _scan_of(physics, spec)
        got = readings_from_scan(scan, LidarMount(mount), UGV).readings
        np.testing.assert_allclose(got[single], truth[single], rtol=1e-6)
        assert (got[~single] <= truth[~single] + 1e-6).all()  # nearest in the beam
        # that lidar mounted upside down: its ray at angle a faces yaw - a
        upside = LaserScanData(-scan.angle_min - (N_RAYS - 1) * scan.angle_increment,
                               scan.angle_increment, 0.0, 8.0, scan.ranges[::-1])
        got_up = readings_from_scan(upside, LidarMount(mount, inverted=True), UGV).readings
        np.testing.assert_allclose(got_up, got, rtol=0, atol=1e-12)
        # a mount other than the lidar's gives other readings: the mount matters
        wrong = readings_from_scan(scan, LidarMount(mount.compose(Transform2D(0, 0, 1.0))), UGV)
        assert np.abs(np.minimum(wrong.readings, 4) - np.minimum(got, 4)).max() > 0.5


def test_a_scan_that_does_not_look_behind_leaves_rear_sensors_uncovered() -> None:
    n = 181
    inc = math.pi / (n - 1)
    scan = LaserScanData(-math.pi / 2, inc, 0.1, 8.0, np.full(n, 3.0))
    got = readings_from_scan(scan, LidarMount(), UGV)
    assert got.uncovered == (3, 4, 5, 6)  # facing 112.5 .. 247.5 deg
    assert np.isinf(got.readings[[3, 4, 5, 6]]).all()
    with pytest.raises(ValueError, match="ray width"):
        readings_from_scan(scan, LidarMount(), UGV, ray_width=-0.1)


def test_the_simulated_lidar_codes_rep117_and_draws_seeded_noise() -> None:
    world = World(4.0)
    physics = PymunkWorld(world, SWARM)
    physics.add_robot("r", (1.0, 2.0, 0.0))
    spec = LidarSpec(8, range_min=0.2, range_max=2.5)
    r = lidar_scan(physics, "r", spec)
    assert spec.angle_min == -math.pi and spec.angle_increment == pytest.approx(math.pi / 4)
    assert r[0] == pytest.approx(1.0)  # the left wall, behind
    assert np.isinf(r[4])  # 3 m to the right wall: beyond range_max
    near = lidar_scan(physics, "r", LidarSpec(8, range_min=1.5, range_max=2.5))
    assert near[0] == -math.inf  # the left wall 1 m away, nearer than range_min
    noisy = LidarSpec(8, range_max=2.5, noise=0.01)
    a = lidar_scan(physics, "r", noisy, np.random.default_rng(5))
    b = lidar_scan(physics, "r", noisy, np.random.default_rng(5))
    np.testing.assert_array_equal(a, b)  # same seed, same noise
    assert 0 < abs(a[0] - 1.0) < 0.05
    fov = LidarSpec(5, fov=math.pi)
    assert (fov.angle_min, fov.angle_max) == (pytest.approx(-math.pi / 2),
                                              pytest.approx(math.pi / 2))
    for bad in ({"rays": 1}, {"rays": 10, "fov": 7.0}, {"rays": 10, "range_min": 5.0},
                {"rays": 10, "noise": -1.0}):
        with pytest.raises(ValueError):
            LidarSpec(**bad)  # type: ignore[arg-type]


def _scan_of(physics: PymunkWorld, spec: LidarSpec) -> LaserScanData:
    r = lidar_scan(physics, "r", spec).astype(np.float32)
    return LaserScanData(spec.angle_min, spec.angle_increment, spec.range_min, spec.range_max, r)


@pytest.mark.parametrize(("profile", "share"), [(UGV, 0.97), (SWARM, 0.97)])
def test_a_720_ray_scan_gives_the_simulators_readings(profile: RobotProfile, share: float) -> None:
    world = training_scenarios(profile, 0, n=1)[0].world
    spec = LidarSpec(720, range_max=2 * profile.sensor_range)
    da, reach = spec.angle_increment, profile.sensor_range
    widths = fields_of_view(profile, 0.0)
    rng = np.random.default_rng(1)
    single, beam, phantoms = [], [], 0
    poses = 0
    while poses < 120:
        pose = (rng.uniform(0, world.size), rng.uniform(0, world.size), rng.uniform(-3, 3))
        physics = PymunkWorld(world, profile)
        if physics.collides(pose):
            continue
        poses += 1
        physics.add_robot("r", pose)
        truth = np.minimum(physics.ranges(pose, robot="r"), reach)
        got = np.minimum(readings_from_scan(_scan_of(physics, spec), LidarMount(),
                                            profile).readings, reach)
        frames = sensor_frames(np.array([pose]), profile)[0]
        for i, (ox, oy, facing) in enumerate(frames):
            tol = truth[i] * da + 1e-5
            (beam if profile.ray_counts[i] > 1 else single).append(
                got[i] <= truth[i] + tol if profile.ray_counts[i] > 1
                else abs(got[i] - truth[i]) <= tol
            )
            # the true nearest in the field widened by 2 increments, cast every 1/8 increment
            # or finer (its own sampling error: that step times the range)
            half = 0.5 * widths[i] + 2 * da
            n = max(33, int(16 * half / da) + 1)
            around = physics.cast((ox, oy), facing + np.linspace(-half, half, n), reach, "r")
            nearest = min(around.min(), reach)
            phantoms += bool(got[i] < nearest - nearest * 2 * half / (n - 1) - 1e-5)
    assert np.mean(single) >= share
    assert not beam or np.mean(beam) >= 0.99
    assert phantoms == 0


def test_a_scans_rays_sit_where_the_lidar_is_and_read_what_it_read() -> None:
    # four rays of a lidar 0.2 m ahead of the centre, turned 90 deg, on a robot at (1, 2)
    # facing +y: the lidar sits at (1, 2.2) facing -x
    scan = LaserScanData(0.0, math.pi / 2, 0.1, 5.0, [1.0, math.inf, -math.inf, math.nan])
    mount = LidarMount(Transform2D(0.2, 0.0, math.pi / 2))
    frames, readings = MountedScan(scan, mount).rays((1.0, 2.0, math.pi / 2))
    np.testing.assert_allclose(frames[:, :2], [[1.0, 2.2]] * 3, atol=1e-12)
    # headings pi, 3 pi / 2, 2 pi; a return, nothing within reach, one nearer than range_min
    np.testing.assert_allclose(frames[:, 2], [math.pi, 1.5 * math.pi, 2 * math.pi])
    np.testing.assert_array_equal(readings, [1.0, math.inf, 0.1])  # NaN: left out
    # upside down, the ray at angle a faces yaw - a
    upside = MountedScan(scan, LidarMount(mount.pose, inverted=True))
    np.testing.assert_allclose(upside.rays((1.0, 2.0, math.pi / 2))[0][:, 2],
                               [math.pi, math.pi / 2, 0.0], atol=1e-12)  # fmt: skip
