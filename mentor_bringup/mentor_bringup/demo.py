"""One command for a demo: the simulator and one planner per robot, in one process.

    ros2 run mentor_bringup demo                                    # ROS 2 Jazzy installed
    ros2_ws/install/mentor_bringup/lib/mentor_bringup/demo          # pip-only machine

No ``launch`` needed: the nodes share one process and one executor. It is single-threaded on
purpose: the nodes are light (a step is a few pymunk queries and a small network), Python's
GIL would serialise a thread pool anyway, and one thread never runs a callback of a node that
is being destroyed at shutdown. By default a UGV
(``ugv_0``) and a Swarm-Robot (``swarm_0``) share the UGV's training world (seed 0), each
planning with ``bags/regression/<profile>_reference_genome.json`` (paths relative to the
working directory: run it from the repository root, or give ``--genome``), for 2 episodes as
fast as the planners answer; ``--real-time-factor 1`` runs in real time (watch ``/clock``,
``/mentor/obstacles`` and the robots' topics in Foxglove or rviz). ``--deployment shipped``
runs the planners as the shipped planners run (``mentor-bench --deployment shipped``; a file:
a deployment of one's own). Discovery stays on this machine
(``ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST``, ``ROS_DOMAIN_ID=42``) unless the environment
says otherwise.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from collections.abc import Sequence
from typing import Any

DEFAULT_DOMAIN_ID = "42"


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="demo", description=__doc__.split("\n")[0])
    p.add_argument(
        "--robots", nargs="+", default=["ugv", "swarm"], metavar="PROFILE",
        help="one robot per entry, namespace <profile>_<i> (default: ugv swarm)",
    )
    p.add_argument(
        "--genome", action="append", default=[], metavar="PROFILE=FILE",
        help="genome of a profile (default bags/regression/<profile>_reference_genome.json)",
    )
    src = p.add_mutually_exclusive_group()
    src.add_argument("--world", default="", help="world file (YAML) with scenarios")
    src.add_argument("--scenario-bag", default="", help="scenario bag")
    p.add_argument("--seed", type=int, default=0, help="training world seed without a file")
    p.add_argument("--episodes", type=int, default=2, help="episodes to run (0: endless)")
    p.add_argument(
        "--real-time-factor", type=float, default=0.0,
        help="sim s per wall s (default 0: as fast as the planners answer)",
    )
    p.add_argument("--time-limit", type=float, default=0.0, help="episode limit, s (0: T_tot)")
    p.add_argument("--record", default="", help="episode bag to write (one profile only)")
    p.add_argument("--timeout", type=float, default=0.0, help="stop after this many wall s")
    p.add_argument(
        "--continuous", action="store_true",
        help="the simulator runs like Gazebo (at --real-time-factor, 0 meaning 1) and each "
             "planner decides on its own timer at its genome's period, so genomes of "
             "different periods run together",
    )
    p.add_argument(
        "--deployment", default="none", metavar="NAME|FILE",
        help="how every planner runs: 'none' (as trained), 'shipped' (as the shipped planners, "
             "mentor-bench --deployment shipped) or a deployment YAML file",
    )
    return p


def run_graph(
    sim_parameters: dict[str, Any],
    planners: Sequence[tuple[str, dict[str, Any]]],
    timeout_s: float = 0.0,
    args: list[str] | None = None,
) -> list[Any]:
    """Run the simulator and the planners in one process until the simulator has run its
    ``episodes`` (or ``timeout_s`` wall s, 0: no limit, or Ctrl-C).

    ``planners`` holds ``(namespace, parameters)`` per robot; every planner runs on sim
    time. Returns the simulator's :attr:`SimNode.outcomes` (:class:`mentor_core.Outcome`
    each). Raises the nodes' setup errors.
    """
    import rclpy
    from rclpy.executors import ExternalShutdownException, SingleThreadedExecutor
    from rclpy.parameter import Parameter

    from mentor_planner_node.planner import PlannerNode
    from mentor_sim_node.sim import SimNode

    def overrides(values: dict[str, Any]) -> list[Parameter]:
        return [Parameter(k, value=v) for k, v in values.items()]

    rclpy.init(args=args)
    nodes: list[Any] = []
    executor = SingleThreadedExecutor()
    try:
        sim = SimNode(parameter_overrides=overrides(sim_parameters))
        nodes.append(sim)
        for ns, values in planners:
            values = {"use_sim_time": True, **values}
            nodes.append(PlannerNode(namespace=ns, parameter_overrides=overrides(values)))
        for node in nodes:
            executor.add_node(node)
        deadline = time.monotonic() + timeout_s if timeout_s > 0.0 else None
        try:
            while rclpy.ok() and not sim.finished:
                if deadline is not None and time.monotonic() > deadline:
                    sim.get_logger().warning(f"stopping after {timeout_s} s (--timeout)")
                    break
                executor.spin_once(timeout_sec=0.1)
        except (KeyboardInterrupt, ExternalShutdownException):
            pass
        return list(sim.outcomes)
    finally:
        for node in reversed(nodes):
            executor.remove_node(node)
            node.destroy_node()
        executor.shutdown()
        rclpy.try_shutdown()


def main(argv: list[str] | None = None) -> None:
    """Parse the options, start the nodes, print one line per finished robot episode."""
    from rclpy.utilities import remove_ros_args

    all_args = sys.argv[1:] if argv is None else argv
    ros_args = remove_ros_args(["demo", *all_args])[1:]
    opts = _parser().parse_args(ros_args)
    os.environ.setdefault("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
    os.environ.setdefault("ROS_DOMAIN_ID", DEFAULT_DOMAIN_ID)
    from rclpy.exceptions import ParameterException

    from mentor_core import MentorError, parse_genomes, robot_planners, simulator_period

    try:
        planners = robot_planners(
            opts.robots, parse_genomes(opts.genome), deployment=opts.deployment,
            continuous=opts.continuous,
        )
        sim = {
            "robots": [p.namespace for p in planners],
            "profiles": [p.profile for p in planners],
            "world": opts.world,
            "scenario_bag": opts.scenario_bag,
            "seed": opts.seed,
            "episodes": opts.episodes,
            "real_time_factor": opts.real_time_factor,
            "time_limit": opts.time_limit,
            "record": opts.record,
            # continuous: each planner keeps its own period, the simulator holds its commands
            "control_period": simulator_period(planners, opts.continuous, "--continuous"),
            "continuous": opts.continuous,
        }
        graph = [(f"/{p.namespace}", p.parameters) for p in planners]
        outcomes = run_graph(sim, graph, opts.timeout, args=["demo", *all_args])
    except (MentorError, ValueError, ParameterException) as err:
        sys.exit(f"demo: {' '.join(str(err).split())}")
    for o in outcomes:
        print(
            f"episode {o.episode}: {o.robot} {o.event} in scenario {o.scenario} after "
            f"{o.steps} {'physics steps' if opts.continuous else 'decisions'} "
            f"({o.time_used:.2f} s)"
        )
