"""Which robots a simulated session starts and the planner each runs
(``mentor_core.runtime.robot_graph``), shared by the ``demo`` executable and
``mentor.launch.py``; and the launch files' own use of it (``mentor.launch.py``,
``planner.launch.py``), run here with stand-ins for ``launch`` (no PyPI wheel), so that
their logic runs on a pip-only machine too."""

from __future__ import annotations

import importlib.util
import math
import sys
import types
from pathlib import Path
from typing import Any

import pytest

from mentor_core import FileFormatError, MentorError, get_profile
from mentor_core.benchmark.contenders import as_deployed, evolved
from mentor_core.runtime.robot_graph import (
    default_genome,
    headline_parameters,
    parse_genomes,
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


@pytest.mark.parametrize("robot, genome", [("ugv", UGV), ("swarm", SWARM)])
def test_headline_planners_run_as_the_benchmark_scores_them(robot: str, genome: str) -> None:
    """The node parameters of ``headline`` give the planner node the profile that
    ``mentor-bench --deployed`` scores: the same shim, guard and gain on the turn."""
    (planner,) = robot_planners([robot], {robot: genome}, headline=True)
    values = planner.parameters
    deployed = as_deployed(evolved(ROOT / genome, get_profile(robot))).profile
    assert values["scan_map"] is True
    assert values["collision_guard"] is deployed.collision_guard is True
    assert deployed.rotation_shim is not None
    assert math.radians(values["rotation_shim_deg"]) == pytest.approx(deployed.rotation_shim)
    assert values["turn_gain"] == deployed.turn_gain == (0.75 if robot == "swarm" else 1.0)
    assert values["view_margin"] == (deployed.view_margin or 0.0)
    assert values["view_margin"] == (0.1 if robot == "swarm" else 0.0)
    assert values["control_period"] == deployed.control_period == (
        0.5 if robot == "swarm" else 0.25)


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


def test_the_simulator_steps_at_the_genomes_period() -> None:
    both = robot_planners(["ugv", "swarm"], {"ugv": UGV, "swarm": SWARM})
    assert simulator_period(both[:1], continuous=False) == 0.5
    assert simulator_period(both[1:], continuous=False) == 1.0
    # continuous: each planner on its own timer, the simulator at the shortest period
    assert simulator_period(both, continuous=True) == 0.5
    with pytest.raises(MentorError, match=r"different periods \(0.5, 1 s\); run them with -c"):
        simulator_period(both, continuous=False, continuous_hint="-c")


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
                 "headline": "true"}  # fmt: skip
    with pytest.raises(MentorError, match="continuous:=true"):
        _launch(launch_file, **arguments)
    sim, ugv, swarm = _launch(launch_file, continuous="true", **arguments)
    (sim_values,) = sim["parameters"]
    assert sim_values["robots"] == ["ugv_0", "swarm_0"]
    assert sim_values["profiles"] == ["ugv", "swarm"]
    assert sim_values["control_period"] == 0.25  # the UGV's headline period, the shorter
    assert sim_values["real_time_factor"] == 1.0
    (values,) = swarm["parameters"]
    assert values["genome"] == SWARM and values["decide_on_timer"] is True
    assert values["scan_map"] is True and values["turn_gain"] == 0.75
    assert values["view_margin"] == 0.1
    assert ugv["namespace"] == "ugv_0" and ugv["parameters"][0]["turn_gain"] == 1.0
    assert ugv["parameters"][0]["view_margin"] == 0.0
    assert ugv["parameters"][0]["control_period"] == 0.25 and values["control_period"] == 0.5


LAYERS = ("control_period", "scan_map", "rotation_shim_deg", "collision_guard", "turn_gain",
          "view_margin")


def test_the_planner_launch_file_runs_a_headline_planner_as_the_benchmark_scores_it(
    planner_launch_file: types.ModuleType,
) -> None:
    """``headline:=true`` gives the layers of ``mentor-bench --deployed``; a layer given as
    well wins; without it the node keeps its own defaults."""
    (plain,) = _launch(planner_launch_file, genome=UGV)
    (values,) = plain["parameters"]
    assert not set(LAYERS) & set(values)
    (swarm,) = _launch(planner_launch_file, genome=SWARM, profile="swarm", headline="true")
    (values,) = swarm["parameters"]
    assert {k: values[k] for k in LAYERS} == headline_parameters("swarm", SWARM)
    assert values["turn_gain"] == 0.75 and values["view_margin"] == 0.1
    assert values["scan_map"] is True
    (ugv,) = _launch(planner_launch_file, genome=UGV, headline="true", turn_gain="0.9",
                     collision_guard="false", view_margin="0.3")
    (values,) = ugv["parameters"]
    assert values["turn_gain"] == 0.9 and values["collision_guard"] is False
    assert values["view_margin"] == 0.3
    assert values["rotation_shim_deg"] == 45.0 and values["scan_map"] is True
    with pytest.raises(MentorError, match="turn_gain:=fast: expected a number"):
        _launch(planner_launch_file, genome=UGV, turn_gain="fast")
    with pytest.raises(MentorError, match="collision_guard:=ture: expected true or false"):
        _launch(planner_launch_file, genome=UGV, collision_guard="ture")


def test_the_launch_files_refuse_a_mistyped_argument_in_one_line(
    launch_file: types.ModuleType,
) -> None:
    for name, text in (("continuous", "maybe"), ("rviz", "ture"), ("lidar_rays", "-3"),
                       ("real_time_factor", "fast"), ("headline", "yess")):  # fmt: skip
        with pytest.raises(MentorError, match=f"{name}:={text}: expected"):
            _launch(launch_file, **{name: text})
