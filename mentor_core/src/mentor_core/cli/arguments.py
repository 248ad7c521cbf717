"""Argument parsing shared by the ``mentor-*`` commands: one-line errors and checked values.

A bad argument (a seed of -1, ``--n -2``, a missing option) is refused by argparse itself, in
one line ``PROG: error: ARGUMENT: FAULT (see PROG --help)`` with exit status 2, before any work
starts, the same as every other bad input of the commands.
"""

from __future__ import annotations

import argparse
import math
import sys
from typing import NoReturn

from mentor_core.errors import MentorError
from mentor_core.navigation.scan_map import scan_guide_config
from mentor_core.sim.robots import RobotProfile


class Parser(argparse.ArgumentParser):
    """An ArgumentParser whose errors are one line on stderr and exit status 2."""

    def error(self, message: str) -> NoReturn:
        """Print ``PROG: error: MESSAGE (see PROG --help)`` and exit 2."""
        text = " ".join(message.split())
        self.exit(2, f"{self.prog}: error: {text} (see {self.prog} --help)\n")


def seed(text: str) -> int:
    """A seed of numpy's generators: a whole number >= 0."""
    return _whole(text, 0, "a whole number >= 0")


def index(text: str) -> int:
    """An index or a count that may be 0: a whole number >= 0."""
    return _whole(text, 0, "a whole number >= 0")


def count(text: str) -> int:
    """A count of things: a whole number >= 1."""
    return _whole(text, 1, "a whole number >= 1")


def duration(text: str) -> float:
    """A positive finite number of seconds."""
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not (math.isfinite(value) and value > 0.0):
        raise argparse.ArgumentTypeError(f"expected a positive number of seconds, got {text!r}")
    return value


def rotation_shim_threshold(degrees: float | None) -> float | None:
    """``--rotation-shim DEG`` as the profile's threshold (rad; None when not given);
    MentorError unless DEG lies in (0, 180]."""
    if degrees is None:
        return None
    if not 0.0 < degrees <= 180.0:
        raise MentorError(f"--rotation-shim must be in (0, 180] deg, got {degrees}")
    return math.radians(degrees)


def turn_gain_value(gain: float | None) -> float:
    """``--turn-gain G`` as the profile's gain on the turn (1 when not given); MentorError
    unless G lies in (0, 1]."""
    if gain is None:
        return 1.0
    if not 0.0 < gain <= 1.0:
        raise MentorError(f"--turn-gain must be in (0, 1], got {gain}")
    return gain


def view_margin(text: str) -> float:
    """``--view-margin``'s text: a number of metres, or ``none`` (``inf``: no corridor, as
    everything lies within an infinite margin); :func:`view_margin_value` checks it."""
    if text.strip().lower() == "none":
        return math.inf
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected metres or 'none', got {text!r}") from None


def view_margin_value(margin: float | None) -> float | None:
    """``--view-margin M`` as the profile's view corridor margin (None when not given; ``inf``
    for ``none``); MentorError unless M is a positive number of metres."""
    if margin is not None and not margin > 0.0:
        raise MentorError(f"--view-margin must be a positive number of metres or 'none', "
                          f"got {margin}")  # fmt: skip
    return margin


def control_period_value(period: float | None) -> float | None:
    """``--control-period S`` (None when not given); MentorError unless S is a positive number
    of seconds (whether it is at most a genome's own period is the genome's check)."""
    if period is not None and not (math.isfinite(period) and period > 0.0):
        raise MentorError(f"--control-period must be a positive number of seconds, got {period}")
    return period


def add_clearance_arguments(parser: argparse.ArgumentParser) -> None:
    """``--clearance-cost W`` and ``--least-margin M``: the plan on the scan map's clearance
    cost (``navigation.scan_map.scan_guide_config``)."""
    parser.add_argument("--clearance-cost", type=float, metavar="W",
                        help="with --scan-map or --deployed: the weight of the plan's cost for "
                             "keeping less than its margin (a footprint radius) clear, >= 0; "
                             "0: the margin is a hard disc (default: the robot's, 1 for the "
                             "Swarm-Robot, 0 for the UGV)")
    parser.add_argument("--least-margin", type=float, metavar="M",
                        help="with --scan-map or --deployed and a clearance cost: the least "
                             "margin the plan keeps, m (default half a footprint radius)")


def clearance_values(args: argparse.Namespace, robot: RobotProfile) -> dict[str, float | None]:
    """``--clearance-cost`` and ``--least-margin`` as ``scan_guide_config``'s keywords (None:
    the robot's); MentorError for either without a scan map (``--scan-map`` or
    ``--deployed``), a negative cost, or a least margin outside ``[0, the plan's whole
    margin]`` (its robot's scan-map margin, a footprint radius)."""
    for flag in ("clearance_cost", "least_margin"):
        if getattr(args, flag) is not None and not (args.scan_map or args.deployed):
            raise MentorError(f"--{flag.replace('_', '-')}: only with --scan-map or --deployed")
    cost, least = args.clearance_cost, args.least_margin
    if cost is not None and not (math.isfinite(cost) and cost >= 0.0):
        raise MentorError(f"--clearance-cost must be a number >= 0, got {cost}")
    whole = scan_guide_config(robot).margin
    if least is not None and not (math.isfinite(least) and 0.0 <= least <= whole):
        raise MentorError(f"--least-margin must be in [0, {whole:g}] m (the plan's whole "
                          f"margin, a footprint radius), got {least}")  # fmt: skip
    return {"clearance_cost": cost, "least_margin": least}


def check_deployed(args: argparse.Namespace) -> None:
    """MentorError when ``--deployed`` comes with one of the flags that add the layers it
    adds itself (``--scan-map``, ``--rotation-shim``, ``--collision-guard``); its gain on
    the turn and view corridor may be replaced (``--turn-gain``, ``--view-margin``)."""
    if args.deployed and (args.scan_map or args.rotation_shim is not None
                          or args.collision_guard):  # fmt: skip
        raise MentorError("--deployed: give none of --scan-map, --rotation-shim, "
                          "--collision-guard with it (it adds them all)")


def _whole(text: str, least: int, expected: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected {expected}, got {text!r}") from None
    if value < least:
        raise argparse.ArgumentTypeError(f"expected {expected}, got {value}")
    return value


def fail(prog: str, message: object) -> int:
    """Print ``PROG: MESSAGE`` (on one line) on stderr; returns exit status 2."""
    print(f"{prog}: {' '.join(str(message).split())}", file=sys.stderr)
    return 2


__all__ = ["Parser", "count", "duration", "fail", "index", "seed"]
