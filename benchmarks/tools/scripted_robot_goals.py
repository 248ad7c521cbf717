"""A TurtleBot3 played by a script, driven to goals by the planner node at a preset's defaults.

    python benchmarks/tools/scripted_robot_goals.py --robot turtlebot3_burger \
        --genome planners/ugv-paper-dual-s1.json --family forest_medium --goals 10 --seed 1

The robot (:class:`mentor_core.StreamedRobot`, ROS side
:class:`mentor_bringup.scripted_robot.ScriptedRobot`) is not this project's simulator: a
kinematic differential drive at the preset robot's limits (:data:`SPECS`: the Burger's 0.22 m/s
or the Waffle's 0.26 m/s), a 360-ray lidar with 1 cm noise at 5 Hz behind its centre, odometry
and TF at 30 Hz, in one process with the planner node
(:class:`mentor_planner_node.planner.PlannerNode` with the preset's parameter file and nothing
else but the genome and sim time), ``--speedup`` times faster than real time. Each goal is a
start/goal pair 4-5 m apart, solvable for the robot's body, in one world of a benchmark
family (10 m side) drawn from ``--seed``; the robot is placed at the start and sent the goal
on ``/goal_pose``, as RViz's tool does, the planner keeping its scan map from goal to goal.
Prints one line per goal (how it ended, sim s, m driven, m left, collisions) and the total.
Issue 56; experiment E091; ``docs/ros.md``, "Your own robot". ``--param KEY=VALUE`` changes a
parameter of the preset (a YAML value: ``--param scan_map_size=100``); ``--timing`` also prints
the node's time from each answered scan's arrival to its Twist's publication and the time of
its plans on the scan map (p50, p95, p99, max; issue 57). Run it with
``ros2_ws/interfaces/install/local_setup.bash`` sourced for TF (else frames come from the
preset's parameters).
"""

from __future__ import annotations

import argparse
import os
import sys
from collections.abc import Sequence
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
for _pkg in ("mentor_sim_node", "mentor_planner_node", "mentor_ros_common", "mentor_bringup"):
    sys.path.insert(0, str(ROOT / _pkg))  # the node packages, from the source tree

# ruff: noqa: E402 (the imports below need the node packages on sys.path)
import numpy as np
import rclpy
import yaml
from rclpy.context import Context
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node

from mentor_bringup.scripted_robot import GoalRig, GoalRun, drive_goals, run_for, spinner
from mentor_core.navigation.pairs import world_with_pairs
from mentor_core.runtime.footprint import footprint_box, with_footprint
from mentor_core.runtime.streamed_robot import StreamedRobot, StreamSpec
from mentor_core.runtime.velocity_limits import VelocityLimits
from mentor_core.sim.families import FAMILIES
from mentor_core.sim.lidar import LidarSpec
from mentor_core.sim.robots import get_profile
from mentor_core.sim.transforms import Transform2D
from mentor_core.sim.world import World
from mentor_planner_node.presets import SOURCE_CONFIG, preset_values

#: the robot each preset is for: its body, limits and lidar mount (ROBOTIS' specifications)
SPECS = {
    "turtlebot3_burger": StreamSpec(),
    "turtlebot3_waffle": StreamSpec(
        lidar=LidarSpec(360, mount=Transform2D(-0.064, 0.0, 0.0), range_min=0.12,
                        range_max=3.5, noise=0.01),
        limits=VelocityLimits(max_vel_x=0.26, max_vel_theta=1.82, acc_lim_x=2.5,
                              acc_lim_theta=3.2),
        # the box about base_footprint holding Nav2's Waffle footprint, as the preset keeps
        body=footprint_box(preset_values(SOURCE_CONFIG / "turtlebot3_waffle.yaml")
                           ["footprint"]) or (0.41, 0.31)),
}


def goal_pairs(family: str, count: int, seed: int,
               body: tuple[float, float]) -> tuple[World, list[tuple[tuple, tuple]]]:  # fmt: skip
    """A world of ``family`` (10 m) and ``count`` (start, goal) pairs in it 4-5 m apart,
    solvable for a ``body`` (length, width) box, drawn from ``seed``."""
    robot = with_footprint(get_profile("ugv"), body)
    world, pairs = world_with_pairs(FAMILIES[family][1], 10.0, family, robot, count,
                                    (4.0, 5.0), 15.0, np.random.default_rng(seed))
    return world, [(s.start, s.goal) for s, _ in pairs]


