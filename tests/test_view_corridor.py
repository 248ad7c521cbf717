"""The view corridor (the stage ``view_corridor``; trained with: ``view_margin``; not in the
paper): the network reads as nothing seen whatever its sensors hit farther than the margin
from the segment to its goal. The geometry is checked by hand; the episodes, the planner on
the command line and the command-line tools all take it. (The planner node decides with it as
the planner does: ``tests/test_planner_node.py``.)"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from deployment_set_support import check_stage_setting

from mentor_core.benchmark.contenders import evolved
from mentor_core.controller.deployment import (
    Deployment,
    deploy,
    load_deployment,
    trained_stages,
)
from mentor_core.controller.pipeline import DecisionChain
from mentor_core.controller.view_corridor import ViewCorridor, corridor_ranges
from mentor_core.errors import ConfigError
from mentor_core.files.genome_file import load_genome_and_metadata
from mentor_core.runtime.planner import GenomePlanner, planner_profile
from mentor_core.sim.observation import network_inputs
from mentor_core.sim.robots import RobotProfile, get_profile
from mentor_core.sim.sensors import sensor_readings
from mentor_core.sim.world import World

REPO = Path(__file__).resolve().parents[1]
SWARM_PLANNER = REPO / "planners" / "swarm-paper-dual-s1.json"
# the Swarm-Robot's sensors: mounts (0.04, -0.025), (0.04, 0), (0.04, 0.025) facing -45, 0,
# 45 deg, single rays, 0.6 m
SWARM = get_profile("swarm")
MARGIN = 0.1
SIN45 = math.sin(math.pi / 4)


def corridor(profile: RobotProfile, ranges: list[float], pose: tuple[float, float, float],
             goal: tuple[float, float], margin: float = MARGIN) -> list[float]:  # fmt: skip
    out = corridor_ranges(np.array([ranges]), np.array([pose]), np.array([goal]), profile,
                          margin)  # fmt: skip
    return [float(v) for v in out[0]]


def test_a_reading_on_the_way_stays_and_one_beside_it_reads_as_nothing_seen() -> None:
    """Goal 1 m ahead: the front sensor's hit (0.34, 0) lies on the way; the left sensor's
    hit at 0.3 m, (0.252, 0.237), lies 0.237 m from it; the right sensor's at 0.05 m,
    (0.075, -0.060), 0.060 m."""
    assert corridor(SWARM, [0.05, 0.3, 0.3], (0.0, 0.0, 0.0), (1.0, 0.0)) == [0.05, 0.3, 0.6]


def test_the_margin_is_a_distance_from_the_segment() -> None:
    """The left sensor's hit lies ``0.025 + r sin 45`` beside the way: r = 0.10 puts it
    0.0957 m away (kept), r = 0.112 0.104 m away (nothing seen)."""
    assert corridor(SWARM, [0.6, 0.6, 0.10], (0.0, 0.0, 0.0), (1.0, 0.0))[2] == 0.10
    assert 0.025 + 0.112 * SIN45 > 0.1
    assert corridor(SWARM, [0.6, 0.6, 0.112], (0.0, 0.0, 0.0), (1.0, 0.0))[2] == 0.6


def test_what_lies_ahead_of_a_robot_facing_away_from_its_goal_is_not_in_its_way() -> None:
    """Goal 1 m behind: the front hit (0.34, 0) lies 0.34 m from the segment's end at the
    robot; a reading 0.05 m ahead, 0.09 m from it, stays."""
    assert corridor(SWARM, [0.6, 0.3, 0.6], (0.0, 0.0, 0.0), (-1.0, 0.0))[1] == 0.6
    assert corridor(SWARM, [0.6, 0.05, 0.6], (0.0, 0.0, 0.0), (-1.0, 0.0))[1] == 0.05


def test_the_corridor_is_taken_in_the_body_frame() -> None:
    """The first case turned by 90 deg and moved: the same readings stay."""
    turned = corridor(SWARM, [0.05, 0.3, 0.3], (5.0, 5.0, math.pi / 2), (5.0, 6.0))
    assert turned == [0.05, 0.3, 0.6]


def test_a_beam_stays_when_any_of_its_rays_hits_near_the_way() -> None:
    """The UGV's sensor 1 faces 22.5 deg with rays from 0 to 45 deg (mount (0.15, 0.038));
    its goal lies at 45 deg. Its middle ray's hit at 1 m, (1.074, 0.421), lies 0.46 m from
    the way, its edge ray's, (0.857, 0.745), 0.079 m: the reading may come from that ray, so
    it stays. With the goal at -45 deg every ray's hit lies beyond 0.1 m."""
    ugv = get_profile("ugv")
    assert ugv.beam_sensors == (0, 1)
    ranges = [4.0, 1.0, 4.0, 4.0, 4.0, 4.0, 4.0, 4.0]
    assert corridor(ugv, ranges, (0.0, 0.0, 0.0), (2.0, 2.0))[1] == 1.0
    assert corridor(ugv, ranges, (0.0, 0.0, 0.0), (2.0, -2.0))[1] == 4.0


