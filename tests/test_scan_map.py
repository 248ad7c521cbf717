"""The map a robot builds from its own readings, and the plan on it."""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from mentor_core.controller.episodes import run_episodes
from mentor_core.navigation.grid import FREE, OCCUPIED, UNKNOWN
from mentor_core.navigation.guide import guide_config
from mentor_core.navigation.scan_map import (
    ScanGuide,
    ScanMap,
    scan_guide_config,
    scan_guided_goals,
    scan_map_resolution,
)
from mentor_core.runtime.guided_planner import ScanGuidedPlanner
from mentor_core.runtime.planner import GenomePlanner
from mentor_core.sim.lidar import LidarSpec, lidar_scan
from mentor_core.sim.pymunk_world import PymunkWorld
from mentor_core.sim.robots import get_profile
from mentor_core.sim.scan_adapter import LaserScanData, LidarMount, MountedScan, readings_from_scan
from mentor_core.sim.sensors import sensor_frames, sensor_readings
from mentor_core.sim.world import Scenario, World

UGV = get_profile("ugv")
REGRESSION = Path(__file__).resolve().parents[1] / "bags" / "regression"
# a wall across the middle of a 12 m arena, open at its top end
WALL = World(12.0, np.array([[5.9, 0.0, 6.1, 9.0]]))


def test_the_map_cell_is_a_quarter_of_the_footprint_radius_at_least_25_mm() -> None:
    assert scan_map_resolution(UGV) == 0.05  # the cells chosen on the validation split
    assert scan_map_resolution(get_profile("swarm")) == 0.025  # the floor


def test_a_ray_clears_the_cells_before_its_hit_and_marks_the_hit() -> None:
    scan = ScanMap(12.0, 0.1)
    new = scan.update([[2.0, 4.5, 0.0]], [3.0], max_range=4.0)  # hits x = 5.0
    np.testing.assert_allclose(new, [[5.05, 4.55]])
    row = scan.data[45]
    assert (row[20:49] == FREE).all() and row[50] == OCCUPIED and row[51] == UNKNOWN
    assert scan.update([[2.0, 4.5, 0.0]], [3.0], max_range=4.0).size == 0  # nothing new
    assert scan.data[45, 50] == OCCUPIED
    # out of range: free all the way, no hit
    scan.update([[1.05, 2.0, math.pi / 2]], [math.inf], max_range=4.0)
    assert (scan.data[20:59, 10] == FREE).all() and (scan.data[61:, 10] == UNKNOWN).all()
    # a hit stays while no more rays pass its cell than ended there (two hits, then passes)
    for passes in (1, 2, 3):
        scan.update([[5.05, 1.0, math.pi / 2]], [math.inf], max_range=4.0)
        assert scan.data[45, 50] == (OCCUPIED if passes <= 2 else FREE)


def test_a_map_from_another_origin_is_the_same_map_moved() -> None:
    # the planner node's map lies in the odometry frame, its lower-left corner anywhere
    here, there = ScanMap(12.0, 0.1), ScanMap(12.0, 0.1, origin=(-64.0, 32.0))
    # (rays off the cells' edges: a sample on an edge may round either way in either frame)
    rays = np.array([[2.013, 4.537, 0.0], [1.071, 2.029, math.pi / 2], [7.261, 7.243, 2.5]])
    shift = np.array([-64.0, 32.0])
    moved = np.concatenate([rays[:, :2] + shift, rays[:, 2:]], axis=1)
    new = here.update(rays, [3.0, math.inf, 1.5], max_range=4.0)
    new_there = there.update(moved, [3.0, math.inf, 1.5], max_range=4.0)
    assert (here.data == OCCUPIED).sum() == 2 and (here.data == FREE).sum() > 60
    np.testing.assert_array_equal(here.data, there.data)
    np.testing.assert_allclose(new_there, new + shift[None, :])
    assert there.grid().origin[:2] == (-64.0, 32.0)


def test_a_beam_reading_lies_on_every_ray_of_its_cone() -> None:
    scan = ScanMap(12.0, 0.1)
    cone = [[2.0, 4.5, a] for a in (-0.2, 0.0, 0.2)]
    scan.update(cone, [3.0, 3.0, 3.0], max_range=4.0)
    rows, cols = np.nonzero(scan.data == OCCUPIED)
    ends = np.array([[2.0 + 3.0 * math.cos(a), 4.5 + 3.0 * math.sin(a)] for a in (-0.2, 0, 0.2)])
    np.testing.assert_array_equal(
        sorted(zip(rows.tolist(), cols.tolist(), strict=True)),
        sorted((int(y / 0.1), int(x / 0.1)) for x, y in ends),
    )


