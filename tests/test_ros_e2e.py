"""End to end: the simulator node and planner nodes exchange real messages, and the episodes
they produce equal mentor_core's in-process episodes for the same genome and scenarios.

The in-process reference is :func:`mentor_core.runtime.simulator.run_reference_episode`: the same
pymunk physics, the planner's :class:`GenomePlanner`, and the values a message carries (float32
scan ranges, the heading through a quaternion, the decision through a Twist). Agreement is
asserted within 1e-6 m; it is in fact exact.

(The trainer's batched engine, :func:`mentor_core.controller.episodes.run_episodes`, feeds its
networks float64 readings; the float32 of a LaserScan changes the inputs by ~1e-7 relative, which a
trained network may amplify over tens of decisions, so ROS episodes are compared with the
reference that mirrors the wire, not with the trainer's episodes. ``tests/test_simulator.py``
compares the reference with the trainer's episodes for untrained networks.)
"""

from __future__ import annotations

import itertools
import math
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest
from geometry_msgs.msg import PoseStamped, Twist
from nav_msgs.msg import Odometry
from rclpy.qos import qos_profile_sensor_data
from ros_support import REGRESSION, ROOT, Graph, params, workspace_env
from tf_support import tf_tree

from mentor_core.files.bags import read_episode_bag
from mentor_core.runtime.planner import GenomePlanner
from mentor_core.runtime.recording import recorded_episodes
from mentor_core.runtime.scenario_plan import ScenarioPlan, load_scenario_source
from mentor_core.runtime.simulator import RobotSetup, run_reference_episode
from mentor_core.runtime.wiring import Wiring
from mentor_core.sim.lidar import LidarSpec
from mentor_core.sim.observation import twist_from_action
from mentor_core.sim.robots import get_profile
from mentor_core.sim.scan_adapter import LidarMount
from mentor_core.sim.scenarios import training_scenarios
from mentor_core.sim.transforms import Transform2D
from mentor_core.sim.world import save_world
from mentor_planner_node.planner import PlannerNode, TFMessage
from mentor_sim_node.sim import SimNode

pytestmark = pytest.mark.ros

TOLERANCE = 1e-6  # m
EPISODES = 3



def _genome(robot: str) -> Path:
    return REGRESSION / f"{robot}_reference_genome.json"


def _planner(graph: Graph, ns: str, robot: str) -> PlannerNode:
    values = {"genome": str(_genome(robot)), "profile": robot, "use_sim_time": True}
    return graph.add(
        PlannerNode(
            context=graph.context, namespace=f"/{ns}", parameter_overrides=params(**values)
        )
    )


def _heading_error(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.abs(np.remainder(a - b + np.pi, 2 * np.pi) - np.pi).max())


@pytest.mark.parametrize("robot", ["ugv", "swarm"])
def test_episodes_through_ros_equal_the_in_process_episodes(
    graph: Graph, tmp_path: Path, robot: str
) -> None:
    profile = get_profile(robot)
    scenarios = training_scenarios(profile, 0, n=EPISODES)
    world = scenarios[0].world
    save_world(tmp_path / "world.yaml", world, scenarios)
    bag = tmp_path / "episodes"
    sim = graph.add(
        SimNode(
            context=graph.context,
            parameter_overrides=params(
                robots=["robot_0"], profiles=[robot], world=str(tmp_path / "world.yaml"),
                episodes=EPISODES, record=str(bag),
            ),
        )
    )
    planner = _planner(graph, "robot_0", robot)
    assert graph.spin_until(lambda: sim.finished)
    runs = recorded_episodes(read_episode_bag(bag), bag)
    assert [r.setup.scenario for r in runs] == list(range(EPISODES))
    reference = GenomePlanner.load(_genome(robot), robot)
    worst = 0.0
    for run in runs:
        trace = run_reference_episode(world, [run.setup], {"robot_0": reference.decide})
        ref = trace["robot_0"]
        assert run.outcome == ref.outcome
        assert len(run.odometry) == ref.steps + 1 and len(run.commands) == ref.steps
        poses = np.array([o.pose for o in run.odometry])
        worst = max(worst, float(np.abs(poses[:, :2] - ref.poses[:, :2]).max()))
        assert np.abs(poses[:, :2] - ref.poses[:, :2]).max() <= TOLERANCE
        assert _heading_error(poses[:, 2], ref.poses[:, 2]) <= 1e-9
        np.testing.assert_array_equal(np.array([s.ranges for s in run.scans]), ref.ranges)
        wz, vx = twist_from_action(ref.decisions[:, 0], ref.decisions[:, 1], 1.0)
        np.testing.assert_array_equal([c.linear_x for c in run.commands], vx)
        np.testing.assert_array_equal([c.angular_z for c in run.commands], wz)
    assert worst == 0.0  # not only within 1e-6 m: the very same numbers
    assert planner.decisions == sum(len(r.commands) for r in runs)
    assert planner.zero_commands == 0


