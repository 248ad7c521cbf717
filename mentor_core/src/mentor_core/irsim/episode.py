"""One start/goal pair of a world driven to its end in IR-SIM, as deployed.

Every control period of the driver (``spec.profile.control_period``) the robot's latest
lidar scan is read off as its profile's sensors
(:func:`mentor_core.sim.scan_adapter.readings_from_scan` of :func:`.adapter.scan_data`), the
driver decides (a driver on a scan map is handed the scan too, for a deployment whose map
takes its every ray, as the planner node hands it over), and its decision's Twist
(:func:`.adapter.velocity_command`) is held for the period's IR-SIM steps
(``world.step_time`` each). A scan the planner node would refuse
(:func:`mentor_core.sim.scan_adapter.readings_fault`) gives a zero Twist, as the node stops
the robot. IR-SIM moves every object and checks collisions itself (``collision_mode:
unobstructed_obstacles``: the robot stops at its first contact, the agents walk on).

The episode ends on the first of: the robot's centre within the robot's goal radius
(``robots.yaml``) of the goal (reached), a collision (with a static obstacle, or with a
moving agent: any object of IR-SIM's that is not ``static``), or the time limit (the
paper's 50 s). Scores as the benchmark's: SPL ``S l / max(p, l)``
(:func:`mentor_core.benchmark.scores.spl`), ``l`` the pair's shortest path on the static
map, ``p`` the path driven.
"""

from __future__ import annotations

import math
import tempfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import yaml
from numpy.typing import NDArray

from mentor_core.benchmark.scores import spl
from mentor_core.benchmark.suite import PAPER_LIMIT
from mentor_core.errors import ConfigError
from mentor_core.irsim.adapter import irsim_action, lidar_mount, scan_data, velocity_command
from mentor_core.irsim.dependency import load_irsim
from mentor_core.irsim.drivers import DriverSpec
from mentor_core.irsim.world_file import IrsimWorld, pair_config
from mentor_core.runtime.guided_planner import ScanGuidedPlanner
from mentor_core.sim.robots import get_profile
from mentor_core.sim.scan_adapter import MountedScan, readings_fault, readings_from_scan
from mentor_core.sim.world import Scenario, World

FloatArray = NDArray[np.float64]
OUTCOMES = ("reached", "collision_static", "collision_agent", "timeout")


@dataclass(frozen=True)
class EpisodeResult:
    """How one episode ended (module docstring): ``outcome`` one of :data:`OUTCOMES`, sim
    ``time`` (s), ``path_length`` (m), the pair's ``shortest`` (m), ``spl``, the driver's
    ``decisions``, the scans it ``refused`` and the ``agent_speed`` of an agent it touched;
    with ``record`` the robot's poses ``(t, 3)`` and the agents' positions ``(t, m, 2)``,
    one row per IR-SIM step from the start."""

    world: str
    pair: int
    driver: str
    seed: int
    outcome: str
    time: float
    path_length: float
    shortest: float
    spl: float
    decisions: int
    refused: int
    #: m/s: the speed of the fastest agent the robot touched (0: it stood; NaN: none)
    agent_speed: float = math.nan
    trajectory: FloatArray | None = field(default=None, repr=False)
    agents: FloatArray | None = field(default=None, repr=False)

    @property
    def reached(self) -> bool:
        """The goal was reached within the limit."""
        return self.outcome == "reached"


def steps_per_period(period: float, step_time: float) -> int:
    """IR-SIM steps in a control period; ConfigError when the step does not divide it."""
    steps = round(period / step_time)
    if steps < 1 or abs(steps * step_time - period) > 1e-9 * max(1.0, period):
        raise ConfigError(f"the world's step_time {step_time:g} s does not divide the "
                          f"driver's control period {period:g} s", key="world.step_time")
    return steps


def make_env(config: dict[str, Any], seed: int) -> Any:
    """An IR-SIM environment of ``config`` (IR-SIM's blocks), headless, its random draws
    (lidar noise, wandering goals) from ``seed``."""
    irsim = load_irsim()
    with tempfile.TemporaryDirectory(prefix="mentor-irsim-") as folder:
        path = Path(folder) / "world.yaml"
        path.write_text(yaml.safe_dump(config, sort_keys=False))
        return irsim.make(str(path), disable_all_plot=True, seed=seed, log_level="ERROR")