def test_the_plan_goes_round_a_wall_once_the_robot_has_read_it() -> None:
    guide = ScanGuide(12.0, guide_config(UGV, resolution=0.1))
    start, goal = np.array([3.0, 4.0, 0.0]), (9.0, 4.0)
    frames = sensor_frames(start[None], UGV)[0]
    aim_blind = guide.target(frames, np.full(UGV.n_sensors, np.inf), UGV.sensor_range,
                             start[:2], goal)  # fmt: skip
    assert abs(aim_blind[1] - 4.0) < 1e-9  # unknown is free: straight at the goal
    near = np.array([5.4, 4.0, 0.0])  # facing the wall 0.5 m ahead
    readings = sensor_readings(near[None], UGV, WALL)[0]
    aim = guide.target(sensor_frames(near[None], UGV)[0], readings, UGV.sensor_range,
                       near[:2], goal)  # fmt: skip
    assert guide.plans == 1
    # round the part of the wall it has seen (the rest is unknown, so planned as free)
    path = guide.guide.path
    assert path is not None and path[:, 1].max() > 4.5
    assert abs(aim[1] - 4.0) > 0.3  # the network is sent along the wall, not into it


def test_every_robot_plans_on_its_own_map() -> None:
    open_world = World(12.0, np.zeros((0, 4)))
    scenarios = [Scenario(WALL, (3.0, 4.0, 0.0), (9.0, 4.0)),
                 Scenario(open_world, (3.0, 4.0, 0.0), (9.0, 4.0))]  # fmt: skip

    def stand(inputs: np.ndarray, robots: np.ndarray) -> np.ndarray:
        return np.tile([0.5, 0.0], (len(robots), 1))  # no turn, the smallest step

    inner = slice(56, 62)  # x 5.6-6.2 m: the inner wall, and the arcs a cone puts before it
    for arcs in (True, False):
        config = guide_config(UGV, resolution=0.1)
        goals, guides = scan_guided_goals(scenarios, UGV, config, beam_arcs=arcs)
        run_episodes(scenarios, UGV, stand, time_budgets=3.0, input_goals=goals)
        # only the front beams face the wall: without arcs they clear the way and mark nothing
        assert (guides[0].map.data[:, inner] == OCCUPIED).any() == arcs
        assert (guides[0].map.data[40, 35:55] == FREE).all()
        assert not (guides[1].map.data[:, inner] == OCCUPIED).any()  # robot 1's world: none


def test_a_single_ray_sensor_counts_once_beside_the_beams() -> None:
    open_world = World(12.0, np.zeros((0, 4)))
    pose = np.array([[6.0, 6.0, 0.0]])
    goals, guides = scan_guided_goals([Scenario(open_world, (6.0, 6.0, 0.0), (9.0, 6.0))], UGV,
                                      guide_config(UGV, resolution=0.1))  # fmt: skip
    goals(pose, np.array([0]))
    frame = sensor_frames(pose, UGV)[0, 2]  # left-front: one ray, away from the front cones
    x, y = frame[:2] + 2.0 * np.array([math.cos(frame[2]), math.sin(frame[2])])
    assert guides[0].map.misses[int(y / 0.1), int(x / 0.1)] == 1


def test_a_kept_map_plans_the_next_goal_round_what_was_read() -> None:
    genome = REGRESSION / "ugv_reference_genome.json"
    mapped = ScanGuidedPlanner(GenomePlanner.load(genome, "ugv"), scan_guide_config(UGV), 12.0)
    for y in np.arange(1.0, 8.5, 0.25):  # along the wall, its right side 0.5 m off it
        pose = np.array([5.4, y, math.pi / 2])
        mapped.decide(sensor_readings(pose[None], UGV, WALL)[0], pose, (9.0, 4.0))
    read = mapped.scan.map.data
    cell = scan_map_resolution(UGV)
    wall = slice(round(5.9 / cell), round(6.1 / cell))  # the wall's columns, x 5.9-6.1 m
    assert (read[:, wall] == OCCUPIED).sum() > 3.0 / cell  # every few cells of y 1-8 m
    start, blind = np.array([3.0, 4.0, 0.0]), np.full(UGV.n_sensors, np.inf)

    mapped.reset(keep_map=True)  # the next goal, in the same place: the map stays
    np.testing.assert_array_equal(mapped.scan.map.data, read)
    mapped.decide(blind, start, (9.0, 4.5))
    path = mapped.guide.path
    assert path is not None and (np.abs(path[:, 1] - 4.25) > 0.5).any()  # round the wall read

    mapped.reset()  # a new goal as benchmarked (or a new episode): an empty map
    assert (mapped.scan.map.data == UNKNOWN).all()
    mapped.decide(blind, start, (9.0, 4.5))
    path = mapped.guide.path
    assert path is not None and (np.abs(path[:, 1] - 4.25) < 0.3).all()  # straight through