def test_robots_of_both_kinds_share_a_world_through_ros(graph: Graph) -> None:
    """A UGV and a Swarm-Robot in one world, each with its own planner; the episode equals
    the in-process one with both robots in it (they see and may hit each other)."""
    robots = {"ugv_0": "ugv", "swarm_0": "swarm"}
    sim = graph.add(
        SimNode(
            context=graph.context,
            parameter_overrides=params(
                robots=list(robots), profiles=list(robots.values()), episodes=2
            ),
        )
    )
    planners = [_planner(graph, ns, robot) for ns, robot in robots.items()]
    assert graph.spin_until(lambda: sim.finished)
    # the simulator's default source: the UGV's training scenarios, the Swarm-Robot's own
    # missions in that world
    plan = ScenarioPlan(load_scenario_source(profile=get_profile("ugv"), seed=0),
                        [(ns, get_profile(robot)) for ns, robot in robots.items()])  # fmt: skip
    policies = {
        ns: GenomePlanner.load(_genome(robot), robot).decide for ns, robot in robots.items()
    }
    for episode in range(2):
        setups = plan.setups(episode)
        ref = run_reference_episode(plan.source.world, setups, policies)
        got = {o.robot: o for o in sim.outcomes if o.episode == episode}
        assert set(got) == set(robots)
        for ns, o in got.items():
            assert (o.event, o.scenario, o.steps) == (ref[ns].outcome, ref[ns].scenario,
                                                      ref[ns].steps)
            assert o.time_used == ref[ns].time_used
            assert np.abs(np.array(o.pose[:2]) - ref[ns].poses[-1, :2]).max() <= TOLERANCE
    assert all(p.decisions > 0 and p.zero_commands == 0 for p in planners)


# the shipped deployment: each planner decides at half its genome's period, run here in
# continuous mode as on a robot
@pytest.mark.parametrize(
    "mode",
    [[], ["--deployment", "shipped", "--continuous", "--real-time-factor", "10", "--time-limit",
          "8"]],
    ids=["plain", "shipped-deployment"],
)  # fmt: skip
def test_the_demo_command_runs_the_simulator_and_a_planner_per_robot(
    tmp_path: Path, mode: list[str]
) -> None:
    exe = ROOT / "ros2_ws/install/mentor_bringup/lib/mentor_bringup/demo"
    assert exe.is_file(), "run `bash scripts/bootstrap.sh` first"
    env = workspace_env()
    proc = subprocess.run(
        [str(exe), "--robots", "ugv", "swarm", "--episodes", "1", "--timeout", "30", *mode],
        cwd=ROOT, env=env, capture_output=True, timeout=60,
    )
    out = proc.stdout.decode()
    assert proc.returncode == 0, proc.stderr.decode()[-2000:]
    lines = out.strip().splitlines()
    assert len(lines) == 2 and all(line.startswith("episode 0: ") for line in lines)
    assert sorted(line.split()[2] for line in lines) == ["swarm_0", "ugv_0"]
    assert env["ROS_DOMAIN_ID"] == os.environ["ROS_DOMAIN_ID"]


