"""The problems a trainer config asks for: its training problem (:func:`make_problem`: the
robot's scenarios, the network's inputs and the F settings) and the scenarios its refinement
draws (:func:`refinement_problem`), checked before any generation runs.
"""

from __future__ import annotations

import dataclasses

from mentor_core.errors import ConfigError, one_line
from mentor_core.sim.planner_settings import with_planner
from mentor_core.sim.robots import RobotProfile, get_profile
from mentor_core.sim.scenarios import training_scenarios
from mentor_core.training.config import TrainerConfig
from mentor_core.training.curriculum import family_scenarios, unseen_distances
from mentor_core.training.problem import NavigationProblem


def make_problem(
    config: TrainerConfig, profile: RobotProfile | None = None, source: str = "trainer config"
) -> NavigationProblem:
    """The training problem of a config: its robot's scenarios from ``scenario_seed``, the
    network fed with the config's input encoding (``profile`` defaults to the shipped one).

    ConfigError naming ``source`` (the config file) for planner settings outside the robot's
    own ranges and more training worlds than scenarios."""
    robot = profile or get_profile(config.robot)
    prof = with_planner(robot, **config.planner_settings(), source=source)
    if config.turn_frame == "goal" and config.input_encoding != "egocentric":
        raise ConfigError(
            "turns relative to the goal need input_encoding: egocentric", key="turn_frame",
            path=source,
        )  # fmt: skip
    count = config.n_scenarios or prof.train_scenarios
    if config.training_worlds > count:
        raise ConfigError(
            f"{count} training scenarios cannot cover {config.training_worlds} worlds",
            key="training_worlds",
            path=source,
        )
    # pairs must be drivable within the budget a training pair gets (the config's, when set)
    bound = prof if config.time_budget is None else dataclasses.replace(
        prof, time_budget_cap=config.time_budget)
    distances = unseen_distances(robot, bound) if config.pair_distances == "test" else None
    try:
        scenarios = training_scenarios(
            prof, config.scenario_seed, count, cfg=config.doe, worlds=config.training_worlds,
            distances=distances,
        )  # fmt: skip
    except ValueError as err:  # more pairs than the training worlds' free space holds
        raise ConfigError(one_line(err), key="n_scenarios", path=source) from None
    if config.families:
        try:
            scenarios += family_scenarios(
                robot, bound, config.families,
                config.family_pairs, config.scenario_seed,
            )  # fmt: skip
        except ValueError as err:
            raise ConfigError(str(err), key="families", path=source) from None
    return NavigationProblem(
        prof, scenarios, time_budget=config.time_budget, goal_distance=config.goal_distance,
        stages=config.trained_stages(), turn_frame=config.turn_frame,
        success_credit=config.success_credit, guide=config.guide,
        guide_share=config.guide_share,
    )


def refinement_problem(
    config: TrainerConfig, source: str = "trainer config", profile: RobotProfile | None = None
) -> NavigationProblem | None:
    """The refinement scenarios of a config (None when it refines nothing): the training
    draw from the refinement's own seed, count, worlds and budget, with the training's and
    its own families' worlds at its family_pairs (:mod:`~mentor_core.training.refinement`),
    for ``profile`` as :func:`make_problem` takes it (default the shipped one).

    ConfigError naming ``refinement.<key>`` when they cannot be drawn (a family's world with
    too few solvable pairs); :func:`train` builds them before the first generation, so that
    such a config fails at once rather than after the evolution."""
    cfg = config.refinement
    if cfg.iterations == 0:
        return None
    scenarios = dataclasses.replace(
        config, scenario_seed=cfg.scenario_seed, n_scenarios=cfg.scenarios,
        training_worlds=cfg.worlds, time_budget=cfg.time_budget,
        families=tuple(dict.fromkeys(config.families + cfg.families)),
        family_pairs=cfg.family_pairs if cfg.families else config.family_pairs,
    )  # fmt: skip
    try:
        return make_problem(scenarios, profile, source=source)
    except ConfigError as err:
        key = "refinement" if err.key is None else f"refinement.{err.key}"
        raise ConfigError(err.message, key=key, path=err.path) from None


__all__ = ["make_problem", "refinement_problem"]
