"""Deployments as data (issue 54): the shipped ones load and validate, a user's file and
``--set`` changes are checked with one-line errors naming the key, a layer is added by one
module and one line of a deployment file (a toy layer here), and a planner runs the same
decision chain in the batched episodes and on its own (the planner node's way)."""

from __future__ import annotations

import json
import textwrap
from pathlib import Path

import numpy as np
import pytest

from mentor_core.benchmark.contenders import evolved
from mentor_core.controller.collision_guard import CollisionGuardStage
from mentor_core.controller.deployment import (
    BUILT_IN,
    Deployment,
    deploy,
    load_deployment,
    shipped_deployments,
    trained_stages,
)
from mentor_core.controller.episodes import run_episodes
from mentor_core.controller.rotation_shim import RotationShim
from mentor_core.controller.view_corridor import ViewCorridor
from mentor_core.errors import ConfigError
from mentor_core.evolution.network import FeedForwardNetwork
from mentor_core.runtime.planner import GenomePlanner, deployed_genome
from mentor_core.sim.robots import get_profile
from mentor_core.sim.scenarios import sample_scenarios, sample_world

UGV_GENOME = Path("planners/ugv-paper-dual-s1.json")
SWARM_GENOME = Path("planners/swarm-paper-dual-s1.json")

TOY_LAYER = '''
"""A toy layer: the network's turn mirrored (a left turn becomes a right one)."""
from typing import Any

import numpy as np

from mentor_core import Stage, StageRun, config_dataclass


@config_dataclass
class Mirror(Stage):
    name = "mirror"
    share: float = 1.0

    def start(self, n: int, profile: Any, arena: Any) -> StageRun:
        return _MirrorRun(self.share)

    def record(self) -> dict[str, Any]:
        return {"mirror": self.share}


class _MirrorRun(StageRun):
    def __init__(self, share: float) -> None:
        self.share = share

    def outputs(self, robots: Any, outputs: Any, inputs: Any) -> Any:
        out = np.array(outputs, dtype=np.float64)
        out[:, 0] = 1.0 - out[:, 0] * self.share
        return out
'''


def _scenarios(robot: str, n: int = 6, seed: int = 3) -> list:
    profile = get_profile(robot)
    rng = np.random.default_rng(seed)
    world = sample_world(profile.test_arena, rng)
    return sample_scenarios(world, profile, n, rng)


def test_the_shipped_deployments_load_for_both_robots_and_name_their_stages_in_order() -> None:
    assert set(shipped_deployments()) == {"ugv", "swarm"}
    ugv, _ = load_deployment("shipped", "ugv")
    swarm, _ = load_deployment("shipped", "swarm")
    assert ugv.decisions_per_period == swarm.decisions_per_period == 2
    assert ugv.scan_map is not None and swarm.scan_map is not None
    assert [s.name for s in ugv.build()] == ["rotation_shim", "collision_guard"]
    assert [s.name for s in swarm.build()] == [
        "view_corridor", "turn_gain", "rotation_shim", "collision_guard"]
    assert load_deployment("none", "ugv")[0] == Deployment()


def test_a_deployment_runs_its_genome_at_a_share_of_the_trained_period() -> None:
    _, trained = deployed_genome(UGV_GENOME, "ugv")
    _, shipped = deployed_genome(UGV_GENOME, "ugv", load_deployment("shipped", "ugv")[0])
    assert shipped.profile.control_period == trained.profile.control_period / 2
    assert shipped.profile.step_max == pytest.approx(trained.profile.step_max / 2)
    assert shipped.guide is not None and trained.guide is None


def test_a_genomes_trained_stages_run_unless_the_deployment_names_them() -> None:
    metadata = {"view_margin": 0.2, "rotation_shim": np.radians(30.0)}
    trained = trained_stages(metadata)
    assert trained[0] == ViewCorridor(margin=0.2)
    assert isinstance(trained[1], RotationShim)
    assert trained[1].threshold_deg == pytest.approx(30.0)
    profile = get_profile("swarm")
    deployment = load_deployment("none", "swarm", ["stages.turn_gain.gain=0.5",
                                                   "stages.view_corridor.margin=0.1"])[0]
    stages = deploy(profile, trained, deployment).stages
    # the built-in order: the gain before the trained shim, which keeps its full turn
    assert [s.name for s in stages] == ["view_corridor", "turn_gain", "rotation_shim"]
    assert stages[0] == ViewCorridor(margin=0.1)
    dropped = load_deployment("none", "swarm", ["stages.view_corridor=null"])[0]
    assert [s.name for s in deploy(profile, trained, dropped).stages] == ["rotation_shim"]
    with pytest.raises(ConfigError, match=r"rotation_shim: must be a number in \(0, pi\] rad"):
        trained_stages({"rotation_shim": 10.0}, "g.json")


