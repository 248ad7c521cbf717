"""The gain on the turn (the stage ``turn_gain``; not in the paper): at deployment the network's
turn is scaled about its middle, the same in the batched episodes and on the command lines,
and the rotation shim behind it still turns by its full limit. (The planner on the robot
decides with it as the engine does: ``tests/test_rotation_shim.py``.)"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from deployment_set_support import check_stage_setting

from mentor_core.benchmark.contenders import evolved
from mentor_core.controller.deployment import Deployment, load_deployment
from mentor_core.controller.episodes import run_episodes
from mentor_core.controller.rotation_shim import RotationShim
from mentor_core.controller.turn_gain import TurnGain, turn_gain
from mentor_core.errors import ConfigError
from mentor_core.evolution.genome import genome_from_edges
from mentor_core.evolution.network import FeedForwardNetwork
from mentor_core.runtime.planner import GenomePlanner
from mentor_core.sim.observation import actions_from_outputs
from mentor_core.sim.planner_settings import with_planner
from mentor_core.sim.robots import RobotProfile, get_profile
from mentor_core.sim.world import Scenario, World

REPO = Path(__file__).resolve().parents[1]
SWARM_PLANNER = REPO / "planners" / "swarm-paper-dual-s1.json"


def planner(**settings: object) -> RobotProfile:
    """The planner's profile the gain is tested with (the gain itself is a stage)."""
    return with_planner(get_profile("swarm"), heading_change_max=math.pi / 4,
                        **settings)  # fmt: skip


def test_the_turn_is_scaled_and_the_step_and_memory_pass_unchanged() -> None:
    rng = np.random.default_rng(0)
    outputs = rng.uniform(-0.3, 1.3, (200, 3))  # outside [0, 1] too: clipped as actions are
    profile = planner(memory_units=1)
    out = turn_gain(outputs, 0.5)
    np.testing.assert_array_equal(out[:, 1:], outputs[:, 1:])
    turn, step = actions_from_outputs(outputs, profile)
    turn_half, step_half = actions_from_outputs(out, profile)
    np.testing.assert_allclose(turn_half, 0.5 * turn, atol=1e-12)
    np.testing.assert_array_equal(step_half, step)
    assert np.abs(turn_half).max() <= 0.5 * profile.heading_change_max + 1e-12
    # the stage's run does the same to the robots deciding
    run = TurnGain(gain=0.5).start(200, profile, None)
    np.testing.assert_array_equal(run.outputs(np.arange(200), outputs, np.zeros((200, 1))), out)


def test_at_gain_one_the_outputs_are_the_networks() -> None:
    outputs = np.array([[0.0, 1.0], [0.3, 0.2], [1.0, 0.0]])
    assert turn_gain(outputs, 1.0) is outputs  # training's case: not even a copy
    assert TurnGain().gain == 1.0 and TurnGain().record() == {}  # the paper's: off
    assert TurnGain(gain=0.75).record() == {"turn_gain": 0.75}


@pytest.mark.parametrize(
    "bad, text", [(0.0, "0"), (-0.5, "-0.5"), (1.5, "1.5"), (math.nan, ".nan"), (True, "true"),
                  ("0.5", "'0.5'")],
)  # fmt: skip
def test_a_gain_outside_zero_to_one_is_refused_naming_the_key(bad: object, text: str) -> None:
    with pytest.raises(ConfigError, match="gain"):
        TurnGain(gain=bad)  # type: ignore[arg-type]
    with pytest.raises(ConfigError, match=r"--set: stages\.turn_gain\.gain: "):
        load_deployment("none", "swarm", [f"stages.turn_gain.gain={text}"])


def test_the_shim_still_turns_by_its_full_limit_behind_the_gain() -> None:
    """A robot facing away from its goal turns on the spot by the whole limit (the shim's
    turn is not the network's); then a network that always turns fully left turns by half."""
    profile = planner(step_max=0.08, step_min=0.01)
    stages = (TurnGain(gain=0.5), RotationShim(threshold_deg=45))
    n_in = profile.n_inputs
    bias = n_in  # genome_from_edges: inputs, then the bias node, then the outputs
    genome = genome_from_edges(n_in, 2, [(bias, n_in + 1, 30.0)])  # o_1 = 1: full left
    away = Scenario(World(4.0, np.zeros((0, 4))), (1.0, 2.0, math.pi), (3.0, 2.0))
    batch = run_episodes([away], profile, FeedForwardNetwork.from_genome(genome).episode_policy(1),
                         max_steps=8, stages=stages)  # fmt: skip
    turns = batch.experience[0][:, profile.n_sensors]
    limit = profile.heading_change_max
    np.testing.assert_allclose(np.abs(turns[:4]), limit, atol=1e-12)  # the shim: pi in 4
    np.testing.assert_allclose(turns[4:], 0.5 * limit, atol=1e-12)  # the network, halved


def test_the_shipped_swarm_planners_are_deployed_with_their_gain() -> None:
    def gains(robot: str) -> list[float]:
        deployment, _ = load_deployment("shipped", robot)
        return [s.gain for s in deployment.build() if isinstance(s, TurnGain)]

    assert gains("swarm") == [0.75] and gains("ugv") == []
    swarm, ugv = get_profile("swarm"), get_profile("ugv")
    shipped = load_deployment("shipped", "swarm")[0]
    assert TurnGain(gain=0.75) in evolved(SWARM_PLANNER, swarm, deployment=shipped).stages
    ugv_planner = REPO / "planners" / "ugv-paper-dual-s1.json"
    shipped_ugv = load_deployment("shipped", "ugv")[0]
    assert not any(isinstance(s, TurnGain)
                   for s in evolved(ugv_planner, ugv, deployment=shipped_ugv).stages)  # fmt: skip
    loaded = GenomePlanner.load(SWARM_PLANNER, "swarm",
                                Deployment(stages={"turn_gain": {"gain": 0.75}}))  # fmt: skip
    assert loaded.stages[-1] == TurnGain(gain=0.75)
    with pytest.raises(ConfigError, match=r"stages\.turn_gain\.gain"):
        GenomePlanner.load(SWARM_PLANNER, "swarm", Deployment(stages={"turn_gain": {"gain": 2.0}}))


def test_the_command_lines_take_a_gain_and_the_shipped_one_can_be_dropped(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    check_stage_setting("stages.turn_gain.gain", 0.75, "1.5", "turn_gain",
                        "stages.turn_gain=null", tmp_path, capsys)  # fmt: skip
