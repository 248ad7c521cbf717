"""The planner node on a robot that is not this project's simulator: a TurtleBot3 Burger played
by a script (a 360-ray lidar at 5 Hz, 3.2 cm behind its centre, odometry at 30 Hz, the
Burger's limits), driven at the ``turtlebot3_burger`` preset's parameters and nothing else
(issue 56, point 6)."""

from __future__ import annotations

import time

import pytest
from ros_support import Graph
from scripted_support import Burger, goal_msg

from mentor_core.navigation.grid_planner import GridPlanner

pytestmark = pytest.mark.ros

def test_the_burger_preset_reaches_goals_through_a_door(graph: Graph) -> None:
    burger = Burger(graph, (3.0, 2.5, 1.0))
    runs = burger.drive((7.0, 5.5))
    assert [r.status for r in runs] == ["reached"], runs
    assert runs[0].collisions == 0 and runs[0].left <= 0.5
    assert burger.planner.goals_reached == 1
    # then it publishes nothing: a teleoperator may drive
    sent = burger.robot.commands
    burger.run(2.0)
    assert burger.robot.commands == sent


@pytest.mark.parametrize("fault", ["scan_nan", "scan_zero", "scan_inf", "scan_stop",
                                   "odom_stop"])  # fmt: skip
def test_bad_data_stops_the_robot_before_the_wall(
    graph: Graph, capfd: pytest.CaptureFixture[str], fault: str
) -> None:
    """Failed before: an all-NaN or all-zero scan read as free space drove the robot into a
    box it had mapped; stopped odometry or scans re-sent the last command until the stale
    timeout (0.9-1.6 m blind)."""
    burger = Burger(graph, (1.0, 4.6, 0.0))
    burger.goal.publish(goal_msg((9.0, 4.6)))  # through the door: straight on at first
    deadline = burger.sim.time + 20.0
    while burger.sim.velocity[0] < 0.15:
        assert burger.sim.time < deadline, "the robot never drove"
        burger.goal.publish(goal_msg((9.0, 4.6)))
        burger.run(0.2)
    burger.sim.fault = fault
    x0 = burger.sim.pose[0]
    # staleness is judged on the wall clock, the run goes at twice real time: 2 s of sim time
    # leaves room for a loaded machine (before: 0.9-1.6 m blind, 4-7 s at 0.22 m/s)
    burger.run(2.0)
    assert burger.sim.velocity == (0.0, 0.0)
    assert burger.sim.pose[0] - x0 < 0.45
    stopped = burger.sim.pose
    burger.run(1.0)  # and stays stopped while the fault lasts
    assert burger.sim.pose == stopped and burger.sim.collisions == 0
    err = capfd.readouterr().err
    assert "stopping" in err or "watchdog" in err


def test_a_goal_in_a_box_the_scans_have_seen_is_refused(graph: Graph) -> None:
    burger = Burger(graph, (1.7, 6.0, 0.0))
    runs = burger.drive((3.5, 6.0))  # past the box at x 2-3, y 6.5-7.5: its side sensors
    assert runs[0].status == "reached"  # read its face (y 6.5) into the scan map
    burger.statuses.clear()
    burger.goal.publish(goal_msg((2.5, 6.55)))  # just behind that face
    burger.run(0.5)
    refused = [s for s in burger.statuses if s.startswith("goal refused")]
    assert refused and "lies in an obstacle the scans have seen" in refused[0]
    assert not any(s.startswith("accepted") for s in burger.statuses)
    assert burger.sim.collisions == 0


def test_a_slow_planner_leaves_the_controller_on_time(
    graph: Graph, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Issue 57: deciding on its timer, the node plans on the scan map beside the decisions;
    with every plan made to take 0.8 s (three control periods) it still decides every period,
    on the older plan meanwhile, and reaches the goal."""
    plan = GridPlanner.plan

    def slow(self: GridPlanner, start: object, goal: object) -> object:
        time.sleep(0.8)
        return plan(self, start, goal)  # type: ignore[arg-type]

    monkeypatch.setattr(GridPlanner, "plan", slow)
    burger = Burger(graph, (3.0, 2.5, 1.0))
    t0, decided = burger.sim.time, burger.planner.decisions
    runs = burger.drive((7.0, 5.5))
    assert [r.status for r in runs] == ["reached"], runs
    assert runs[0].collisions == 0
    scan = burger.planner.global_plan.planner.scan
    assert scan.map.growing  # the preset sets no size: the map grows from the first pose
    assert burger.planner.global_plan._map_sent is not None  # sent from the plan thread
    assert len(scan.plan_seconds) >= 2 and min(scan.plan_seconds) >= 0.8
    periods = (burger.sim.time - t0) / burger.planner.control_period
    assert burger.planner.decisions - decided >= 0.9 * periods


def test_the_scan_map_holds_every_ray_of_the_lidar(graph: Graph) -> None:
    """The shipped UGV deployment maps the whole scan (``scan_map.whole_scan``, E100): after
    a few decisions the map holds more obstacle cells than the sensors' rays could have ended
    in (one each a decision)."""
    burger = Burger(graph, (3.0, 2.5, 1.0))
    burger.goal.publish(goal_msg((7.0, 5.5)))
    burger.run(1.0)
    planner = burger.planner
    scan = planner.global_plan.planner.scan
    assert scan.guide.config.whole_scan and planner.decisions >= 1
    assert scan.map.occupied.sum() > 3 * planner.decisions * planner.profile.n_sensors