def test_a_robot_on_its_goal_keeps_only_what_is_within_the_margin_of_it() -> None:
    assert corridor(SWARM, [0.05, 0.3, 0.6], (0.0, 0.0, 0.0), (0.0, 0.0)) == [0.05, 0.6, 0.6]


def test_an_infinite_margin_keeps_every_reading() -> None:
    ranges = np.array([[0.05, 0.3, 0.3]])
    assert corridor_ranges(ranges, np.zeros((1, 3)), np.ones((1, 2)), SWARM, math.inf) is ranges
    assert ViewCorridor(margin=math.inf).record() == {}  # listed as no corridor
    assert ViewCorridor(margin=MARGIN).record() == {"view_margin": MARGIN}
    # the paper's: off, unless trained with or deployed with
    assert load_deployment("none", "swarm")[0].build() == ()
    assert trained_stages({"robot": "swarm"}) == ()


def test_the_network_reads_the_corridor_and_the_same_goal() -> None:
    """Only the range inputs change; nothing seen (inf) reads as the sensor's range."""
    ranges = np.array([[np.inf, 0.3, 0.3]])
    pose, goal = np.array([[0.0, 0.0, 0.0]]), np.array([[1.0, 0.0]])
    read: list[np.ndarray] = []

    def policy(inputs: np.ndarray, robots: np.ndarray) -> np.ndarray:
        read.append(inputs.copy())
        return np.full((len(robots), 2), 0.5)

    chain = DecisionChain(SWARM, (ViewCorridor(margin=MARGIN),), 1)
    chain.decide(np.zeros(1, dtype=np.int64), ranges, pose, goal, policy)
    (seen,) = read
    assert seen.tolist() == network_inputs([[0.6, 0.3, 0.6]], pose, goal, SWARM).tolist()
    assert seen[0, 3:].tolist() == network_inputs(ranges, pose, goal, SWARM)[0, 3:].tolist()
    # the network's inputs of their own apply no corridor any more: the stage does
    assert network_inputs(ranges, pose, goal, SWARM)[0, 2] != seen[0, 2]


@pytest.mark.parametrize(
    "bad, text", [(0.0, "0"), (-0.1, "-0.1"), (-math.inf, "-.inf"), (math.nan, ".nan"),
                  (True, "true"), ("0.1", "'0.1'")],
)  # fmt: skip
def test_a_margin_that_is_not_positive_is_refused_naming_the_key(bad: object, text: str) -> None:
    with pytest.raises(ConfigError, match="margin"):
        ViewCorridor(margin=bad)  # type: ignore[arg-type]
    with pytest.raises(ConfigError, match=r"--set: stages\.view_corridor\.margin: "):
        load_deployment("none", "swarm", [f"stages.view_corridor.margin={text}"])