def test_the_demo_refuses_a_deployment_it_cannot_run_in_one_line(tmp_path: Path) -> None:
    """Before any node starts: a missing file, a bad value (naming its key)."""
    exe = ROOT / "ros2_ws/install/mentor_bringup/lib/mentor_bringup/demo"
    bad = tmp_path / "bad.yaml"
    bad.write_text("stages:\n  turn_gain: {gain: 1.5}\n")
    for deployment, fault in ((tmp_path / "missing.yaml", "missing.yaml: no such file"),
                              (bad, "stages.turn_gain.gain: must be <= 1")):  # fmt: skip
        proc = subprocess.run(
            [str(exe), "--robots", "swarm", "--episodes", "1", "--deployment", str(deployment)],
            cwd=ROOT, env=workspace_env(), capture_output=True, timeout=60,
        )
        err = proc.stderr.decode().strip().splitlines()
        assert proc.returncode != 0 and len(err) == 1, err
        assert err[0].startswith("demo: ") and fault in err[0], err


def test_the_demo_runs_the_shipped_planners_of_both_robots_together_in_continuous_mode(
) -> None:
    """The shipped UGV planners decide every 0.5 s, the Swarm-Robot's every 1 s: lockstep
    refuses them together (one line naming the way out), the continuous mode runs them."""
    exe = ROOT / "ros2_ws/install/mentor_bringup/lib/mentor_bringup/demo"
    env = workspace_env()
    shipped = ["--genome", f"ugv={ROOT / 'planners/ugv-paper-dual-s1.json'}",
               "--genome", f"swarm={ROOT / 'planners/swarm-paper-dual-s1.json'}"]
    common = [str(exe), "--robots", "ugv", "swarm", "--episodes", "1", *shipped]
    refused = subprocess.run(common, cwd=ROOT, env=env, capture_output=True, timeout=60)
    err = refused.stderr.decode().strip().splitlines()
    assert refused.returncode != 0 and "different periods (0.5, 1 s)" in err[-1]
    assert "--continuous" in err[-1]
    proc = subprocess.run(
        [*common, "--continuous", "--real-time-factor", "10", "--time-limit", "8",
         "--timeout", "40"],
        cwd=ROOT, env=env, capture_output=True, timeout=60,
    )
    assert proc.returncode == 0, proc.stderr.decode()[-2000:]
    lines = proc.stdout.decode().strip().splitlines()
    assert sorted(line.split()[2] for line in lines) == ["swarm_0", "ugv_0"]
    assert all("physics steps" in line for line in lines)
    assert "no cmd_vel for the command timeout" not in proc.stderr.decode()


# -------------------------------------------------------------------- issue 16: any robot


LIDAR_MOUNT = Transform2D(0.05, 0.02, 0.3)  # off the body centre, turned
MAP_TO_ODOM = Transform2D(1.0, -0.5, 0.3)
USER_GOAL = (10.0, 7.5)