def test_the_swarm_robots_plan_passes_a_gap_its_hard_disc_closed() -> None:
    # two boxes 0.27 m apart (four of its body widths) either side of the way to the goal;
    # its two angled sensors read one each. The hard disc of the footprint's radius plus a
    # whole margin closes the gap between the two hits and sends the robot round; with the
    # clearance cost it keeps half the margin there and goes straight on
    swarm = get_profile("swarm")
    gap = World(4.0, np.array([[1.8, 1.5, 2.0, 1.865], [1.8, 2.135, 2.0, 2.5]]))
    pose = np.array([1.7, 2.0, 0.0])
    readings = sensor_readings(pose[None], swarm, gap)[0]
    assert np.isfinite(readings[[0, 2]]).all() and np.isinf(readings[1])
    paths = {}
    for cost in (None, 0.0):
        guide = ScanGuide(4.0, scan_guide_config(swarm, clearance_cost=cost))
        guide.read(pose, readings, (3.0, 2.0), swarm)
        paths[cost] = guide.guide.path
    assert paths[None] is not None and np.allclose(paths[None], [[1.7, 2.0], [3.0, 2.0]])
    assert paths[0.0] is not None and np.abs(paths[0.0][:, 1] - 2.0).max() > 0.2
    # the UGV keeps its hard disc (its mazes lost with the cost on the validation split)
    assert scan_guide_config(UGV).clearance_cost == 0.0
    assert scan_guide_config(swarm).hard_inflation == pytest.approx(1.5 * swarm.half_diagonal)


def _numpy_update(hits, misses, origin, res, rays, readings, max_range, located):
    """The scan map's update as it was in numpy (before the compiled kernel): the reference."""
    n = hits.shape[0]

    def cells(y, x):
        rows = np.clip(np.floor((y - origin[1]) / res).astype(np.int64), 0, n - 1)
        cols = np.clip(np.floor((x - origin[0]) / res).astype(np.int64), 0, n - 1)
        return rows, cols

    before = (hits > 0) & (hits >= misses)
    hit = np.isfinite(readings) & (readings < max_range)
    reach = np.where(hit, readings, max_range)
    step = 0.5 * res
    t = np.arange(math.ceil(max_range / step)) * step
    along = t[None, :] < reach[:, None] - step
    cos, sin = np.cos(rays[:, 2]), np.sin(rays[:, 2])
    rows, cols = cells(rays[:, 1, None] + sin[:, None] * t, rays[:, 0, None] + cos[:, None] * t)
    ray = np.broadcast_to(np.arange(len(rays))[:, None], along.shape)
    passed = np.unique((ray[along] * n + rows[along]) * n + cols[along]) % (n * n)
    np.add.at(misses.reshape(-1), passed, 1)
    hit &= located
    ends = cells(rays[hit, 1] + sin[hit] * reach[hit], rays[hit, 0] + cos[hit] * reach[hit])
    np.add.at(hits.reshape(-1), np.unique(ends[0] * n + ends[1]), 1)
    rows, cols = np.nonzero((hits > 0) & (hits >= misses) & ~before)
    return np.stack([(cols + 0.5), (rows + 0.5)], axis=1) * res + origin


def test_the_compiled_update_counts_as_the_numpy_one_did() -> None:
    # cell for cell, rays leaving the map (border cells) and readings out of range included
    rng = np.random.default_rng(11)
    origin, res, size = (-1.0, 0.5), 0.05, 6.0
    scan = ScanMap(size, res, origin)
    n = scan.hits.shape[0]
    hits, misses = np.zeros((n, n), np.int64), np.zeros((n, n), np.int64)
    for _ in range(40):
        k = 60
        rays = np.c_[rng.uniform(-1.5, 5.5, (k, 2)), rng.uniform(-np.pi, np.pi, k)]
        readings = np.where(rng.random(k) < 0.2, np.inf, rng.uniform(0.0, 3.5, k))
        located = rng.random(k) < 0.7
        got = scan.update(rays, readings, 3.0, located)
        want = _numpy_update(hits, misses, origin, res, rays, readings, 3.0, located)
        np.testing.assert_array_equal(got, want)
        np.testing.assert_array_equal(scan.hits, hits)
        np.testing.assert_array_equal(scan.misses, misses)
        np.testing.assert_array_equal(scan.occupied, (hits > 0) & (hits >= misses))
    assert scan.occupied.any() and (scan.misses > 0).any()


