"""The pure pursuit in a network's place (issue 55, "what carries the result"): it turns onto
the goal the network is shown and drives at it, under the same deployment, and mentor-bench
runs one per distinct planner setting, apart from the baselines."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from mentor_core.benchmark.contenders import evolved, pursuit_of
from mentor_core.benchmark.pursuit import pursuit_outputs
from mentor_core.cli.bench import main as bench_main
from mentor_core.controller.deployment import load_deployment
from mentor_core.controller.rotation_shim import goal_bearing
from mentor_core.report.head_to_head import baseline_choice
from mentor_core.sim import observation
from mentor_core.sim.robots import get_profile

UGV_S1 = Path("planners/ugv-paper-dual-s1.json")
UGV_S2 = Path("planners/ugv-paper-dual-s2.json")


@pytest.mark.parametrize("bearing_deg", [-170.0, -60.0, -20.0, 0.0, 10.0, 44.0, 90.0])
def test_it_turns_onto_the_goal_and_steps_long_only_once_the_goal_lies_within_a_turn(
    bearing_deg: float,
) -> None:
    profile = evolved(UGV_S1, get_profile("ugv")).profile
    beta = math.radians(bearing_deg)
    pose = np.array([[2.0, 3.0, 0.4]])
    goal = pose[:, :2] + 3.0 * np.array([[math.cos(0.4 + beta), math.sin(0.4 + beta)]])
    ranges = np.full((1, profile.n_sensors), np.inf)
    context = observation.initial_context(1, profile)
    inputs = observation.network_inputs(ranges, pose, goal, profile, context)
    assert goal_bearing(inputs, profile)[0] == pytest.approx(beta)
    out = pursuit_outputs(inputs, profile)
    assert out.shape == (1, profile.n_outputs)
    dtheta, ds = observation.actions_from_outputs(out, profile, ranges)
    h = profile.heading_change_max
    assert dtheta[0] == pytest.approx(float(np.clip(beta, -h, h)))
    assert ds[0] == pytest.approx(profile.step_max if abs(beta) <= h else profile.step_min)
    assert not out[:, 2:].any()


def test_a_pursuit_keeps_its_planners_deployment_but_not_its_network() -> None:
    deployment = load_deployment("shipped", "ugv")[0]
    planner = evolved(UGV_S1, get_profile("ugv"), "dual-s1", deployment)
    pursuit = pursuit_of(planner)
    assert (pursuit.name, pursuit.kind) == ("pursuit-dual-s1", "pursuit")
    assert pursuit.profile == planner.profile and pursuit.stages == planner.stages
    assert pursuit.guide == planner.guide and pursuit.make_goals is planner.make_goals
    assert pursuit.make_policy is not planner.make_policy


def test_mentor_bench_runs_one_pursuit_per_planner_setting_apart_from_the_baselines(
    tmp_path: Path,
) -> None:
    out = tmp_path / "bench"
    code = bench_main([str(UGV_S1), str(UGV_S2), "--label", "s1", "--label", "s2", "--robot",
                       "ugv", "--families", "rooms", "--pairs-per-family", "2", "--baselines",
                       "vfh", "--no-oracle", "--deployment", "shipped", "--pursuit",
                       "--out", str(out)])  # fmt: skip
    assert code == 0
    doc = json.loads((out / "bench.json").read_text())
    kinds = {c["name"]: c["kind"] for c in doc["contenders"]}
    # the two seeds share their settings: one pursuit
    assert [n for n, k in kinds.items() if k == "pursuit"] == ["pursuit-s1"]
    pursuit = next(c for c in doc["contenders"] if c["kind"] == "pursuit")
    planner = next(c for c in doc["contenders"] if c["name"] == "s1")
    assert pursuit["settings"] == planner["settings"]
    assert pursuit["scan_map"] == planner["scan_map"]
    # the best baseline of each family is chosen among the baselines alone
    choice = baseline_choice(doc, "paper")
    baselines = {n for n, k in kinds.items() if k == "baseline"}
    assert {"vfh", "guard-vfh", "mapped-vfh", "mapped-guard-vfh"} <= baselines
    assert {name for row in choice.values() for name in row.values()} <= baselines
