"""Episodes: many robots, one policy call per control period for all of them in a world.

Each robot runs one scenario. Once per control period every still-active robot reads its
sensors, its decision passes the decision chain (:mod:`~mentor_core.controller.pipeline`: the
deployment's stages about one policy call for all of them), and
:class:`mentor_core.sim.engine.BatchEngine` moves every robot along its arc. A robot stops when
it reaches its goal, collides, or has used its ``ceil(T_tot / control_period)`` decisions
(T_tot from :meth:`RobotProfile.time_budget`, the paper's T_tot,i). The outcome is a
:class:`~mentor_core.sim.episode.EpisodeBatch` (time and experience: its module docstring).

Context (a planner with ``feedback_action`` or ``memory_units``): each robot carries what its
network output at its previous decision into its next inputs
(:func:`mentor_core.sim.observation.next_context`), from
:func:`~mentor_core.sim.observation.initial_context` at its episode's start. It is not part
of the experience: G measures behaviour (readings and actions), as in the paper.
"""

from __future__ import annotations

from collections.abc import Sequence
from itertools import chain as flat

import numpy as np
from numpy.typing import ArrayLike, NDArray

from mentor_core.controller.pipeline import DecisionChain
from mentor_core.controller.stage import Stage
from mentor_core.sim import observation
from mentor_core.sim.engine import BatchEngine
from mentor_core.sim.episode import (
    EpisodeBatch,
    InputGoals,
    Policy,
    decision_limits,
    group_experience,
    merge_batches,
    world_groups,
)
from mentor_core.sim.robots import RobotProfile
from mentor_core.sim.sensors import Backend
from mentor_core.sim.world import Scenario

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]


def run_episodes(
    scenarios: Sequence[Scenario], profile: RobotProfile, policy: Policy, *,
    time_budgets: ArrayLike | None = None, max_steps: int | None = None,
    backend: Backend = "auto", input_goals: InputGoals | None = None,
    stages: Sequence[Stage] = (),
) -> EpisodeBatch:
    """Run one robot per scenario to the end.

    The robots of one world step together in one engine; scenarios in several worlds run as
    one such batch per world, and since a robot's outputs do not depend on which robots share
    a policy call, the result is the same as one run per scenario.

    Args:
        scenarios: start/goal pairs, in one world or several.
        profile: the robot.
        policy: ``policy(inputs (m, n_inputs), robots (m,) int) -> outputs (m, n_outputs)``
            (the profile's: the two actions, then its memory units), called
            once per control period (and world) for the ``m`` still-active robots (indices
            into ``scenarios``, ascending).
        time_budgets: per-scenario T_tot (s) instead of ``profile.time_budget``.
        max_steps: cap on the decisions of every robot.
        backend: kernel backend of the engine.
        input_goals: the goal (x, y) each network sees, called like ``policy`` with the
            robots' poses (a carrot along a global path); None: its scenario's goal. Reaching
            is always judged against the scenario's goal.
        stages: the controller's stages each decision passes
            (:class:`~mentor_core.controller.pipeline.DecisionChain`; none: the network
            decides alone, as in the paper), fresh for each world.
    """
    groups = world_groups(scenarios)
    if len(groups) == 1:
        return _run_world(
            scenarios, profile, policy, time_budgets, max_steps, backend, input_goals, stages
        )
    n = len(scenarios)
    budgets = (
        None if time_budgets is None
        else np.broadcast_to(np.asarray(time_budgets, dtype=np.float64), (n,))
    )  # fmt: skip
    parts = []
    for idx in groups:
        def world_policy(inputs: FloatArray, robots: IntArray, idx: IntArray = idx) -> ArrayLike:
            return policy(inputs, idx[robots])

        def world_goals(poses: FloatArray, robots: IntArray, idx: IntArray = idx) -> ArrayLike:
            assert input_goals is not None
            return input_goals(poses, idx[robots])

        parts.append(_run_world(
            [scenarios[i] for i in idx], profile, world_policy,
            None if budgets is None else budgets[idx], max_steps, backend,
            None if input_goals is None else world_goals, stages,
        ))  # fmt: skip
    return merge_batches(parts, groups, n)


def _aims(input_goals: InputGoals, poses: FloatArray, idx: IntArray) -> FloatArray:
    """The goals ``(m, 2)`` the networks of robots ``idx`` at ``poses`` see."""
    aims = np.asarray(input_goals(poses.copy(), idx), dtype=np.float64)
    if aims.shape != (idx.size, 2):
        raise ValueError(f"input_goals gave shape {aims.shape}, need {(idx.size, 2)}")
    return aims


def _run_world(
    scenarios: Sequence[Scenario], profile: RobotProfile, policy: Policy,
    time_budgets: ArrayLike | None, max_steps: int | None, backend: Backend,
    input_goals: InputGoals | None, stages: Sequence[Stage],
) -> EpisodeBatch:
    """:func:`run_episodes` of scenarios that all lie in the first one's world."""
    world = scenarios[0].world
    n = len(scenarios)
    # fromiter over the flat coordinates: half the time of np.array over 8,000 tuples
    starts = np.fromiter(flat.from_iterable([sc.start for sc in scenarios]), np.float64,
                         count=3 * n).reshape(n, 3)
    goals = np.fromiter(flat.from_iterable([sc.goal for sc in scenarios]), np.float64,
                        count=2 * n).reshape(n, 2)
    budget, allowed = decision_limits(starts, goals, profile, time_budgets, max_steps)
    dt = float(profile.control_period)

    engine = BatchEngine(world, profile, backend=backend)
    engine.reset(starts, goals)
    reached = engine.goal_distance() <= profile.goal_radius  # already there: no decision
    collided = np.zeros(n, dtype=np.bool_)
    steps = np.zeros(n, dtype=np.int64)
    time_used = np.zeros(n, dtype=np.float64)
    active = ~reached & (allowed > 0)
    ranges = engine.observe()
    chain = DecisionChain(profile, stages, n, world.size)
    trajectory = [engine.poses.copy()]
    chunks: list[FloatArray] = []
    owners: list[IntArray] = []
    zeros = np.zeros(n, dtype=np.float64)

    while active.any():
        idx = np.flatnonzero(active)
        seen = ranges[idx]
        aims = goals[idx] if input_goals is None else _aims(input_goals, engine.poses[idx], idx)
        decision = chain.decide(idx, seen, engine.poses[idx], aims, policy)
        dth, ds = decision.dtheta, decision.ds
        dtheta_all, ds_all = zeros.copy(), zeros.copy()
        dtheta_all[idx], ds_all[idx] = dth, ds
        result = engine.step(dtheta_all, ds_all, active)
        after = engine.observe(idx)
        action = np.stack([dth, ds], axis=1)
        chunks.append(observation.experience_point(seen, action, after, profile))
        owners.append(idx)
        ranges[idx] = after
        steps[idx] += 1
        time_used[idx] += np.where(result.reached[idx], result.fraction[idx], 1.0) * dt
        reached |= result.reached
        collided |= result.collided
        active &= ~(result.reached | result.collided) & (steps < allowed)
        trajectory.append(engine.poses.copy())

    rows, experience = group_experience(chunks, owners, steps, 2 * profile.n_sensors + 2)
    return EpisodeBatch(
        reached=reached,
        collided=collided,
        timed_out=~(reached | collided),
        time_used=time_used,
        time_budget=budget,
        final_distance=engine.goal_distance(),
        steps=steps,
        trajectories=np.stack(trajectory, axis=1),
        experience=experience,
        experience_rows=rows,
    )
