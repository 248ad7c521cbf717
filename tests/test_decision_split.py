"""Deciding more often than trained (``mentor_core.controller.decision_split``, a deployment's
``decisions_per_period``; not in the paper): each decision is that share of the trained step
and turn, so the robot is commanded the speeds it was trained to drive; the benchmark,
``mentor-eval``, the planner node and the launch files all run the shipped planners (their
shipped deployment) at half their trained period."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from mentor_core.benchmark.contenders import evolved
from mentor_core.cli import bench as bench_cli
from mentor_core.cli import evaluate as eval_cli
from mentor_core.controller.decision_split import at_control_period
from mentor_core.controller.deployment import Deployment, load_deployment
from mentor_core.errors import ConfigError
from mentor_core.files.bags import read_episode_bag
from mentor_core.runtime.planner import GenomePlanner, deployed_genome, genome_profile
from mentor_core.runtime.robot_graph import planner_period, robot_planners, simulator_period
from mentor_core.sim.robots import get_profile

REPO = Path(__file__).resolve().parents[1]
UGV_PLANNER = REPO / "planners" / "ugv-paper-dual-s1.json"  # trained every 0.5 s
SWARM_PLANNER = REPO / "planners" / "swarm-paper-dual-s1.json"  # every 1 s


def test_a_shorter_period_keeps_the_pace_the_turn_rate_and_the_time_budget() -> None:
    trained = genome_profile(UGV_PLANNER, "ugv")
    split = at_control_period(trained, trained.control_period / 2)
    assert split.control_period == 0.25
    assert split.step_max / split.control_period == pytest.approx(
        trained.step_max / trained.control_period)
    assert split.step_min / split.control_period == pytest.approx(
        trained.step_min / trained.control_period)
    assert split.heading_change_max / split.control_period == pytest.approx(
        trained.heading_change_max / trained.control_period)
    assert split.rated_speed == pytest.approx(trained.rated_speed)
    start, goal = (1.0, 1.0), (9.0, 7.0)
    assert split.time_budget(start, goal) == pytest.approx(trained.time_budget(start, goal))
    assert at_control_period(trained, None) is trained
    assert at_control_period(trained, trained.control_period) is trained


@pytest.mark.parametrize("bad", [0.0, -0.25, 0.75, math.nan, math.inf])
def test_a_period_longer_than_trained_or_not_positive_is_refused_naming_the_file(
    bad: float,
) -> None:
    with pytest.raises(ConfigError, match=r"g\.json.*control_period"):
        at_control_period(genome_profile(UGV_PLANNER, "ugv"), bad, "g.json")


@pytest.mark.parametrize("bad", ["0", "-2", "1.5", "17", "true", ".nan", "'2'"])
def test_decisions_per_period_must_be_a_whole_number_from_one_to_sixteen(bad: str) -> None:
    with pytest.raises(ConfigError, match=r"--set: decisions_per_period: "):
        load_deployment("none", "ugv", [f"decisions_per_period={bad}"])
    with pytest.raises(ConfigError, match="decisions_per_period"):
        Deployment(decisions_per_period=bad)  # type: ignore[arg-type]


def test_the_planner_commands_the_trained_speeds_at_half_the_period() -> None:
    """The same readings give the same Twist at 0.25 s as at 0.5 s: half the turn and half
    the step in half the time (where the step is not held back near an obstacle)."""
    trained = GenomePlanner.load(UGV_PLANNER, "ugv")
    split = GenomePlanner.load(UGV_PLANNER, "ugv", Deployment(decisions_per_period=2))
    assert split.profile.control_period == 0.25
    rng = np.random.default_rng(3)
    for _ in range(20):
        ranges = rng.uniform(2.0, 4.0, trained.profile.n_sensors)  # nothing near: no clamp
        pose = (*rng.uniform(0.0, 5.0, 2), rng.uniform(-math.pi, math.pi))
        goal = tuple(rng.uniform(0.0, 5.0, 2))
        (turn, step), (half_turn, half_step) = (
            p.decide(ranges, pose, goal) for p in (trained, split))
        assert half_turn == pytest.approx(turn / 2) and half_step == pytest.approx(step / 2)
        np.testing.assert_allclose(split.command(ranges, pose, goal),
                                   trained.command(ranges, pose, goal))  # fmt: skip


def test_the_shipped_planners_decide_twice_per_trained_period_when_deployed() -> None:
    ugv, swarm = get_profile("ugv"), get_profile("swarm")
    shipped_ugv = load_deployment("shipped", "ugv")[0]
    shipped_swarm = load_deployment("shipped", "swarm")[0]
    assert shipped_ugv.decisions_per_period == shipped_swarm.decisions_per_period == 2
    assert deployed_genome(UGV_PLANNER, "ugv", shipped_ugv)[1].profile.control_period == 0.25
    assert deployed_genome(SWARM_PLANNER, "swarm", shipped_swarm)[1].profile.control_period == 0.5
    deployed = evolved(UGV_PLANNER, ugv, deployment=shipped_ugv).profile
    assert deployed.control_period == 0.25 and deployed.step_max == 0.25
    assert deployed.heading_change_max == pytest.approx(math.radians(22.5))
    deployed = evolved(SWARM_PLANNER, swarm, deployment=shipped_swarm).profile
    assert deployed.control_period == 0.5 and deployed.step_max == pytest.approx(0.04)
    once = load_deployment("shipped", "ugv", ["decisions_per_period=1"])[0]
    again = evolved(UGV_PLANNER, ugv, deployment=once).profile
    assert again.control_period == 0.5 and again.step_max == 0.5
    # as trained (no deployment): the trained period
    assert evolved(UGV_PLANNER, ugv).profile.control_period == 0.5


def test_a_shipped_deployment_session_steps_at_the_deployed_period(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.chdir(REPO)
    ugv = "planners/ugv-paper-dual-s1.json"
    (shipped,) = robot_planners(["ugv"], {"ugv": ugv}, deployment="shipped")
    (plain,) = robot_planners(["ugv"], {"ugv": ugv})
    assert shipped.options["deployment"] == "shipped"
    assert planner_period(shipped) == 0.25 and planner_period(plain) == 0.5
    assert simulator_period([shipped], continuous=False) == 0.25
    assert simulator_period([plain], continuous=False) == 0.5


def test_the_command_lines_take_a_period_and_refuse_a_bad_one_in_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    common = [str(UGV_PLANNER), "--robot", "ugv", "--families", "rooms",
              "--pairs-per-family", "2", "--baselines", "none", "--no-oracle"]  # fmt: skip
    runs = (([], 0.5), (["--set", "decisions_per_period=2"], 0.25),
            (["--deployment", "shipped"], 0.25),
            (["--deployment", "shipped", "--set", "decisions_per_period=1"], 0.5))
    for i, (extra, period) in enumerate(runs):
        out = tmp_path / f"bench{i}"
        assert bench_cli.main([*common, *extra, "--out", str(out)]) == 0
        settings = json.loads((out / "bench.json").read_text())["contenders"][0]["settings"]
        assert settings["control_period"] == period and settings["step_max"] == period
    for main in (bench_cli.main, eval_cli.main):
        robot = ["--robot", "ugv"] if main is bench_cli.main else ["--bag", "bags/unseen/ugv"]
        for bad in ("0", "1.5", "17"):
            capsys.readouterr()
            assert main([str(UGV_PLANNER), *robot, "--set", f"decisions_per_period={bad}"]) == 2
            err = capsys.readouterr().err
            assert "decisions_per_period" in err and len(err.strip().splitlines()) == 1


def test_a_recording_steps_at_the_period_the_planners_decide_at(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """``mentor-eval --deployment shipped --record``: the bag's simulator steps every 0.25 s,
    as the UGV's planner decides, so every episode ends as the table says; genomes of two
    periods are refused in one line before anything is written."""
    bag = tmp_path / "bag"
    common = [str(UGV_PLANNER), "--bag", "bags/unseen/ugv", "--deployment", "shipped"]
    assert eval_cli.main([*common, "--record", str(bag)]) == 0
    err = capsys.readouterr().err
    assert "recorded 10 episodes" in err and "in the recording" not in err
    assert read_episode_bag(bag).metadata["control_period"] == 0.25
    genome = json.loads(UGV_PLANNER.read_text())
    genome["metadata"]["control_period"] = 1.0  # a genome trained to decide every 1 s
    slow = tmp_path / "slow.json"
    slow.write_text(json.dumps(genome))
    assert eval_cli.main([str(UGV_PLANNER), str(slow), "--bag", "bags/unseen/ugv",
                          "--record", str(tmp_path / "mixed")]) == 2  # fmt: skip
    err = capsys.readouterr().err.strip().splitlines()
    assert "different periods (0.5, 1 s)" in err[-1] and not (tmp_path / "mixed").exists()