@pytest.mark.parametrize("frames", ["tf", "parameters"])
def test_a_lidar_robot_reaches_a_goal_from_a_plain_publisher_as_in_process(
    graph: Graph, tmp_path: Path, frames: str
) -> None:
    """The simulator publishes a 360-ray lidar scan from a frame off the body centre, with
    ``odom`` apart from ``map``; the planner reads that scan (not the per-sensor one); a plain
    (volatile) publisher gives the goal on /goal_pose; the robot reaches it, and the episode
    equals the in-process one (the planner's derivation of its readings from the same float32
    scan, pose and goal in ``odom``) within 1e-9 m, in fact bit for bit up to the rounding of
    turning the recorded odometry back into ``map``. The recording's TF tree, read with
    rosbags' reader, links map, odom, the robot and its sensor and lidar frames. With ``tf``
    the planner takes the lidar's mount and ``map -> odom`` from the simulator's live ``/tf``
    and ``/tf_static`` (its own TF buffer: ``tf2_ros`` has no wheel), with ``parameters`` from
    its parameters (issue 56, point 5)."""
    if frames == "tf" and TFMessage is None:
        pytest.skip("tf2_msgs was not generated (no C compiler at bootstrap: "
                    "interfaces/README.md)")
    ugv = get_profile("ugv")
    scenario = training_scenarios(ugv, 0, n=9)[8]
    world = scenario.world
    save_world(tmp_path / "world.yaml", world, [scenario])
    bag = tmp_path / "episodes"
    mount, offset = list(LIDAR_MOUNT.as_tuple()), list(MAP_TO_ODOM.as_tuple())
    sim = graph.add(SimNode(context=graph.context, parameter_overrides=params(
        robots=["robot_0"], profiles=["ugv"], world=str(tmp_path / "world.yaml"), episodes=1,
        wait_for_goals=True, lidar_rays=360, lidar_mount=mount, map_to_odom=offset,
        record=str(bag),
    )))
    planner = graph.add(PlannerNode(
        context=graph.context, namespace="/robot_0",
        parameter_overrides=params(genome=str(_genome("ugv")), profile="ugv", use_sim_time=True,
                                   **({"use_tf": True} if frames == "tf" else
                                      {"use_tf": False, "lidar_mount": mount,
                                       "map_to_odom": offset})),
        cli_args=["--ros-args", "-r", "scan:=lidar/scan"],
    ))
    user = graph.probe("rviz").create_publisher(PoseStamped, "/goal_pose", 10)
    assert graph.spin_until(lambda: user.get_subscription_count() >= 2)  # sim and planner
    assert graph.spin_until(lambda: sim.session.episode == 0)  # the robot waits at its start
    graph.spin_for(0.3)
    assert sim.sim_time_ns == 0 and not sim.outcomes
    goal = PoseStamped()
    goal.header.frame_id = "map"
    goal.pose.position.x, goal.pose.position.y = USER_GOAL
    user.publish(goal)
    assert graph.spin_until(lambda: sim.finished, timeout=40.0)
    (outcome,) = sim.outcomes
    assert outcome.event == "reached"
    # the episode in-process: what the planner derives from the same lidar scans, in odom
    reference = GenomePlanner.load(_genome("ugv"), "ugv")
    spec = LidarSpec(360, range_max=ugv.sensor_range, mount=LIDAR_MOUNT)
    wiring = Wiring(lidar=spec, planner_mount=LidarMount(LIDAR_MOUNT), map_to_odom=MAP_TO_ODOM)
    setup = RobotSetup("robot_0", ugv, scenario.start, USER_GOAL, 0)
    ref = run_reference_episode(world, [setup], {"robot_0": reference.decide},
                                wiring=wiring)["robot_0"]
    (run,) = recorded_episodes(read_episode_bag(bag), bag)
    assert run.setup.goal == USER_GOAL and run.setup.start == scenario.start
    assert (run.outcome, len(run.commands)) == (ref.outcome, ref.steps)
    assert (outcome.steps, outcome.time_used) == (ref.steps, ref.time_used)
    poses = np.array([o.pose for o in run.odometry])
    assert np.abs(poses[:, :2] - ref.poses[:, :2]).max() <= 1e-9
    assert _heading_error(poses[:, 2], ref.poses[:, 2]) <= 1e-9
    wz, vx = twist_from_action(ref.decisions[:, 0], ref.decisions[:, 1], 1.0)
    np.testing.assert_array_equal([c.linear_x for c in run.commands], vx)  # the very same
    np.testing.assert_array_equal([c.angular_z for c in run.commands], wz)
    assert planner.decisions == ref.steps and planner.zero_commands == 0
    assert planner.frames.uses_tf == (frames == "tf")
    # the per-sensor readings would have been others: the lidar path was the one taken
    plain = run_reference_episode(world, [setup], {"robot_0": reference.decide},
                                  wiring=Wiring(map_to_odom=MAP_TO_ODOM))["robot_0"]
    assert not np.array_equal(plain.ranges[0], ref.ranges[0])
    # one TF tree in the bag
    tree, stamps = tf_tree(bag)
    assert tree.lookup("map", "odom") == MAP_TO_ODOM
    start = tree.lookup("map", "robot_0/base_link").as_tuple()
    assert start == pytest.approx(scenario.start, abs=1e-12)
    lidar = tree.lookup("robot_0/sensor_0", "robot_0/lidar")
    sensor = ugv.sensors[0]
    want = Transform2D(sensor.x, sensor.y, sensor.angle).inverse().compose(LIDAR_MOUNT)
    assert lidar.as_tuple() == pytest.approx(want.as_tuple(), abs=1e-12)
    (robot,) = read_episode_bag(bag).robots
    assert stamps["robot_0/base_link"] == [o.stamp_ns for o in robot.odometry]  # each one


