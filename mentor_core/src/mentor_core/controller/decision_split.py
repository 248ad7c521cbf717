"""Deciding more often than trained: each decision split in time at deployment (a local
controller's rate, as Nav2's ``controller_frequency``, is a deployment setting).

Not in the paper. A planner trained to decide every ``T`` s with steps of up to ``s`` and turns
of up to ``h`` is run deciding every ``T' = T / k`` s with steps of up to ``s / k`` (and its
smallest step ``/ k``) and turns of up to ``h / k``: the same pace and the same turn rate, so
the robot drives the speeds it was trained to and a scenario's time budget holds ``k`` times
as many decisions (:func:`~mentor_core.sim.planner_settings.with_planner`). The network reads the
world ``k`` times as often; one that turns its full limit at nearly every decision, as the
evolved planners do, weaves ``k`` times less wide about its way.

A deployment's ``decisions_per_period`` (:mod:`~mentor_core.controller.deployment`). Chosen
on the benchmark's validation split for the shipped UGV planners (half their trained period,
0.25 s; experiment E079, "Deciding twice as often at deployment") and the Swarm-Robot's (0.5 s;
E081). Training at the finer period did not do as well for the UGV (E069).
"""

from __future__ import annotations

from pathlib import Path

from mentor_core.errors import ConfigError
from mentor_core.sim.planner_settings import with_planner
from mentor_core.sim.robots import RobotProfile


def at_control_period(
    profile: RobotProfile, period: float | None, source: str | Path = ""
) -> RobotProfile:
    """``profile`` (a planner's) deciding every ``period`` s, each decision that share of its
    control period's step and turn limits (module docstring); None or its own period keep it.
    ConfigError naming ``source`` for a period that is not in ``(0, profile.control_period]``.
    """
    if period is None or period == profile.control_period:
        return profile
    base = profile.control_period
    if not (isinstance(period, (int, float)) and 0.0 < period <= base):
        raise ConfigError(
            f"must be in (0, {base:g}] s (the planner's own period or shorter), got {period!r}",
            key="control_period", path=source or None,
        )  # fmt: skip
    share = period / base
    # the smallest step first: the largest is checked against it
    smaller = with_planner(profile, step_min=profile.step_min * share, source=source)
    return with_planner(
        smaller, step_max=profile.step_max * share,
        heading_change_max=profile.heading_change_max * share, control_period=period,
        source=source,
    )  # fmt: skip
