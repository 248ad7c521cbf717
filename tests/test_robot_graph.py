"""Which robots a simulated session starts and the planner each runs
(``mentor_core.runtime.robot_graph``), shared by the ``demo`` executable and
``mentor.launch.py``; and the launch files' own use of it (``mentor.launch.py``,
``planner.launch.py``), run here with stand-ins for ``launch`` (no PyPI wheel), so that
their logic runs on a pip-only machine too."""

from __future__ import annotations

import importlib.util
import sys
import types
from pathlib import Path
from typing import Any

import pytest

from mentor_core import ConfigError, FileFormatError, MentorError, get_profile
from mentor_core.benchmark.contenders import evolved
from mentor_core.controller.collision_guard import CollisionGuardStage
from mentor_core.controller.deployment import load_deployment
from mentor_core.controller.rotation_shim import RotationShim
from mentor_core.controller.turn_gain import TurnGain
from mentor_core.controller.view_corridor import ViewCorridor
from mentor_core.runtime.planner import deployed_genome
from mentor_core.runtime.robot_graph import (
    default_genome,
    parse_genomes,
    planner_period,
    robot_names,
    robot_planners,
    simulator_period,
)

ROOT = Path(__file__).resolve().parents[1]
UGV = "planners/ugv-paper-dual-s1.json"  # decides every 0.5 s
SWARM = "planners/swarm-paper-dual-s1.json"  # every 1 s


