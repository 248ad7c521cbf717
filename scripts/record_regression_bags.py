#!/usr/bin/env python3
"""Record the regression bags in bags/regression/ from the real ROS 2 nodes.

For each robot (ugv, swarm) and its committed reference genome
``bags/regression/<robot>_reference_genome.json``:

1. the robot's training world of scenario seed 0 (the world the quick reference genomes were
   trained in; the paper's DoE) and its first candidate start/goal pairs; the in-process
   reference episode (:func:`mentor_core.runtime.simulator.run_reference_episode`) of each
   candidate picks up to ``--episodes`` scenarios, one per outcome (reached, collided, timed out)
   first, shortest first, so that the bags stay small and cover every ending;
2. ``<robot>_scenarios/``: those scenarios as a scenario bag;
3. ``<robot>_episodes/``: the simulator node (reading that scenario bag) and one planner node
   (the genome) run the episodes in one process, as fast as the planner answers, and the
   simulator records everything it publishes and receives;
4. a check that the recorded outcomes are the in-process ones.

Rerun it after a deliberate change of the simulator, the planner or the bag format:

    .venv/bin/python scripts/record_regression_bags.py [--out bags/regression] [--episodes 3]

Discovery stays on this machine (``ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST``, a domain id of
its own) unless the environment says otherwise.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
for pkg in ("mentor_sim_node", "mentor_planner_node", "mentor_ros_common", "mentor_bringup"):
    sys.path.insert(0, str(ROOT / pkg))
os.environ.setdefault("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
os.environ.setdefault("ROS_DOMAIN_ID", "43")

from mentor_bringup.demo import run_graph  # noqa: E402
from mentor_core.files.bags import read_episode_bag, write_scenario_bag  # noqa: E402
from mentor_core.runtime.planner import GenomePlanner  # noqa: E402
from mentor_core.runtime.recording import recorded_episodes  # noqa: E402
from mentor_core.runtime.simulator import RobotSetup, run_reference_episode  # noqa: E402
from mentor_core.sim.robots import get_profile  # noqa: E402
from mentor_core.sim.scenarios import training_scenarios  # noqa: E402
from mentor_core.sim.world import Scenario  # noqa: E402

SCENARIO_SEED = 0
CANDIDATES = 20
MAX_CANDIDATES = 160
NAMESPACE = "robot_0"


def choose(
    robot: str, planner: GenomePlanner, n: int
) -> tuple[list[Scenario], list[str]]:
    """Up to ``n`` scenarios of the regression world: distinct outcomes first, then short.

    The first ``CANDIDATES`` start/goal pairs, and more (up to ``MAX_CANDIDATES``) only while
    some ending is still missing.
    """
    # the simulator node's robot (its time budgets), not the planner's view of it (a planner
    # with shorter steps has a lower rated speed, hence longer budgets)
    profile = get_profile(robot)
    runs: list[tuple[int, int, str]] = []
    count = CANDIDATES
    while True:
        candidates = training_scenarios(profile, SCENARIO_SEED, n=count)
        world = candidates[0].world
        for i in range(len(runs), count):
            sc = candidates[i]
            setup = RobotSetup(NAMESPACE, profile, sc.start, sc.goal, i)
            planner.reset()  # each episode starts blank (a planner with a memory)
            trace = run_reference_episode(world, [setup], {NAMESPACE: planner.decide})
            runs.append((trace[NAMESPACE].steps, i, trace[NAMESPACE].outcome))
        if len({kind for _, _, kind in runs}) == 3 or count >= MAX_CANDIDATES:
            break
        count = min(2 * count, MAX_CANDIDATES)
    runs.sort()
    picked: list[tuple[int, int, str]] = []
    for kind in ("reached", "collided", "timed_out"):
        picked += [r for r in runs if r[2] == kind][:1]
    picked += [r for r in runs if r not in picked][: max(0, n - len(picked))]
    picked = sorted(picked[:n], key=lambda r: r[1])
    return [candidates[i] for _, i, _ in picked], [kind for _, _, kind in picked]


def record(robot: str, out: Path, n: int) -> None:
    genome = out / f"{robot}_reference_genome.json"
    planner = GenomePlanner.load(genome, robot)
    scenarios, expected = choose(robot, planner, n)
    world = scenarios[0].world
    scenario_bag = out / f"{robot}_scenarios"
    episode_bag = out / f"{robot}_episodes"
    write_scenario_bag(
        scenario_bag, world, scenarios, robot,
        {"purpose": "regression", "scenario_seed": SCENARIO_SEED}, overwrite=True,
    )
    sim = {
        "robots": [NAMESPACE],
        "profiles": [robot],
        "scenario_bag": str(scenario_bag.relative_to(ROOT)),
        "episodes": len(scenarios),
        "record": str(episode_bag),
        "record_metadata": json.dumps(
            {"genome": str(genome.relative_to(ROOT)), "purpose": "regression"}
        ),
    }
    planners = [(f"/{NAMESPACE}", {"genome": str(genome.relative_to(ROOT)), "profile": robot})]
    outcomes = run_graph(sim, planners, timeout_s=120.0)
    got = [o.event for o in outcomes]
    if got != expected:
        sys.exit(f"{robot}: the nodes ended {got}, the in-process reference {expected}")
    runs = recorded_episodes(read_episode_bag(episode_bag), episode_bag)
    if [r.outcome for r in runs] != expected:
        sys.exit(f"{episode_bag}: recorded outcomes {[r.outcome for r in runs]} != {expected}")
    size = sum(f.stat().st_size for f in episode_bag.rglob("*") if f.is_file())
    size += sum(f.stat().st_size for f in scenario_bag.rglob("*") if f.is_file())
    print(f"{robot}: {len(runs)} episodes {got}, {size / 1024:.0f} KiB -> {episode_bag}")


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--out", type=Path, default=ROOT / "bags" / "regression")
    p.add_argument("--episodes", type=int, default=3, help="episodes per robot (default 3)")
    p.add_argument("--robots", nargs="+", default=["ugv", "swarm"])
    opts = p.parse_args()
    os.chdir(ROOT)
    for robot in opts.robots:
        get_profile(robot)
        record(robot, opts.out.resolve(), opts.episodes)


if __name__ == "__main__":
    main()
