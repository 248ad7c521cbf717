"""Argument parsing shared by the ``mentor-*`` commands: one-line errors and checked values.

A bad argument (a seed of -1, ``--n -2``, a missing option) is refused by argparse itself, in
one line ``PROG: error: ARGUMENT: FAULT (see PROG --help)`` with exit status 2, before any work
starts, the same as every other bad input of the commands.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path
from typing import NoReturn

from mentor_core.controller.deployment import NAMED, Deployment, load_deployment
from mentor_core.errors import ConfigError


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


def add_deployment_arguments(
    parser: argparse.ArgumentParser, what: str, repeatable: bool = False
) -> None:
    """``--deployment NAME|FILE`` (``repeatable``: one run per deployment given) and ``--set
    KEY=VALUE``: how ``what`` run (:mod:`mentor_core.controller.deployment`)."""
    again = " (repeatable: a run per deployment, labelled <label> (<deployment>))"
    parser.add_argument(
        "--deployment", action="append" if repeatable else "store", metavar="NAME|FILE",
        help=f"run {what} as this deployment: 'shipped' (the shipped planners' of the robot: "
        "data/deployments.yaml), 'none' (as trained; the default) or a deployment YAML file "
        f"(docs/deployment.md){again if repeatable else ''}",
    )  # fmt: skip
    parser.add_argument(
        "--set", action="append", default=[], metavar="KEY=VALUE", dest="deployment_settings",
        help="change one key of the deployment (repeatable), a dotted key path and a YAML "
        "value: --set stages.turn_gain.gain=1, --set decisions_per_period=1, "
        "--set stages.collision_guard=null",
    )  # fmt: skip


def deployment_names(args: argparse.Namespace) -> list[str]:
    """The deployments ``--deployment`` names (``none`` when not given), in order."""
    given = args.deployment
    if given is None:
        return ["none"]
    return list(given) if isinstance(given, list) else [given]


def deployment_files(args: argparse.Namespace) -> list[Path]:
    """The deployment files ``--deployment`` names (inputs no output may replace)."""
    return [Path(name) for name in deployment_names(args) if name not in NAMED]


def deployment_of(args: argparse.Namespace, robot: str) -> list[Deployment]:
    """The deployments ``--deployment`` and ``--set`` name for robot ``robot``, in order;
    ConfigError naming the file or ``--set`` and the key, and for ``--set`` with more than
    one deployment (which one it changes would not show in the runs' labels)."""
    names = deployment_names(args)
    if len(names) > 1 and args.deployment_settings:
        raise ConfigError("give one --deployment with --set (write a deployment file for "
                          "each other one)", path="--set")  # fmt: skip
    return [load_deployment(name, robot, args.deployment_settings)[0] for name in names]


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


__all__ = [
    "Parser", "add_deployment_arguments", "count", "deployment_files", "deployment_names",
    "deployment_of",
    "duration", "fail", "index", "seed",
]
