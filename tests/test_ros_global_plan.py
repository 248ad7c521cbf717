"""Global plans through ROS: the simulator on a ROS map with a dead end publishes /map, the
planner node plans on it, steers round the dead end and reaches the goal, publishing the path
it follows; the episode equals the in-process one (the same guide on the grid the wire
carries) exactly. A path given on ``plan`` is followed instead of planning. With a deployment
that has a ``scan_map`` (``deployment: shipped``, or a file) the node plans on a map of its own
scans, behind the rotation shim and the collision guard (and a view corridor to its carrot),
as ``mentor-bench --deployment`` runs the shipped planners, and the episode equals the
in-process one."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from nav_msgs.msg import OccupancyGrid as OccupancyGridMsg
from nav_msgs.msg import Path as PathMsg
from ros_support import REGRESSION, Graph, params

from mentor_core.controller.collision_guard import CollisionGuardStage
from mentor_core.controller.decision_split import at_control_period
from mentor_core.controller.rotation_shim import RotationShim
from mentor_core.controller.stage import Stage
from mentor_core.controller.view_corridor import ViewCorridor
from mentor_core.files.bags import read_episode_bag
from mentor_core.files.genome_file import load_genome_and_metadata
from mentor_core.navigation.grid import world_grid
from mentor_core.navigation.guide import guide_config
from mentor_core.navigation.map_file import save_map
from mentor_core.navigation.scan_map import scan_guide_config
from mentor_core.runtime.guided_planner import GuidedPlanner, ScanGuidedPlanner, wire_grid
from mentor_core.runtime.planner import GenomePlanner, genome_profile
from mentor_core.runtime.recording import recorded_episodes
from mentor_core.runtime.scenario_plan import load_scenario_source, source_map
from mentor_core.runtime.simulator import run_reference_episode
from mentor_core.sim.world import World
from mentor_planner_node.conversions import path_msg
from mentor_planner_node.global_plan import MAP_EVERY_S, QOS_MAP, QOS_PATH_OUT, PlanSetupError
from mentor_planner_node.planner import PlannerNode
from mentor_sim_node.sim import SimNode

pytestmark = pytest.mark.ros

GENOME = REGRESSION / "ugv_reference_genome.json"
# a U open towards the start, its back wall between start and goal: a dead end
DEAD_END = World(
    12.0, np.array([[7.0, 3.5, 7.3, 8.5], [4.5, 3.5, 7.3, 3.8], [4.5, 8.2, 7.3, 8.5]])
)
WORLD_FILE = (
    "format: mentor-world\nversion: 1\nmap: dead_end.yaml\n"
    "scenarios: [{start: [2.0, 6.0, 0.0], goal: [10.0, 6.0]}]\n"
)


def _planner(graph: Graph, **extra: object) -> PlannerNode:
    values = {"genome": str(GENOME), "profile": "ugv", "use_sim_time": True, **extra}
    overrides = params(**values)
    return graph.add(
        PlannerNode(context=graph.context, namespace="/robot_0", parameter_overrides=overrides)
    )


def _run_one_episode(graph: Graph, world: Path, bag: Path, period: float = 0.0) -> SimNode:
    """The simulator running the world file's one UGV episode to its end, recorded in ``bag``,
    stepping every ``period`` s (0: the profile's)."""
    sim = graph.add(
        SimNode(
            context=graph.context,
            parameter_overrides=params(
                robots=["robot_0"], profiles=["ugv"], world=str(world),
                episodes=1, record=str(bag), time_limit=50.0, control_period=period,
            ),
        )
    )
    assert graph.spin_until(lambda: sim.finished)
    return sim


def test_the_planner_plans_on_the_simulators_map_and_leaves_the_dead_end(
    graph: Graph, tmp_path: Path
) -> None:
    save_map(tmp_path / "dead_end.yaml", world_grid(DEAD_END, 0.05))
    (tmp_path / "world.yaml").write_text(WORLD_FILE)
    bag = tmp_path / "episodes"
    probe = graph.probe()
    maps: list[OccupancyGridMsg] = []
    paths: list[PathMsg] = []
    probe.create_subscription(OccupancyGridMsg, "/map", maps.append, QOS_MAP)
    probe.create_subscription(PathMsg, "/robot_0/global_plan", paths.append, QOS_PATH_OUT)
    planner = _planner(graph, global_plan=True)
    sim = _run_one_episode(graph, tmp_path / "world.yaml", bag)
    graph.spin_until(lambda: bool(maps) and bool(paths), timeout=2.0)
    assert [o.event for o in sim.outcomes] == ["reached"]
    assert planner.zero_commands == 0
    # /map: the simulated world on the map's cells, latched
    assert len(maps) == 1 and maps[0].header.frame_id == "map"
    assert (maps[0].info.width, maps[0].info.height) == (240, 240)
    # the path it followed, round the U
    assert paths and paths[0].header.frame_id == "map"
    ys = [p.pose.position.y for p in paths[0].poses]
    assert min(ys) < 3.5 or max(ys) > 8.5

    # the same episode in process: the guide on the grid the wire carries
    source = load_scenario_source(world_file=tmp_path / "world.yaml")
    plain = GenomePlanner.load(GENOME, "ugv")
    guided = GuidedPlanner(plain, guide_config(plain.profile))
    guided.set_map(wire_grid(source_map(source, 0.05)))
    run = recorded_episodes(read_episode_bag(bag), bag)[0]
    ref = run_reference_episode(source.world, [run.setup], {"robot_0": guided.decide})["robot_0"]
    assert run.outcome == ref.outcome == "reached"
    poses = np.array([o.pose for o in run.odometry])
    assert len(poses) == ref.steps + 1
    np.testing.assert_array_equal(poses[:, :2], ref.poses[:, :2])


#: a deployment file: the UGV's shipped one at its trained period, with a view corridor
CORRIDOR_DEPLOYMENT = """\
scan_map: {}
stages:
  view_corridor: {margin: 0.5}
  rotation_shim: {threshold_deg: 45}
  collision_guard: {memory: 3}
"""


# the reference genome decides every 1 s; the shipped UGV deployment decides twice in that
# period, each decision half its step and turn
@pytest.mark.parametrize(
    "deployment, settings, margin, period",
    [("shipped", ["decisions_per_period=1"], None, None),
     ("corridor.yaml", [], 0.5, None),
     ("shipped", [], None, 0.5)],
    ids=["all-seen", "view-corridor", "half-period"],
)  # fmt: skip
def test_on_a_scan_map_behind_the_shim_and_the_guard_the_node_runs_as_the_benchmark(
    graph: Graph, tmp_path: Path, deployment: str, settings: list[str], margin: float | None,
    period: float | None,
) -> None:  # fmt: skip
    (tmp_path / "world.yaml").write_text(
        "format: mentor-world\nversion: 1\nsize: 12.0\n"
        f"obstacles: {DEAD_END.obstacles.tolist()}\n"
        "scenarios: [{start: [2.0, 6.0, 0.0], goal: [10.0, 6.0]}]\n"
    )
    bag = tmp_path / "episodes"
    probe = graph.probe()
    paths: list[PathMsg] = []
    maps: list[OccupancyGridMsg] = []
    probe.create_subscription(PathMsg, "/robot_0/global_plan", paths.append, QOS_PATH_OUT)
    probe.create_subscription(OccupancyGridMsg, "/robot_0/scan_map", maps.append, QOS_MAP)
    if deployment.endswith(".yaml"):
        (tmp_path / deployment).write_text(CORRIDOR_DEPLOYMENT)
        deployment = str(tmp_path / deployment)
    extra = {"deployment_set": settings} if settings else {}
    planner = _planner(graph, deployment=deployment, **extra)
    assert planner.global_plan is not None and not planner.global_plan.ready  # no arena yet
    sim = _run_one_episode(graph, tmp_path / "world.yaml", bag, period or 0.0)
    graph.spin_until(lambda: bool(paths) and bool(maps), timeout=2.0)
    assert planner.zero_commands == 0 and len(sim.outcomes) == 1
    assert paths and paths[-1].header.frame_id == "odom"  # the plans it followed, for RViz
    # and the map it planned on, in the odometry frame: 1 s apart and with each new plan
    assert 1 <= len(maps) <= len(paths) + sim.outcomes[0].time_used / MAP_EVERY_S + 1
    assert all(m.header.frame_id == "odom" for m in maps)

    # the same episode in process, built without a deployment: the genome behind the shim
    # and a guard on no arena, on the map of what it read, as mentor-bench --deployment
    # shipped runs it (with a view corridor: it runs to the carrot the node steers to)
    source = load_scenario_source(world_file=tmp_path / "world.yaml")
    genome, _ = load_genome_and_metadata(GENOME)
    profile = genome_profile(GENOME, "ugv")
    if period is not None:
        profile = at_control_period(profile, period)
    stages: tuple[Stage, ...] = (RotationShim(threshold_deg=45.0), CollisionGuardStage(memory=3))
    if margin is not None:
        stages = (ViewCorridor(margin=margin), *stages)
    assert planner.planner is not None and planner.planner.stages == stages
    plain = GenomePlanner(genome, profile, str(GENOME), stages=stages)
    mapped = ScanGuidedPlanner(plain, scan_guide_config(plain.profile), 12.0)
    run = recorded_episodes(read_episode_bag(bag), bag)[0]
    seen: list[np.ndarray] = []  # the map after each decision

    def decide(ranges: object, pose: object, goal: object) -> tuple[float, float]:
        decision = mapped.decide(ranges, pose, goal)
        seen.append(mapped.scan.map.data)
        return decision

    assert run.setup.profile.control_period == plain.profile.control_period
    ref = run_reference_episode(source.world, [run.setup], {"robot_0": decide})["robot_0"]
    assert run.outcome == ref.outcome
    poses = np.array([o.pose for o in run.odometry])
    assert len(poses) == ref.steps + 1
    np.testing.assert_array_equal(poses[:, :2], ref.poses[:, :2])
    assert mapped.scan.plans > 1  # it planned again round what it read
    # each map published is the map of what it had read at one of its decisions, in order
    at = 0
    for msg in maps:
        sent = np.asarray(msg.data, dtype=np.int8).reshape(msg.info.height, msg.info.width)
        at = next(k for k in range(at, len(seen)) if np.array_equal(sent, seen[k]))
    assert (sent == 100).any() and (sent == -1).any()


def test_a_global_plan_and_a_scan_map_at_once_are_refused(graph: Graph) -> None:
    with pytest.raises(PlanSetupError, match="choose one") as err:
        _planner(graph, global_plan=True, deployment="shipped")  # the UGV's has a scan map
    assert "\n" not in str(err.value)
    # the way out the refusal names: the shipped deployment without its scan map
    planner = _planner(graph, global_plan=True, deployment="shipped",
                       deployment_set=["scan_map=null"])  # fmt: skip
    assert planner.global_plan is not None and not planner.global_plan.scan_map


def test_a_given_path_is_followed_and_published(graph: Graph) -> None:
    probe = graph.probe()
    paths: list[PathMsg] = []
    probe.create_subscription(PathMsg, "/robot_0/global_plan", paths.append, QOS_PATH_OUT)
    planner = _planner(graph, global_plan=True, map_topic="/no_map_here")
    assert planner.global_plan is not None and not planner.global_plan.ready
    give = probe.create_publisher(PathMsg, "/robot_0/plan", 1)
    points = np.array([(1.0, 1.0), (5.0, 1.0), (5.0, 5.0)])
    given = path_msg(points, probe.get_clock().now().to_msg())
    assert graph.spin_until(lambda: give.get_subscription_count() > 0)
    give.publish(given)
    assert graph.spin_until(lambda: planner.global_plan.ready)  # type: ignore[union-attr]
    guide = planner.global_plan.planner.guide  # type: ignore[union-attr]
    np.testing.assert_array_equal(guide.path, points)
    # the network is steered along it: the carrot 2 m on from (2, 1.2) is (4, 1)
    guide.target((2.0, 1.2), (5.0, 5.0))
    assert guide.carrot == pytest.approx((4.0, 1.0))