def test_a_growing_map_holds_every_ray_and_rolls_at_its_bound() -> None:
    res = 0.05
    grow = ScanMap(None, res, max_cells=256 * 256)
    assert grow.hits.size == 0 and not grow.blocks((0.0, 0.0), 0.2)
    far = ScanMap(40.0, res, (-20.0, -20.0))  # a fixed map holding all of it, the reference
    for x in (0.0, 3.0, 6.0):  # the robot drives east, reading a wall 2 m north
        rays = np.array([[x, 0.0, np.pi / 2], [x, 0.0, 0.0]])
        for m in (grow, far):
            m.update(rays, [2.0, np.inf], 3.5)
        assert grow.blocks((x, 2.0), 0.1) and far.blocks((x, 2.0), 0.1)
    # the cells it holds are the fixed map's, on the same lattice (a point on a cell's edge
    # may fall either side: the two origins round differently)
    rows0 = round((grow.origin[1] - far.origin[1]) / res)
    cols0 = round((grow.origin[0] - far.origin[0]) / res)
    h, w = grow.hits.shape
    same = far.hits[rows0 : rows0 + h, cols0 : cols0 + w]
    assert (grow.hits != same).sum() <= 4 and (
        grow.misses != far.misses[rows0 : rows0 + h, cols0 : cols0 + w]
    ).mean() < 0.01
    assert far.hits.sum() == grow.hits.sum()  # nothing lost before the bound
    assert h * w <= 256 * 256
    # driving on past the bound (12.8 m square) it rolls: what is far behind is forgotten
    for x in np.arange(9.0, 30.0, 3.0):
        grow.update(np.array([[x, 0.0, np.pi / 2]]), [2.0], 3.5)
    assert grow.hits.size <= 256 * 256 and grow.nbytes <= 256 * 256 * 5
    assert grow.blocks((27.0, 2.0), 0.1) and not grow.blocks((0.0, 2.0), 0.1)


def test_a_lidars_whole_scan_maps_an_obstacle_between_the_sensors() -> None:
    """With ``whole_scan`` and the scan the readings were read off, the map holds what every
    lidar ray saw: a post 2 m to the UGV's left, between its sensors at 67.5 and 112.5 deg,
    whose rays pass 0.6 m wide of it, is on the map, and the plan to a goal beyond it goes
    round it. Without ``whole_scan`` (or without the scan) only the sensors' readings count."""
    post = World(12.0, np.array([[5.8, 7.8, 6.2, 8.2]]))
    pose, goal = np.array([6.0, 6.0, 0.0]), (6.0, 10.0)
    physics = PymunkWorld(post, UGV)
    physics.add_robot("r", tuple(pose))
    spec = LidarSpec(360, range_max=UGV.sensor_range)
    data = LaserScanData(spec.angle_min, spec.angle_increment, spec.range_min, spec.range_max,
                         lidar_scan(physics, "r", spec))  # fmt: skip
    scan = MountedScan(data, LidarMount())
    readings = readings_from_scan(data, LidarMount(), UGV).readings
    assert np.isinf(readings).all()  # no sensor sees it
    genome = GenomePlanner.load(REGRESSION / "ugv_reference_genome.json", "ugv")
    config = scan_guide_config(UGV)
    sensors = ScanGuidedPlanner(genome, config, 12.0)
    lidar = ScanGuidedPlanner(genome, replace(config, whole_scan=True), 12.0)
    sensors.decide(readings, pose, goal, scan)
    lidar.decide(readings, pose, goal, scan)
    cell = scan_map_resolution(UGV)
    at_post = np.s_[round(7.7 / cell) : round(8.3 / cell), round(5.8 / cell) : round(6.2 / cell)]
    assert not (sensors.scan.map.data[at_post] == OCCUPIED).any()
    assert (lidar.scan.map.data[at_post] == OCCUPIED).any()
    straight, path = sensors.guide.path, lidar.guide.path
    assert straight is not None and np.abs(straight[:, 0] - 6.0).max() < 0.05
    assert path is not None and np.abs(path[:, 0] - 6.0).max() > 0.3  # round the post