def test_a_deployment_keeps_replaces_or_removes_the_trained_corridor() -> None:
    _, metadata = load_genome_and_metadata(SWARM_PLANNER)
    trained = trained_stages(metadata, SWARM_PLANNER)
    assert trained == (ViewCorridor(margin=MARGIN),)
    profile = planner_profile(SWARM, metadata, SWARM_PLANNER)

    def corridors(stages: dict[str, object]) -> list[ViewCorridor]:
        deployed = deploy(profile, trained, Deployment(stages=stages), SWARM_PLANNER)  # type: ignore[arg-type]
        return [s for s in deployed.stages if isinstance(s, ViewCorridor)]

    assert corridors({}) == [ViewCorridor(margin=MARGIN)]  # kept
    assert corridors({"view_corridor": {"margin": 0.3}}) == [ViewCorridor(margin=0.3)]
    assert corridors({"view_corridor": {"margin": math.inf}}) == [ViewCorridor(margin=math.inf)]
    with pytest.raises(ConfigError, match=r"stages\.view_corridor\.margin"):
        corridors({"view_corridor": {"margin": -1.0}})


def test_the_shipped_swarm_planners_are_deployed_with_their_corridor() -> None:
    def margins(robot: str) -> list[float]:
        deployment, _ = load_deployment("shipped", robot)
        return [s.margin for s in deployment.build() if isinstance(s, ViewCorridor)]

    assert margins("swarm") == [MARGIN] and margins("ugv") == []
    swarm_shipped = load_deployment("shipped", "swarm")[0]
    deployed = evolved(SWARM_PLANNER, SWARM, deployment=swarm_shipped)
    corridors = [s for s in deployed.stages if isinstance(s, ViewCorridor)]
    assert corridors == [ViewCorridor(margin=MARGIN)]
    ugv_planner = REPO / "planners" / "ugv-paper-dual-s1.json"
    ugv_shipped = load_deployment("shipped", "ugv")[0]
    assert not any(isinstance(s, ViewCorridor) for s in
                   evolved(ugv_planner, get_profile("ugv"), deployment=ugv_shipped).stages)
    # a shipped Swarm-Robot planner was trained with the corridor: it keeps it as trained
    assert evolved(SWARM_PLANNER, SWARM).stages == (ViewCorridor(margin=MARGIN),)
    assert GenomePlanner.load(SWARM_PLANNER, "swarm").stages == (ViewCorridor(margin=MARGIN),)
    # an infinite margin removes it: the planner then decides on every reading, as one
    # without stages does
    unviewed = GenomePlanner.load(
        SWARM_PLANNER, "swarm", Deployment(stages={"view_corridor": {"margin": math.inf}}))
    viewed = GenomePlanner.load(SWARM_PLANNER, "swarm")
    bare = GenomePlanner(viewed.genome, viewed.profile)
    world = World(2.0, np.array([[1.2, 0.0, 1.3, 0.9], [0.6, 1.25, 1.6, 1.35]]))
    pose, goal = np.array([1.0, 1.0, 0.3]), (1.8, 0.2)
    readings = sensor_readings(pose[None], SWARM, world)[0]
    assert np.isfinite(readings).sum() >= 2
    assert unviewed.decide(readings, pose, goal) == bare.decide(readings, pose, goal)
    assert viewed.decide(readings, pose, goal) != bare.decide(readings, pose, goal)
    with pytest.raises(ConfigError, match=r"stages\.view_corridor\.margin"):
        GenomePlanner.load(SWARM_PLANNER, "swarm",
                           Deployment(stages={"view_corridor": {"margin": -1.0}}))


def test_the_command_lines_take_a_margin_and_an_infinite_one_on_top_of_shipped(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    check_stage_setting("stages.view_corridor.margin", 0.2, "0", "view_margin",
                        "stages.view_corridor.margin=.inf", tmp_path, capsys)  # fmt: skip