def test_built_in_stages_run_in_one_order_whatever_order_they_are_given() -> None:
    deployment = load_deployment("shipped", "ugv", ["stages.turn_gain.gain=0.5"])[0]
    assert list(deployment.stages)[-1] == "turn_gain"  # --set appends it
    assert [s.name for s in deployment.build()] == [
        "turn_gain", "rotation_shim", "collision_guard"]


@pytest.mark.parametrize(
    ("settings", "fault"),
    [
        (["stages.turn_gain.gain=2"], "stages.turn_gain.gain: must be <= 1"),
        (["stages.turn_gain.gian=1"], "stages.turn_gain.gian"),
        (["stages.teleport.distance=1"], "stages.teleport: no such stage"),
        (["decisions_per_period=0"], "decisions_per_period: must be >= 1"),
        (["decisions_per_period=1.5"], "decisions_per_period: expected a whole number"),
        (["scan_map.lookahead=-1"], "scan_map.lookahead: must be > 0"),
        (["stages.rotation_shim.threshold_deg=270"], "stages.rotation_shim.threshold_deg"),
        (["stages.odd.plugin=no_such_module:Layer"], "stages.odd.plugin: cannot load"),
        (["stages.odd.plugin=mentor_core.errors:ConfigError"], "is not a Stage"),
        (["stages.odd.plugin=nocolon"], 'expected "module:Class"'),
        (["turn_gain"], "--set: expected KEY=VALUE"),
    ],
)
def test_a_bad_setting_is_one_line_naming_the_key(settings: list[str], fault: str) -> None:
    with pytest.raises(ConfigError) as err:
        load_deployment("shipped", "swarm", settings)
    text = str(err.value)
    assert fault in text and "\n" not in text


def test_a_deployment_file_is_checked_with_its_name_in_the_error(tmp_path: Path) -> None:
    path = tmp_path / "mine.yaml"
    path.write_text("stages:\n  collision_guard: {memory: 0}\n", encoding="utf-8")
    with pytest.raises(ConfigError, match=r"mine.yaml: stages.collision_guard.memory"):
        load_deployment(path, "ugv")
    path.write_text("- a list\n", encoding="utf-8")
    with pytest.raises(ConfigError, match=r"mine\.yaml: expected a mapping"):
        load_deployment(path, "ugv")
    with pytest.raises(ConfigError, match=r"no shipped deployment for robot .tank."):
        load_deployment("shipped", "tank")


def test_a_stage_dropped_with_set_is_gone_and_another_setting_keeps_the_rest() -> None:
    deployment = load_deployment("shipped", "swarm", ["stages.turn_gain=null",
                                                      "stages.collision_guard.memory=5"])[0]
    assert [s.name for s in deployment.build()] == [
        "view_corridor", "rotation_shim", "collision_guard"]
    assert CollisionGuardStage(memory=5) in deployment.build()
    assert set(BUILT_IN) >= {"view_corridor", "turn_gain", "rotation_shim", "collision_guard"}