def run_episode(
    world: IrsimWorld, k: int, spec: DriverSpec, seed: int = 1,
    limit: float = PAPER_LIMIT, record: bool = False,
) -> EpisodeResult:  # fmt: skip
    """Pair ``k`` of ``world`` driven by a fresh driver of ``spec`` (module docstring),
    IR-SIM's draws from ``seed``; ``record`` keeps the poses. ConfigError for a driver of
    another robot or a step that does not divide its period."""
    if spec.profile.name != world.robot:
        raise ConfigError(f"{spec.name} drives robot {spec.profile.name!r}; the world "
                          f"{world.name} is for {world.robot!r}", path=world.path)  # fmt: skip
    steps = steps_per_period(spec.profile.control_period, world.step_time)
    pair = world.pairs[k]
    env = make_env(pair_config(world, k), seed)
    robot = env.robot
    mount = lidar_mount(robot.get_lidar_offset())
    driver = spec.driver(Scenario(World(world.size), pair.start, pair.goal))
    goal = np.asarray(pair.goal, dtype=np.float64)
    radius = get_profile(world.robot).goal_radius
    most = math.ceil(limit / world.step_time - 1e-9)
    poses = [_pose(robot)]
    agents = [_agents(env)] if record else []
    outcome, done, decisions, refused, length = "timeout", 0, 0, 0, 0.0
    hit_speed = math.nan
    while outcome == "timeout" and done < most:
        if math.dist(poses[-1][:2], goal) <= radius:
            outcome = "reached"
            break
        data = scan_data(robot.get_lidar_scan())
        read = readings_from_scan(data, mount, spec.profile)
        if readings_fault(read):
            command, refused = (0.0, 0.0), refused + 1
        else:
            if isinstance(driver, ScanGuidedPlanner):
                scan = MountedScan(data, mount)
                dtheta, ds = driver.decide(read.readings, poses[-1], goal, scan)
            else:
                dtheta, ds = driver.decide(read.readings, poses[-1], goal)
            command = velocity_command(dtheta, ds, spec.profile.control_period)
        decisions += 1
        for _ in range(min(steps, most - done)):
            env.step(irsim_action(command))
            done += 1
            pose = _pose(robot)
            length += math.dist(poses[-1][:2], pose[:2])
            poses.append(pose)
            if record:
                agents.append(_agents(env))
            if robot.collision_flag:
                moving = [o for o in robot.collision_obj if not getattr(o, "static", True)]
                outcome = "collision_agent" if moving else "collision_static"
                if moving:
                    hit_speed = max(_speed(o) for o in moving)
                break
            if math.dist(pose[:2], goal) <= radius:
                outcome = "reached"
                break
    ok = np.array([outcome == "reached"])
    score = float(spl(ok, np.array([pair.shortest]), np.array([length]))[0])
    return EpisodeResult(
        world.name, k, spec.name, seed, outcome, done * world.step_time, length,
        pair.shortest, score, decisions, refused, hit_speed,
        np.array(poses) if record else None,
        np.array(agents) if record else None,
    )  # fmt: skip


def _pose(robot: Any) -> tuple[float, float, float]:
    s = np.asarray(robot.state, dtype=np.float64).reshape(-1)
    return float(s[0]), float(s[1]), float(s[2])


def _speed(obj: Any) -> float:
    v = np.asarray(obj.velocity, dtype=np.float64).reshape(-1)[:2]
    return float(np.hypot(v[0], v[1]))


def _agents(env: Any) -> FloatArray:
    moving = [o for o in env.obstacle_list if not getattr(o, "static", True)]
    if not moving:
        return np.zeros((0, 2))
    return np.array([np.asarray(o.state, dtype=np.float64).reshape(-1)[:2] for o in moving])


__all__ = ["OUTCOMES", "EpisodeResult", "make_env", "run_episode", "steps_per_period"]
