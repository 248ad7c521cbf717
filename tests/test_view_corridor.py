"""The view corridor (``view_margin``; not in the paper): at deployment the network reads as
nothing seen whatever its sensors hit farther than the margin from the segment to its goal.
The geometry is checked by hand; the episodes, the planner on the command line and the
command-line tools all take it. (The planner node decides with it as the planner does:
``tests/test_planner_node.py``.)"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from deployment_support import check_deployment_flag

from mentor_core.benchmark.contenders import as_deployed, evolved
from mentor_core.errors import ConfigError
from mentor_core.runtime.planner import GenomePlanner, deployed_view_margin
from mentor_core.sim.observation import network_inputs
from mentor_core.sim.planner_settings import with_planner
from mentor_core.sim.robots import RobotProfile, get_profile
from mentor_core.sim.view_corridor import corridor_ranges, set_view_margin

REPO = Path(__file__).resolve().parents[1]
SWARM_PLANNER = REPO / "planners" / "swarm-paper-dual-s1.json"
# the Swarm-Robot's sensors: mounts (0.04, -0.025), (0.04, 0), (0.04, 0.025) facing -45, 0,
# 45 deg, single rays, 0.6 m
SWARM = with_planner(get_profile("swarm"), view_margin=0.1)
SIN45 = math.sin(math.pi / 4)


def corridor(profile: RobotProfile, ranges: list[float], pose: tuple[float, float, float],
             goal: tuple[float, float]) -> list[float]:  # fmt: skip
    out = corridor_ranges(np.array([ranges]), np.array([pose]), np.array([goal]), profile)
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
    ugv = with_planner(get_profile("ugv"), view_margin=0.1)
    assert get_profile("ugv").beam_sensors == (0, 1)
    ranges = [4.0, 1.0, 4.0, 4.0, 4.0, 4.0, 4.0, 4.0]
    assert corridor(ugv, ranges, (0.0, 0.0, 0.0), (2.0, 2.0))[1] == 1.0
    assert corridor(ugv, ranges, (0.0, 0.0, 0.0), (2.0, -2.0))[1] == 4.0


def test_a_robot_on_its_goal_keeps_only_what_is_within_the_margin_of_it() -> None:
    assert corridor(SWARM, [0.05, 0.3, 0.6], (0.0, 0.0, 0.0), (0.0, 0.0)) == [0.05, 0.6, 0.6]


def test_without_a_margin_the_readings_are_the_networks() -> None:
    ranges = np.array([[0.05, 0.3, 0.3]])
    plain = get_profile("swarm")
    assert plain.view_margin is None  # the paper's: off
    assert corridor_ranges(ranges, np.zeros((1, 3)), np.ones((1, 2)), plain) is ranges


def test_the_network_reads_the_corridor_and_the_same_goal() -> None:
    """Only the range inputs change; nothing seen (inf) reads as the sensor's range."""
    plain = get_profile("swarm")
    ranges = [[np.inf, 0.3, 0.3]]
    pose, goal = [[0.0, 0.0, 0.0]], [[1.0, 0.0]]
    seen = network_inputs(ranges, pose, goal, SWARM)
    assert seen.tolist() == network_inputs([[0.6, 0.3, 0.6]], pose, goal, plain).tolist()
    assert seen[0, 3:].tolist() == network_inputs(ranges, pose, goal, plain)[0, 3:].tolist()


@pytest.mark.parametrize("bad", [0.0, -0.1, math.inf, math.nan, True, "0.1"])
def test_a_margin_that_is_not_positive_is_refused_naming_the_key(bad: object) -> None:
    with pytest.raises(ConfigError, match="view_margin"):
        with_planner(get_profile("swarm"), view_margin=bad, source="g.json")


def test_set_view_margin_keeps_replaces_or_removes() -> None:
    trained = with_planner(get_profile("swarm"), view_margin=0.1)
    assert set_view_margin(trained, None) is trained
    assert set_view_margin(trained, 0.3).view_margin == 0.3
    assert set_view_margin(trained, math.inf).view_margin is None
    with pytest.raises(ConfigError, match="view_margin"):
        set_view_margin(trained, -1.0, "g.json")


def test_the_shipped_swarm_planners_are_deployed_with_their_corridor() -> None:
    assert deployed_view_margin("swarm") == 0.1 and deployed_view_margin("ugv") is None
    assert as_deployed(evolved(SWARM_PLANNER, get_profile("swarm"))).profile.view_margin == 0.1
    ugv_planner = REPO / "planners" / "ugv-paper-dual-s1.json"
    assert as_deployed(evolved(ugv_planner, get_profile("ugv"))).profile.view_margin is None
    # a shipped Swarm-Robot planner was trained with the corridor; inf (none) removes it
    shipped = evolved(SWARM_PLANNER, get_profile("swarm"))
    assert shipped.profile.view_margin == 0.1
    assert as_deployed(shipped, view_margin=math.inf).profile.view_margin is None
    unviewed = GenomePlanner.load(SWARM_PLANNER, "swarm", view_margin=math.inf)
    assert unviewed.profile.view_margin is None
    loaded = GenomePlanner.load(SWARM_PLANNER, "swarm", view_margin=0.1)
    assert loaded.profile.view_margin == 0.1
    with pytest.raises(ConfigError, match="view_margin"):
        GenomePlanner.load(SWARM_PLANNER, "swarm", view_margin=-1.0)


def test_the_command_lines_take_a_margin_and_none_beside_deployed(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    check_deployment_flag("--view-margin", 0.1, "0", "view_margin", "none", tmp_path, capsys)
