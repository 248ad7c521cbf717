"""The gain on the turn (``turn_gain``; not in the paper): at deployment the network's turn
is scaled about its middle, the same in the batched episodes and on the command lines, and
the rotation shim in front of it still turns by its full limit. (The planner on the robot
decides with it as the engine does: ``tests/test_rotation_shim.py``.)"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from deployment_support import check_deployment_flag

from mentor_core.benchmark.contenders import as_deployed, evolved
from mentor_core.errors import ConfigError
from mentor_core.evolution.genome import genome_from_edges
from mentor_core.evolution.network import FeedForwardNetwork
from mentor_core.runtime.planner import GenomePlanner, deployed_turn_gain
from mentor_core.sim.episode import run_episodes
from mentor_core.sim.observation import actions_from_outputs
from mentor_core.sim.planner_settings import with_planner
from mentor_core.sim.robots import RobotProfile, get_profile
from mentor_core.sim.turn_gain import turn_gain
from mentor_core.sim.world import Scenario, World

REPO = Path(__file__).resolve().parents[1]
SWARM_PLANNER = REPO / "planners" / "swarm-paper-dual-s1.json"


def gained(gain: float, **settings: object) -> RobotProfile:
    return with_planner(get_profile("swarm"), heading_change_max=math.pi / 4, turn_gain=gain,
                        **settings)  # fmt: skip


def test_the_turn_is_scaled_and_the_step_and_memory_pass_unchanged() -> None:
    rng = np.random.default_rng(0)
    outputs = rng.uniform(-0.3, 1.3, (200, 3))  # outside [0, 1] too: clipped as actions are
    plain = gained(1.0, memory_units=1)
    half = gained(0.5, memory_units=1)
    out = turn_gain(outputs, half)
    np.testing.assert_array_equal(out[:, 1:], outputs[:, 1:])
    turn, step = actions_from_outputs(outputs, plain)
    turn_half, step_half = actions_from_outputs(out, half)
    np.testing.assert_allclose(turn_half, 0.5 * turn, atol=1e-12)
    np.testing.assert_array_equal(step_half, step)
    assert np.abs(turn_half).max() <= 0.5 * half.heading_change_max + 1e-12


def test_at_gain_one_the_outputs_are_the_networks() -> None:
    outputs = np.array([[0.0, 1.0], [0.3, 0.2], [1.0, 0.0]])
    assert turn_gain(outputs, gained(1.0)) is outputs  # training's case: not even a copy
    assert get_profile("ugv").turn_gain == 1.0  # the paper's: off


@pytest.mark.parametrize("bad", [0.0, -0.5, 1.5, math.nan, True, "0.5"])
def test_a_gain_outside_zero_to_one_is_refused_naming_the_key(bad: object) -> None:
    with pytest.raises(ConfigError, match="turn_gain"):
        with_planner(get_profile("swarm"), turn_gain=bad, source="g.json")


def test_the_shim_still_turns_by_its_full_limit_in_front_of_the_gain() -> None:
    """A robot facing away from its goal turns on the spot by the whole limit (the shim's
    turn is not the network's); then a network that always turns fully left turns by half."""
    profile = gained(0.5, step_max=0.08, step_min=0.01, rotation_shim=math.pi / 4)
    n_in = profile.n_inputs
    bias = n_in  # genome_from_edges: inputs, then the bias node, then the outputs
    genome = genome_from_edges(n_in, 2, [(bias, n_in + 1, 30.0)])  # o_1 = 1: full left
    away = Scenario(World(4.0, np.zeros((0, 4))), (1.0, 2.0, math.pi), (3.0, 2.0))
    batch = run_episodes([away], profile, FeedForwardNetwork.from_genome(genome).episode_policy(1),
                         max_steps=8)  # fmt: skip
    turns = batch.experience[0][:, profile.n_sensors]
    limit = profile.heading_change_max
    np.testing.assert_allclose(np.abs(turns[:4]), limit, atol=1e-12)  # the shim: pi in 4
    np.testing.assert_allclose(turns[4:], 0.5 * limit, atol=1e-12)  # the network, halved


def test_the_shipped_swarm_planners_are_deployed_with_their_gain() -> None:
    assert deployed_turn_gain("swarm") == 0.75 and deployed_turn_gain("ugv") == 1.0
    swarm, ugv = get_profile("swarm"), get_profile("ugv")
    assert as_deployed(evolved(SWARM_PLANNER, swarm)).profile.turn_gain == 0.75
    ugv_planner = REPO / "planners" / "ugv-paper-dual-s1.json"
    assert as_deployed(evolved(ugv_planner, ugv)).profile.turn_gain == 1.0
    loaded = GenomePlanner.load(SWARM_PLANNER, "swarm", turn_gain=0.75)
    assert loaded.profile.turn_gain == 0.75
    with pytest.raises(ConfigError, match="turn_gain"):
        GenomePlanner.load(SWARM_PLANNER, "swarm", turn_gain=2.0)


def test_the_command_lines_take_a_gain_and_one_beside_deployed(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    check_deployment_flag("--turn-gain", 0.75, "1.5", "turn_gain", "1", tmp_path, capsys)