def test_a_toy_layer_is_one_module_and_one_line_of_a_deployment_file(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    (tmp_path / "toy_layer.py").write_text(textwrap.dedent(TOY_LAYER), encoding="utf-8")
    monkeypatch.syspath_prepend(str(tmp_path))
    path = tmp_path / "toy.yaml"
    path.write_text('stages:\n  mirror: {plugin: "toy_layer:Mirror"}\n', encoding="utf-8")
    deployment = load_deployment(path, "ugv")[0]
    profile = get_profile("ugv")
    scenarios = _scenarios("ugv")
    mirrored = evolved(UGV_GENOME, profile, "toy", deployment)
    assert [s.name for s in mirrored.stages] == ["mirror"]
    batch = run_episodes(scenarios, mirrored.profile, mirrored.policy(scenarios),
                         stages=mirrored.stages)

    # the same network with its turn mirrored by hand, no stage
    genome, plain = deployed_genome(UGV_GENOME, "ugv")
    network = FeedForwardNetwork.from_genome(genome)
    inner = network.episode_policy(len(scenarios))

    def by_hand(inputs: np.ndarray, robots: np.ndarray) -> np.ndarray:
        out = np.array(inner(inputs, robots), dtype=np.float64)
        out[:, 0] = 1.0 - out[:, 0]
        return out

    expected = run_episodes(scenarios, plain.profile, by_hand)
    unmirrored = run_episodes(scenarios, plain.profile, network.episode_policy(len(scenarios)))
    np.testing.assert_array_equal(batch.trajectories, expected.trajectories)
    assert not np.array_equal(batch.trajectories, unmirrored.trajectories)

    with pytest.raises(ConfigError, match=r"stages\.mirror\.share"):
        load_deployment(path, "ugv", ["stages.mirror.share=left"])


@pytest.mark.parametrize(("genome", "robot"), [(UGV_GENOME, "ugv"), (SWARM_GENOME, "swarm")])
def test_a_planner_on_its_own_decides_as_the_batched_episodes_of_its_deployment(
    genome: Path, robot: str
) -> None:
    """The planner node's planner (a batch of one) and the benchmark's episodes run one decision
    chain: fed the readings and poses of a batched episode, it answers the same actions."""
    deployment = load_deployment("shipped", robot, ["scan_map=null"])[0]
    g, deployed = deployed_genome(genome, robot, deployment)
    scenario = _scenarios(robot, n=1, seed=5)
    profile = deployed.profile
    batch = run_episodes(scenario, profile, FeedForwardNetwork.from_genome(g).episode_policy(1),
                         stages=deployed.stages)
    planner = GenomePlanner(g, profile, arena=scenario[0].world.size, stages=deployed.stages)
    from mentor_core.sim.sensors import sensor_readings

    goal = np.asarray(scenario[0].goal)
    k = profile.n_sensors
    for t in range(int(batch.steps[0])):
        pose = batch.trajectories[0, t]
        seen = sensor_readings(pose[None], profile, scenario[0].world)[0]
        dtheta, ds = planner.decide(seen, pose, goal)
        row = batch.experience[0][t]
        np.testing.assert_allclose(row[:k], np.minimum(seen, profile.sensor_range))
        assert (dtheta, ds) == (row[k], row[k + 1])


def test_bench_json_lists_the_stages_settings(tmp_path: Path) -> None:
    from mentor_core.cli.bench import main

    out = tmp_path / "bench"
    code = main([str(SWARM_GENOME), "--robot", "swarm", "--families", "rooms",
                 "--pairs-per-family", "1", "--baselines", "none", "--no-oracle",
                 "--deployment", "shipped", "--set", "stages.turn_gain.gain=0.5",
                 "--out", str(out)])  # fmt: skip
    assert code == 0
    settings = json.loads((out / "bench.json").read_text())["contenders"][0]["settings"]
    assert settings["turn_gain"] == 0.5 and settings["collision_guard"] is True
    assert settings["view_margin"] == 0.1 and settings["control_period"] == 0.5


@pytest.mark.parametrize(
    ("module_text", "fault"),
    [
        ("raise RuntimeError('broken plugin')", "cannot load 'bad_layer:Layer': RuntimeError"),
        ("from mentor_core import Stage\nclass Layer(Stage):\n    name = 'layer'\n",
         "is not a config dataclass"),
    ],
)
def test_a_plugin_that_cannot_serve_is_one_line(
    module_text: str, fault: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    (tmp_path / "bad_layer.py").write_text(module_text, encoding="utf-8")
    monkeypatch.syspath_prepend(str(tmp_path))
    with pytest.raises(ConfigError) as err:
        load_deployment("none", "ugv", ['stages.odd.plugin="bad_layer:Layer"'])
    assert fault in str(err.value) and "stages.odd.plugin" in str(err.value)


def test_mentor_eval_refuses_set_with_two_deployments_and_a_recording_of_two_periods(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    from mentor_core.cli.evaluate import main as eval_main

    base = [str(UGV_GENOME), "--bag", "bags/unseen/ugv", "--deployment", "none",
            "--deployment", "shipped"]  # fmt: skip
    assert eval_main([*base, "--set", "stages.turn_gain.gain=0.5"]) == 2
    assert "give one --deployment with --set" in capsys.readouterr().err
    out = tmp_path / "eval.json"
    assert eval_main([*base, "--record", str(tmp_path / "bag"), "--out", str(out)]) == 2
    err = capsys.readouterr()
    assert "different periods (0.25, 0.5 s)" in err.err
    assert "success" not in err.out and not out.exists()  # refused before any run


def test_mentor_bench_pursuit_needs_a_genome(capsys: pytest.CaptureFixture[str]) -> None:
    from mentor_core.cli.bench import main as bench_main

    assert bench_main(["--robot", "ugv", "--pursuit"]) == 2
    assert "--pursuit takes the place of a genome's network" in capsys.readouterr().err