@pytest.mark.parametrize("repeat_rate", [10.0, 0.0])
def test_a_continuous_simulator_and_a_planner_on_its_own_timer(
    graph: Graph, repeat_rate: float
) -> None:
    """The simulator runs like Gazebo (physics every 0.05 s, scans at 10 Hz, each cmd_vel held
    until replaced or 0.5 s old); the planner decides once per control period (1 s) of sim
    time with the latest scan and odometry, and sends its cmd_vel again at ``repeat_rate``
    between decisions. Its decisions drive the robot to an end of the episode; with the
    repeats no command outlives the simulator's timeout, without them each one does."""
    robot = "swarm"
    sim = graph.add(SimNode(context=graph.context, parameter_overrides=params(
        robots=["robot_0"], profiles=[robot], episodes=1, continuous=True,
        real_time_factor=10.0, time_limit=8.0, command_timeout=0.5,
    )))
    planner = graph.add(PlannerNode(
        context=graph.context, namespace="/robot_0",
        parameter_overrides=params(genome=str(_genome(robot)), profile=robot,
                                   use_sim_time=True, decide_on_timer=True,
                                   repeat_rate=repeat_rate),
    ))
    heard: list[int] = []  # sim time (ns) of each cmd_vel the simulator gets
    odometry: list[tuple[float, float]] = []  # (x, y) of each odometry message, m
    probe = graph.probe()
    probe.create_subscription(Twist, "/robot_0/cmd_vel",
                              lambda _: heard.append(sim.sim_time_ns), 10)
    probe.create_subscription(
        Odometry, "/robot_0/odom",
        lambda m: odometry.append((m.pose.pose.position.x, m.pose.pose.position.y)),
        qos_profile_sensor_data)
    assert graph.spin_until(lambda: sim.finished, timeout=20.0)
    (outcome,) = sim.outcomes
    # It drove: the length of its odometry path, not where it ended, since a continuous
    # run's decisions hang on wall-clock timing and may bring it back near its start.
    assert sum(math.dist(a, b) for a, b in itertools.pairwise(odometry)) > 0.1
    assert 3 <= planner.decisions <= 9  # about one per second of sim time, not one per scan
    assert outcome.steps == round(outcome.time_used / 0.05)  # physics steps
    gaps = np.diff(heard) / 1e9  # s of sim time between commands
    if repeat_rate:
        assert planner.repeats >= 5 * planner.decisions
        assert gaps.max() <= 0.5  # never quiet for the command timeout
    else:
        assert planner.repeats == 0
        assert np.median(gaps) > 0.5  # one a decision: the robot stood for half of each


def test_the_two_robot_demo_sends_each_robot_on_missions_of_its_own_scale() -> None:
    """Failed before: the Swarm-Robot got the UGV's 12 m missions and timed out in every
    episode (issue 56, point 7). The README's two-robot command, three episodes."""
    exe = ROOT / "ros2_ws/install/mentor_bringup/lib/mentor_bringup/demo"
    proc = subprocess.run(
        [str(exe), "--robots", "ugv", "swarm", "--deployment", "shipped",
         "--genome", "ugv=planners/ugv-paper-dual-s1.json",
         "--genome", "swarm=planners/swarm-paper-dual-s1.json",
         "--continuous", "--real-time-factor", "10", "--episodes", "3", "--timeout", "100"],
        cwd=ROOT, env=workspace_env(), capture_output=True, timeout=150,
    )  # fmt: skip
    assert proc.returncode == 0, proc.stderr.decode()[-2000:]
    lines = proc.stdout.decode().strip().splitlines()
    assert len(lines) == 6, lines
    for robot in ("ugv_0", "swarm_0"):
        assert any(f" {robot} reached " in line for line in lines), lines
