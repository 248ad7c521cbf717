"""Plans on the scan map made beside the decisions (issue 57): at once, a set number of
decisions late, or on a thread; the decision follows the latest plan it has."""

from __future__ import annotations

import threading
import time

import numpy as np
import pytest

from mentor_core.navigation.grid import OccupancyGrid
from mentor_core.navigation.grid_planner import GridPlanner
from mentor_core.navigation.guide import guide_config
from mentor_core.navigation.plan_worker import DelayedPlans, PlanJob, ThreadPlans
from mentor_core.navigation.scan_map import ScanGuide, scan_guide_config
from mentor_core.sim.robots import get_profile

UGV = get_profile("ugv")
EMPTY = OccupancyGrid(0.05, (0.0, 0.0, 0.0), np.zeros((200, 200), dtype=np.int8))


def job(goal: tuple[float, float], owner: object = None) -> PlanJob:
    return PlanJob(owner, lambda: EMPTY, (1.0, 1.0), goal, guide_config(UGV))


def test_delayed_plans_hand_each_plan_back_that_many_polls_late() -> None:
    worker = DelayedPlans(2)
    worker.submit(job((8.0, 8.0)))
    worker.submit(job((5.0, 5.0)))  # waits its turn: the latest one only
    worker.submit(job((6.0, 6.0)))
    assert worker.busy and worker.poll() is None
    first = worker.poll()
    assert first is not None and first.goal == (8.0, 8.0) and first.path is not None
    assert worker.poll() is None
    second = worker.poll()
    assert second is not None and second.goal == (6.0, 6.0)
    assert not worker.busy and worker.poll() is None
    with pytest.raises(ValueError, match="at least 1"):
        DelayedPlans(0)


def test_a_thread_makes_the_latest_plan_and_the_caller_never_waits(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    release = threading.Event()
    plan = GridPlanner.plan

    def held(self: GridPlanner, start: object, goal: object) -> object:
        release.wait(10.0)
        return plan(self, start, goal)  # type: ignore[arg-type]

    monkeypatch.setattr(GridPlanner, "plan", held)
    worker = ThreadPlans()
    try:
        worker.submit(job((8.0, 8.0)))
        time.sleep(0.05)
        worker.submit(job((5.0, 5.0)))
        worker.submit(job((6.0, 6.0)))  # replaces (5, 5), not started
        assert worker.busy and worker.poll() is None  # returns at once while it plans
        release.set()
        done = []
        deadline = time.monotonic() + 10.0
        while len(done) < 2 and time.monotonic() < deadline:
            got = worker.poll()
            if got is not None:
                done.append(got.goal)
            time.sleep(0.01)
        assert done in ([(8.0, 8.0), (6.0, 6.0)], [(6.0, 6.0)])  # a poll may miss the first
        assert not worker.busy
    finally:
        worker.close()


def test_with_a_delay_the_guide_follows_the_goal_until_the_plan_comes() -> None:
    config = scan_guide_config(UGV)
    guide = ScanGuide(12.0, config, worker=DelayedPlans(3))
    wall = np.array([[4.0, y, 0.0] for y in np.arange(3.0, 9.0, 0.2)])  # rays onto x = 6
    goal = (10.0, 6.0)
    aims, paths = [], []
    for _ in range(5):
        aims.append(guide.target(wall, np.full(len(wall), 2.0), 4.0, (2.0, 6.0), goal))
        paths.append(guide.guide.path is not None)
    assert aims[0] == goal  # asked at the first decision, steering to the goal meanwhile
    assert paths == [False, False, False, True, True]  # the fourth decision adopted it
    assert aims[-1] != goal  # steering round the wall, along the plan
    assert guide.plans >= 1


def test_a_plan_for_a_replaced_guide_is_not_followed() -> None:
    worker = DelayedPlans(1)
    config = scan_guide_config(UGV)
    old = ScanGuide(12.0, config, worker=worker)
    old.target(np.zeros((0, 3)), np.zeros(0), 4.0, (2.0, 6.0), (10.0, 6.0))
    new = ScanGuide(12.0, config, worker=worker)  # a new episode, the same worker
    new._asked = ((10.0, 6.0), 0.0)  # it asked for the same goal, on its own map
    new.target(np.zeros((0, 3)), np.zeros(0), 4.0, (2.0, 6.0), (10.0, 6.0))
    assert new.guide.path is None  # the old guide's plan was not taken


def test_a_failing_plan_leaves_the_thread_planning() -> None:
    worker = ThreadPlans()
    try:
        worker.submit(PlanJob(None, lambda: 1 / 0, (1.0, 1.0), (8.0, 8.0),  # type: ignore[arg-type,return-value]
                              guide_config(UGV)))  # fmt: skip
        deadline = time.monotonic() + 10.0
        while worker.busy and time.monotonic() < deadline:
            time.sleep(0.01)
        assert worker.error.startswith("ZeroDivisionError") and worker.poll() is None
        worker.submit(job((8.0, 8.0)))
        got = None
        while got is None and time.monotonic() < deadline:
            got = worker.poll()
            time.sleep(0.01)
        assert got is not None and got.path is not None
    finally:
        worker.close()


@pytest.mark.parametrize("delay", [0, 2])
def test_a_growing_map_plans_from_an_empty_start(delay: int) -> None:
    # no size to set: the first rays and the goal make the map; a wall ahead is planned round
    import dataclasses

    config = dataclasses.replace(scan_guide_config(UGV), plan_delay=delay)
    guide = ScanGuide(None, config)
    assert guide.map.hits.size == 0
    wall = np.array([[-2.0, y, 0.0] for y in np.arange(-3.0, 3.0, 0.2)])  # rays onto x = 0
    for _ in range(4):
        aim = guide.target(wall, np.full(len(wall), 2.0), 4.0, (-4.0, 0.0), (4.0, 0.0))
    assert guide.map.growing and guide.map.hits.size > 0
    assert guide.guide.path is not None and aim != (4.0, 0.0)
    assert guide.map.blocks((0.0, 0.0), 0.1)
