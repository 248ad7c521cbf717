"""The robot the closed-loop tests play: its streams at their own rates, the base's limits,
collisions, and the faults real sensors have."""

from __future__ import annotations

import numpy as np
import pytest

from mentor_core.runtime.streamed_robot import FAULTS, StreamedRobot, StreamSpec
from mentor_core.sim.robots import get_profile
from mentor_core.sim.world import World

WORLD = World(10.0, np.array([[6.0, 0.0, 7.0, 10.0]]))  # a wall across at x 6-7


def _run(robot: StreamedRobot, seconds: float) -> list:
    ticks = []
    while robot.time < seconds - 1e-9:
        ticks.append(robot.step())
    return ticks


def test_scans_at_5_hz_and_odometry_at_30_hz_of_sim_time() -> None:
    robot = StreamedRobot(WORLD, get_profile("ugv"), (3.0, 5.0, 0.0))
    ticks = _run(robot, 2.0)
    # the first at the first tick, then every 0.2 s and every 1/30 s up to 2.0 s
    assert sum(t.scan is not None for t in ticks) == 11
    assert sum(t.odometry is not None for t in ticks) == 60
    scan = next(t.scan for t in ticks if t.scan is not None)
    assert scan.shape == (360,)
    ahead = scan[180]  # the ray straight ahead (angle 0 of -pi..pi)
    assert ahead == pytest.approx(6.0 - 3.0 + 0.032, abs=0.05)  # lidar 3.2 cm behind centre


def test_the_base_clips_commands_to_its_limits_and_a_wall_stops_it() -> None:
    robot = StreamedRobot(WORLD, get_profile("ugv"), (4.0, 5.0, 0.0))
    robot.command = (1.0, 0.0)  # far beyond the Burger's 0.22 m/s
    _run(robot, 1.0)
    assert robot.velocity[0] == pytest.approx(0.22)  # reached within 0.1 s at 2.5 m/s^2
    _run(robot, 12.0)
    assert robot.collisions >= 1 and robot.velocity == (0.0, 0.0)
    assert robot.pose[0] < 6.0 - robot.spec.body[0] / 2 + 1e-9  # stopped at the wall


@pytest.mark.parametrize("fault", FAULTS[1:])
def test_faults_spoil_what_is_streamed(fault: str) -> None:
    robot = StreamedRobot(WORLD, get_profile("ugv"), (2.0, 5.0, 0.0), StreamSpec(), seed=2)
    robot.fault = fault
    ticks = _run(robot, 1.0)
    scans = [t.scan for t in ticks if t.scan is not None]
    odometry = [t.odometry for t in ticks if t.odometry is not None]
    if fault == "scan_stop":
        assert not scans and odometry
    elif fault == "odom_stop":
        assert scans and not odometry
    else:
        assert scans and odometry
        bad = scans[0]
        if fault == "scan_nan":
            assert np.isnan(bad).all()
        elif fault == "scan_zero":
            assert (bad == 0.0).all()
        else:
            assert np.isposinf(bad[::2]).all() and np.isneginf(bad[1::2]).all()