@pytest.fixture(autouse=True)
def _in_root(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(ROOT)  # the default genomes are paths from the repository root


def test_robots_are_named_by_profile_and_count() -> None:
    assert robot_names(["ugv", "ugv", "swarm", "ugv"]) == ["ugv_0", "ugv_1", "swarm_0", "ugv_2"]


def test_genomes_are_given_per_profile() -> None:
    assert parse_genomes([f"ugv={UGV}", f" swarm = {SWARM} "]) == {"ugv": UGV, "swarm": SWARM}
    for bad in ("ugv", "=g.json", "ugv="):
        with pytest.raises(MentorError, match="expected PROFILE=FILE"):
            parse_genomes([bad])


def test_each_robot_plans_with_its_profiles_genome_or_the_reference() -> None:
    planners = robot_planners(["ugv", "swarm", "ugv"], {"ugv": UGV})
    assert [(p.namespace, p.profile, p.genome) for p in planners] == [
        ("ugv_0", "ugv", UGV),
        ("swarm_0", "swarm", default_genome("swarm")),
        ("ugv_1", "ugv", UGV),
    ]
    assert planners[1].parameters == {"genome": default_genome("swarm"), "profile": "swarm"}
    named = robot_planners(["ugv", "ugv"], names=["/left", "right"], continuous=True)
    assert [p.namespace for p in named] == ["left", "right"]
    assert all(p.parameters["decide_on_timer"] for p in named)


#: the shipped deployments' stages
SHIPPED_STAGES = {
    "ugv": (RotationShim(threshold_deg=45.0), CollisionGuardStage(memory=3)),
    "swarm": (ViewCorridor(margin=0.1), TurnGain(gain=0.75), RotationShim(threshold_deg=45.0),
              CollisionGuardStage(memory=3)),
}  # fmt: skip


@pytest.mark.parametrize("robot, genome", [("ugv", UGV), ("swarm", SWARM)])
def test_shipped_planners_run_as_the_benchmark_scores_them(robot: str, genome: str) -> None:
    """The node parameters of ``deployment="shipped"`` give the planner node (which loads
    them as ``mentor_planner_node.params`` does) the planner that ``mentor-bench --deployment
    shipped`` scores: the same stages, period and scan map."""
    (planner,) = robot_planners([robot], {robot: genome}, deployment="shipped")
    values = planner.parameters
    assert values == {"genome": genome, "profile": robot, "deployment": "shipped"}
    deployment = load_deployment(values["deployment"], values["profile"])[0]
    node = deployed_genome(values["genome"], values["profile"], deployment)[1]
    bench = evolved(ROOT / genome, get_profile(robot), deployment=deployment)
    assert node.stages == bench.stages == SHIPPED_STAGES[robot]
    assert node.guide is not None and node.guide == bench.guide
    assert node.guide.clearance_cost == (1.0 if robot == "swarm" else 0.0)
    assert planner_period(planner) == node.profile.control_period == bench.profile.control_period
    assert planner_period(planner) == (0.5 if robot == "swarm" else 0.25)


def test_a_bad_robot_list_is_refused_in_one_line(tmp_path: Path) -> None:
    with pytest.raises(MentorError, match="no robot"):
        robot_planners([])
    with pytest.raises(MentorError, match="tank"):
        robot_planners(["ugv", "tank"])
    with pytest.raises(MentorError, match="a genome for swarm, but no robot of that profile"):
        robot_planners(["ugv"], {"swarm": SWARM})
    with pytest.raises(MentorError, match="1 robot names for 2 profiles"):
        robot_planners(["ugv", "ugv"], names=["a"])
    missing = str(tmp_path / "gone.json")
    with pytest.raises(FileFormatError, match=f"{missing}: no such genome file"):
        robot_planners(["ugv"], {"ugv": missing})
    # a deployment that cannot be read, before any node starts
    with pytest.raises(FileFormatError, match=r"gone\.yaml: no such file"):
        robot_planners(["ugv"], deployment=str(tmp_path / "gone.yaml"))
    bad = tmp_path / "bad.yaml"
    bad.write_text("decisions_per_period: 0\n")
    with pytest.raises(ConfigError, match="decisions_per_period: must be >= 1") as err:
        robot_planners(["ugv", "swarm"], {"ugv": UGV}, deployment=str(bad))
    assert "\n" not in str(err.value)


def test_the_simulator_steps_at_the_genomes_period() -> None:
    both = robot_planners(["ugv", "swarm"], {"ugv": UGV, "swarm": SWARM})
    assert simulator_period(both[:1], continuous=False) == 0.5
    assert simulator_period(both[1:], continuous=False) == 1.0
    # continuous: each planner on its own timer, the simulator at the shortest period
    assert simulator_period(both, continuous=True) == 0.5
    with pytest.raises(MentorError, match=r"different periods \(0.5, 1 s\); run them with -c"):
        simulator_period(both, continuous=False, continuous_hint="-c")
    # as deployed: at twice the decisions of their genomes
    shipped = robot_planners(["ugv", "swarm"], {"ugv": UGV, "swarm": SWARM},
                             deployment="shipped")  # fmt: skip
    assert [planner_period(p) for p in shipped] == [0.25, 0.5]
    assert simulator_period(shipped, continuous=True) == 0.25
    with pytest.raises(MentorError, match=r"different periods \(0.25, 0.5 s\)"):
        simulator_period(shipped, continuous=False)


# --- the launch files with stand-ins for launch, launch_ros and ament_index_python ---------


class _Config:
    def __init__(self, name: str) -> None:
        self.name = name

    def perform(self, context: dict[str, str]) -> str:
        return context[self.name]


class _Node:
    def __init__(self, **kwargs: Any) -> None:
        self.kwargs = kwargs


def _module(name: str, **attrs: Any) -> types.ModuleType:
    module = types.ModuleType(name)
    module.__dict__.update(attrs)
    return module


class _Value:
    def __init__(self, value: Any, value_type: type | None = None) -> None:
        self.value, self.value_type = value, value_type


def _load(monkeypatch: pytest.MonkeyPatch, package: str, file: str) -> types.ModuleType:
    """The launch file ``<package>/launch/<file>`` run with the stand-ins."""
    stubs = {
        "launch": _module("launch", LaunchContext=dict, LaunchDescription=list),
        "launch.actions": _module("launch.actions", DeclareLaunchArgument=object,
                                  OpaqueFunction=object),
        "launch.substitutions": _module("launch.substitutions", LaunchConfiguration=_Config),
        "launch_ros": _module("launch_ros"),
        "launch_ros.actions": _module("launch_ros.actions", Node=_Node),
        "launch_ros.parameter_descriptions": _module("launch_ros.parameter_descriptions",
                                                     ParameterValue=_Value),
        "ament_index_python": _module("ament_index_python"),
        "ament_index_python.packages": _module("ament_index_python.packages",
                                               get_package_share_directory=str),
    }  # fmt: skip
    for name, stub in stubs.items():
        monkeypatch.setitem(sys.modules, name, stub)
    path = ROOT / package / "launch" / file
    spec = importlib.util.spec_from_file_location(f"{package}_launch_under_test", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture()
def launch_file(monkeypatch: pytest.MonkeyPatch) -> types.ModuleType:
    return _load(monkeypatch, "mentor_sim_node", "mentor.launch.py")


@pytest.fixture()
def planner_launch_file(monkeypatch: pytest.MonkeyPatch) -> types.ModuleType:
    return _load(monkeypatch, "mentor_planner_node", "planner.launch.py")


def _launch(module: types.ModuleType, **arguments: str) -> list[dict[str, Any]]:
    context = {**module.ARGUMENTS, **arguments}
    return [node.kwargs for node in module._nodes(context)]


def test_the_launch_file_starts_one_planner_per_robot_of_one_profile(
    launch_file: types.ModuleType,
) -> None:
    sim, *planners = _launch(launch_file, robots="robot_0,robot_1", lidar_rays="360")
    (sim_values,) = sim["parameters"]
    assert sim_values["robots"] == ["robot_0", "robot_1"]
    assert sim_values["profiles"] == ["ugv", "ugv"]
    assert sim_values["control_period"] == 1.0  # the reference genome's: the paper's 1 s
    assert [p["namespace"] for p in planners] == ["robot_0", "robot_1"]
    assert all(p["remappings"] == [("scan", "lidar/scan")] for p in planners)
    (values,) = planners[0]["parameters"]
    assert values == {"genome": default_genome("ugv"), "profile": "ugv", "use_sim_time": True}


def test_the_launch_file_runs_shipped_planners_of_two_robots_as_deployed(
    launch_file: types.ModuleType,
) -> None:
    arguments = {"profiles": "ugv,swarm", "genomes": f"ugv={UGV},swarm={SWARM}",
                 "deployment": "shipped"}  # fmt: skip
    with pytest.raises(MentorError, match="continuous:=true"):
        _launch(launch_file, **arguments)
    sim, ugv, swarm = _launch(launch_file, continuous="true", **arguments)
    (sim_values,) = sim["parameters"]
    assert sim_values["robots"] == ["ugv_0", "swarm_0"]
    assert sim_values["profiles"] == ["ugv", "swarm"]
    assert sim_values["control_period"] == 0.25  # the UGV's deployed period, the shorter
    assert sim_values["real_time_factor"] == 1.0
    (values,) = swarm["parameters"]
    assert values == {"genome": SWARM, "profile": "swarm", "deployment": "shipped",
                      "decide_on_timer": True, "use_sim_time": True}  # fmt: skip
    assert ugv["namespace"] == "ugv_0" and ugv["parameters"][0]["deployment"] == "shipped"
    # no deployment: the planners' parameters name none (the node's default, "none")
    _, plain = _launch(launch_file, robots="robot_0")
    assert "deployment" not in plain["parameters"][0]


def test_the_planner_launch_file_starts_a_preset_with_the_arguments_given_on_top(
    planner_launch_file: types.ModuleType,
) -> None:
    """``robot:=`` names the preset's parameter file (installed in the package's share); an
    argument left empty keeps its value, one given goes on top; the namespace and the
    remappings reach the node, and ``rviz:=true`` starts RViz2 in that namespace."""
    module = planner_launch_file
    (node,) = _launch(module, robot="turtlebot3_burger")
    preset, given = node["parameters"]
    assert str(preset).endswith("config/turtlebot3_burger.yaml") and given == {}
    assert node["namespace"] == "" and ("scan", "scan") in node["remappings"]
    nodes = _launch(module, robot="turtlebot3_waffle", namespace="tb3_0", genome=UGV,
                    deployment="my_deployment.yaml", goal_radius="0.4", scan="/lidar",
                    params_file="mine.yaml", rviz="true")  # fmt: skip
    planner, rviz = nodes
    preset, mine, given = planner["parameters"]
    assert str(preset).endswith("turtlebot3_waffle.yaml") and mine == "mine.yaml"
    assert given == {"genome": UGV, "deployment": "my_deployment.yaml", "goal_radius": 0.4}
    assert planner["namespace"] == "tb3_0" and ("scan", "/lidar") in planner["remappings"]
    assert rviz["package"] == "rviz2" and rviz["namespace"] == "tb3_0"
    assert str(rviz["arguments"][1]).endswith("config/mentor.rviz")
    with pytest.raises(MentorError, match="robot:=tb4: no preset"):
        _launch(module, robot="tb4")
    with pytest.raises(MentorError, match="goal_radius:=far: expected a number"):
        _launch(module, goal_radius="far")


def test_the_launch_files_refuse_a_mistyped_argument_in_one_line(
    launch_file: types.ModuleType,
) -> None:
    for name, text in (("continuous", "maybe"), ("rviz", "ture"), ("lidar_rays", "-3"),
                       ("real_time_factor", "fast")):  # fmt: skip
        with pytest.raises(MentorError, match=f"{name}:={text}: expected"):
            _launch(launch_file, **{name: text})
    # a deployment that is neither none, shipped nor a file: one line naming it
    with pytest.raises(FileFormatError, match="shiped: no such file"):
        _launch(launch_file, deployment="shiped")
