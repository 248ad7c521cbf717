"""mentor-eval: the genome's input encoding, and --record writing the episodes as a bag."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from memory_support import latch

from mentor_core.cli.evaluate import main as mentor_eval
from mentor_core.errors import ConfigError
from mentor_core.evolution.genome import Genome, genome_from_edges
from mentor_core.files.bags import read_episode_bag, read_scenario_bag
from mentor_core.files.genome_file import save_genome
from mentor_core.runtime.planner import GenomePlanner, planner_profile
from mentor_core.runtime.recording import record_planners, recorded_episodes
from mentor_core.runtime.simulator import RobotSetup, run_reference_episode
from mentor_core.sim.observation import action_from_twist
from mentor_core.sim.planner_settings import with_planner
from mentor_core.sim.robots import get_profile, sensor_record

ROOT = Path(__file__).resolve().parents[1]
UNSEEN_SWARM = ROOT / "bags" / "unseen" / "swarm"
SWARM = get_profile("swarm")


def homing_genome() -> Genome:
    """Swarm-Robot planner: turn towards sin(bearing) (input 4), full step (bias 6)."""
    return genome_from_edges(6, 2, [(4, 7, 2.0), (6, 8, 1.0)])


def test_a_genome_plans_with_the_encoding_its_metadata_names() -> None:
    assert planner_profile(SWARM, {}).input_encoding == "paper"  # saved before the key
    assert planner_profile(SWARM, {"input_encoding": "egocentric"}).input_encoding == (
        "egocentric"
    )
    with pytest.raises(ConfigError, match=r"g\.json: input_encoding"):
        planner_profile(SWARM, {"input_encoding": 3}, "g.json")
    assert planner_profile(SWARM, {}).heading_change_max == SWARM.heading_change_max
    assert planner_profile(SWARM, {"heading_change_max": 0.5}).heading_change_max == 0.5
    with pytest.raises(ConfigError, match=r"g\.json: heading_change_max"):
        planner_profile(SWARM, {"heading_change_max": "wide"}, "g.json")
    assert planner_profile(SWARM, {}).step_max == SWARM.step_max
    assert planner_profile(SWARM, {"step_max": 0.04}).step_max == 0.04
    with pytest.raises(ConfigError, match=r"g\.json: step_max"):
        planner_profile(SWARM, {"step_max": 1.0}, "g.json")
    trained = sensor_record(SWARM)
    assert planner_profile(SWARM, {"sensors": trained}) == planner_profile(SWARM, {})
    trained["sensor_range"] = 0.5  # trained on another robot file
    with pytest.raises(ConfigError, match=r"g\.json: sensors: .*other sensors"):
        planner_profile(SWARM, {"sensors": trained}, "g.json")


def test_recorded_episodes_are_the_reference_episodes(tmp_path: Path) -> None:
    world, scenarios, _, _ = read_scenario_bag(UNSEEN_SWARM)
    path = tmp_path / "g.json"
    save_genome(homing_genome(), path, metadata={"input_encoding": "egocentric"})
    planner = GenomePlanner.load(path, "swarm")
    still = GenomePlanner(genome_from_edges(6, 2, []), SWARM)  # outputs 0.5: straight on
    recorder, traces = record_planners(
        world, SWARM, {"robot_0": planner.decide, "robot_1": still.decide}, scenarios[:3], 50.0
    )
    recorder.save(tmp_path / "bag", SWARM)
    runs = recorded_episodes(read_episode_bag(tmp_path / "bag"), tmp_path / "bag")
    expected = [(ns, k) for ns in ("robot_0", "robot_1") for k in range(3)]
    assert [(r.setup.name, r.setup.scenario) for r in runs] == expected
    for run, (ns, k) in zip(runs, expected, strict=True):
        trace = traces[ns][k]
        assert run.outcome == trace.outcome and run.setup.time_budget == 50.0
        assert len(run.scans) == len(run.commands) == trace.steps
        poses = [o.pose for o in run.odometry][: trace.steps + 1]
        np.testing.assert_allclose(poses, trace.poses, atol=1e-12)  # heading as a quaternion
        np.testing.assert_array_equal([s.ranges for s in run.scans], trace.ranges)
        back = [action_from_twist(c.angular_z, c.linear_x, 1.0) for c in run.commands]
        np.testing.assert_allclose(np.array(back, dtype=float), trace.decisions, atol=1e-15)
    assert {t.outcome for t in traces["robot_0"]} <= {"reached", "collided", "timed_out"}


def test_a_planner_with_a_memory_starts_every_recorded_episode_blank() -> None:
    world, scenarios, _, _ = read_scenario_bag(UNSEEN_SWARM)
    profile = with_planner(SWARM, memory_units=1)
    planner = GenomePlanner(latch(profile), profile)
    _, traces = record_planners(
        world, SWARM, {"robot_0": planner.decide}, scenarios[:3], 5.0,
        resets={"robot_0": planner.reset},
    )  # fmt: skip
    fresh = [run_reference_episode(world, [RobotSetup("r", SWARM, sc.start, sc.goal, k, 5.0)],
                                   {"r": GenomePlanner(latch(profile), profile).decide})["r"]
             for k, sc in enumerate(scenarios[:3])]  # fmt: skip
    for trace, alone in zip(traces["robot_0"], fresh, strict=True):
        np.testing.assert_array_equal(trace.decisions, alone.decisions)
        assert trace.decisions[0, 0] == -np.pi  # a blank memory: a full right turn first


def test_mentor_eval_records_a_bag_and_never_overwrites_one(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    genome = tmp_path / "g.json"
    save_genome(homing_genome(), genome, metadata={"input_encoding": "egocentric"})
    bag, out = tmp_path / "episodes", tmp_path / "eval.json"
    args = [str(genome), "--bag", str(UNSEEN_SWARM), "--record", str(bag), "--out", str(out)]
    assert mentor_eval(args) == 0
    doc = json.loads(out.read_text())
    runs = recorded_episodes(read_episode_bag(bag), bag)
    assert len(runs) == len(doc["runs"][0]["results"]) == 10
    assert "recorded 10 episodes" in capsys.readouterr().err
    before = sorted(p.stat().st_mtime_ns for p in bag.iterdir())
    assert mentor_eval(args[:-2]) == 2  # without --out: the bag alone is refused
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and str(bag) in err and "already exists" in err
    assert sorted(p.stat().st_mtime_ns for p in bag.iterdir()) == before
    assert mentor_eval([*args, "--force"]) == 0  # replaced, all or nothing
    assert len(recorded_episodes(read_episode_bag(bag), bag)) == 10


def test_mentor_eval_refuses_an_unknown_encoding(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    genome = tmp_path / "g.json"
    save_genome(homing_genome(), genome, metadata={"input_encoding": "polar"})
    assert mentor_eval([str(genome), "--bag", str(UNSEEN_SWARM)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and str(genome) in err and "polar" in err