def run(robot: str, genome: str, world: World, pairs: list[tuple[tuple, tuple]],
        speedup: float, limit: float, extra: dict[str, object] | None = None,
        ) -> tuple[list[GoalRun], dict[str, list[float]]]:  # fmt: skip
    """Drive to each pair's goal from its start, in one world, one planner node with the
    preset's parameters and ``extra`` (its scan map kept from goal to goal, as the preset
    keeps it); the :class:`GoalRun` of each and the node's timings (s: ``latency`` from each
    answered scan's arrival, ``answer`` from the answer's start, both to its Twist; ``plan``
    of each plan on the scan map)."""
    values = {**preset_values(SOURCE_CONFIG / f"{robot}.yaml"), "genome": genome,
              "use_sim_time": True, **(extra or {})}
    timings: dict[str, list[float]] = {"latency": [], "answer": [], "plan": []}
    context = Context()
    rclpy.init(context=context)
    executor = SingleThreadedExecutor(context=context)
    runs: list[GoalRun] = []

    def add(node: Node) -> Node:
        executor.add_node(node)
        return node

    try:
        sim = StreamedRobot(world, get_profile("ugv"), pairs[0][0], SPECS[robot], seed=1)
        rig = GoalRig(context, values, sim, add)
        spin = spinner(executor)
        for start, goal in pairs:
            sim.place(start)
            # a second still at the start: the planner's latest scan and odometry are from there
            run_for(spin, rig.robot, 1.0, speedup)
            runs += drive_goals(spin, rig.robot, rig.goal_pub, rig.statuses, [goal], speedup,
                                limit)  # fmt: skip
        timings["latency"] = list(rig.planner.latencies)
        timings["answer"] = list(rig.planner.answer_seconds)
        plan = rig.planner.global_plan
        if plan is not None and plan.planner is not None and hasattr(plan.planner, "scan"):
            timings["plan"] = list(plan.planner.scan.plan_seconds)
    finally:
        executor.shutdown()
        for node in list(executor.get_nodes()):
            node.destroy_node()
        rclpy.try_shutdown(context=context)
    return runs, timings


def quantiles_ms(values: list[float]) -> str:
    """``p50 / p95 / p99 / max`` of ``values`` (s) in ms, and how many."""
    if not values:
        return "none"
    q = np.percentile(np.asarray(values) * 1e3, [50, 95, 99, 100])
    return f"{q[0]:.1f} / {q[1]:.1f} / {q[2]:.1f} / {q[3]:.1f} ms of {len(values)}"


def main(argv: Sequence[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--robot", default="turtlebot3_burger", choices=sorted(SPECS))
    p.add_argument("--genome", default="planners/ugv-paper-dual-s1.json")
    p.add_argument("--family", default="forest_medium")
    p.add_argument("--goals", type=int, default=10)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--speedup", type=float, default=4.0, help="sim s per wall s")
    p.add_argument("--limit", type=float, default=120.0, help="sim s a goal may take")
    p.add_argument("--param", action="append", default=[], metavar="KEY=VALUE",
                   help="change a parameter of the preset (a YAML value)")
    p.add_argument("--timing", action="store_true", help="print the node's timings too")
    args = p.parse_args(argv)
    extra = {}
    for item in args.param:
        key, sep, value = item.partition("=")
        if not sep:
            p.error(f"--param {item}: expected KEY=VALUE")
        extra[key] = yaml.safe_load(value)
    os.environ.setdefault("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
    os.environ.setdefault("ROS_DOMAIN_ID", "43")
    world, pairs = goal_pairs(args.family, args.goals, args.seed, SPECS[args.robot].body)
    runs, timings = run(args.robot, args.genome, world, pairs, args.speedup, args.limit, extra)
    for k, r in enumerate(runs):
        print(f"goal {k + 1}: {r.status or 'no end'}; {r.seconds:.1f} s, {r.driven:.2f} m "
              f"driven, {r.left:.2f} m left, {r.collisions} collisions", flush=True)
    reached = sum(r.status == "reached" for r in runs)
    collided = sum(r.collisions > 0 for r in runs)
    print(f"{args.robot}, {args.family}, seed {args.seed}: {reached} of {len(runs)} goals "
          f"reached, {collided} with a collision")
    if args.timing:
        print(f"scan to Twist (p50 / p95 / p99 / max): {quantiles_ms(timings['latency'])}")
        print(f"answer to Twist (tick or scan): {quantiles_ms(timings['answer'])}")
        print(f"plans on the scan map: {quantiles_ms(timings['plan'])}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
