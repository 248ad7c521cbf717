"""A planner's settings on a robot profile: how a genome's network reads and acts (its input
encoding, action limits, clearance margin, context, control period; from its training config
and its metadata), each checked against the robot's own limits. The layers it is deployed
behind are not settings of the profile but stages of its deployment
(:mod:`mentor_core.controller`).

:func:`with_planner` returns the profile with the settings changed (``dataclasses.replace``),
or one ConfigError line naming the setting, the allowed range and the source (the genome file
or the config) for a value the robot cannot take.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from pathlib import Path
from typing import Any

from mentor_core.errors import ConfigError, is_number, short_repr
from mentor_core.sim.robots import INPUT_ENCODINGS, MAX_MEMORY_UNITS, RobotProfile


def with_planner(
    profile: RobotProfile,
    *,
    input_encoding: object = None,
    heading_change_max: object = None,
    step_max: object = None,
    step_min: object = None,
    clearance_margin: object = None,
    feedback_action: object = None,
    memory_units: object = None,
    control_period: object = None,
    proximity_scale: object = None,
    source: str | Path = "",
) -> RobotProfile:
    """``profile`` as a planner sees it: its input encoding, its heading-change limit (rad, in
    ``(0, pi]``), its largest step (m, in ``[profile.step_min, profile.step_max]``), its
    smallest step (m, in ``[0, step_max]``), its clearance margin (m, >= 0; see
    :func:`mentor_core.sim.observation.clearance_limit`), whether it reads its previous action
    (a bool), its memory units (a whole number in ``[0, MAX_MEMORY_UNITS]``; both see
    :func:`mentor_core.sim.observation.next_context`), its control period (s, in
    ``(0, profile.control_period]``) and its proximity scale (m, > 0;
    :func:`mentor_core.sim.observation.range_inputs`) replaced where given (None keeps the
    profile's). The layers a planner decides through are not the profile's but its stages'
    (:mod:`mentor_core.controller`).

    A planner that steps at most ``step_max`` is rated at ``rated_speed * step_max /
    profile.step_max``: the rated speed keeps its share of the top pace, so the time budget
    of a scenario (:meth:`RobotProfile.time_budget`) stays reachable. A planner that decides
    every ``control_period`` is rated ``profile.control_period / control_period`` times
    faster again, so a budget holds as many decisions as before. Its pace
    (``step_max / control_period``) and turn rate (``heading_change_max / control_period``)
    may not pass the profile's: the robot must be able to drive a decision in its period.

    All of them belong to a planner, not to the robot: the trainer takes them from its config
    and writes them into the genome's metadata (``mentor_core.runtime.planner.planner_profile``).
    ConfigError naming ``source`` and the key for a bad value.
    """
    changes: dict[str, Any] = {}
    where = source or None
    if input_encoding is not None:
        if input_encoding not in INPUT_ENCODINGS:
            raise ConfigError(
                f"must be one of {', '.join(INPUT_ENCODINGS)}, got {input_encoding!r}",
                key="input_encoding",
                path=where,
            )
        changes["input_encoding"] = str(input_encoding)
    if heading_change_max is not None:
        limit = _planner_number(
            heading_change_max, lambda v: 0.0 < v <= math.pi + 1e-12, "(0, pi] rad",
            "heading_change_max", where,
        )  # fmt: skip
        changes["heading_change_max"] = min(limit, math.pi)
    if step_max is not None:
        step = _planner_number(
            step_max, lambda v: profile.step_min <= v <= profile.step_max,
            f"[{profile.step_min}, {profile.step_max}] m", "step_max", where,
        )  # fmt: skip
        changes["step_max"] = step
        changes["rated_speed"] = profile.rated_speed * step / profile.step_max
    if step_min is not None:
        top = changes.get("step_max", profile.step_max)
        changes["step_min"] = _planner_number(
            step_min, lambda v: 0.0 <= v <= top, f"[0, {top}] m", "step_min", where
        )
    if clearance_margin is not None:
        changes["clearance_margin"] = _planner_number(
            clearance_margin, lambda v: 0.0 <= v < math.inf, "[0, inf) m", "clearance_margin",
            where,
        )  # fmt: skip
    if feedback_action is not None:
        if not isinstance(feedback_action, bool):
            raise ConfigError(
                f"must be true or false, got {feedback_action!r}", key="feedback_action",
                path=where,
            )  # fmt: skip
        changes["feedback_action"] = feedback_action
    if memory_units is not None:
        if (
            isinstance(memory_units, bool) or not isinstance(memory_units, int)
            or not 0 <= memory_units <= MAX_MEMORY_UNITS
        ):  # fmt: skip
            raise ConfigError(
                f"must be a whole number in [0, {MAX_MEMORY_UNITS}], got {memory_units!r}",
                key="memory_units", path=where,
            )  # fmt: skip
        changes["memory_units"] = memory_units
    if control_period is not None:
        changes.update(_planner_period(profile, changes, control_period, where))
    if proximity_scale is not None:
        changes["proximity_scale"] = _planner_number(
            proximity_scale, lambda v: 0.0 < v < math.inf, "(0, inf) m", "proximity_scale",
            where,
        )  # fmt: skip
    return dataclasses.replace(profile, **changes)


def _planner_period(
    profile: RobotProfile, changes: dict[str, Any], value: object, where: str | Path | None
) -> dict[str, Any]:
    """The changes a planner's control period ``value`` makes to ``profile`` with ``changes``
    already made (:func:`with_planner`); ConfigError for a period outside ``(0,
    profile.control_period]`` or one in which the robot cannot drive the planner's largest
    decision."""
    base = profile.control_period
    period = _planner_number(value, lambda v: 0.0 < v <= base, f"(0, {base}] s",
                             "control_period", where)  # fmt: skip
    step = changes.get("step_max", profile.step_max)
    turn = changes.get("heading_change_max", profile.heading_change_max)
    tolerance = 1.0 + 1e-9
    if step / period > profile.step_max / base * tolerance:
        raise ConfigError(
            f"{period} s is too short for steps of up to {step} m: the robot drives at most "
            f"{profile.step_max / base:g} m/s", key="control_period", path=where,
        )  # fmt: skip
    if turn / period > profile.heading_change_max / base * tolerance:
        raise ConfigError(
            f"{period} s is too short for turns of up to {math.degrees(turn):g} deg: the robot "
            f"turns at most {math.degrees(profile.heading_change_max / base):g} deg/s",
            key="control_period", path=where,
        )  # fmt: skip
    rated = changes.get("rated_speed", profile.rated_speed)
    return {"control_period": period, "rated_speed": rated * base / period}


def _planner_number(
    value: object, ok: Callable[[float], bool], allowed: str, key: str, where: str | Path | None
) -> float:
    """``value`` as a float when it is a number (not a bool) that ``ok`` accepts, else a
    ConfigError naming ``key`` and the ``allowed`` range."""
    if not is_number(value) or not ok(float(value)):
        raise ConfigError(
            f"must be a number in {allowed}, got {short_repr(value)}", key=key, path=where
        )
    return float(value)


__all__ = ["with_planner"]
