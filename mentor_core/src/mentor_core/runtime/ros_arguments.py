"""ROS command-line arguments checked before rcl sees them, so that a bad one is one line.

rcl parses every ``-p name:=value`` (``--param``) rule inside ``--ros-args`` as YAML and takes
only a scalar or a list of scalars; anything else (a JSON object such as ``{"who": "review"}``
is a YAML mapping) makes ``rclpy.init`` log an error and raise. :func:`parameter_fault` finds
such a rule first and says how to pass the value as a string.

The launch files read their arguments' text with :func:`launch_flag`, :func:`launch_number`
and :func:`launch_count`, which refuse a typo (``collision_guard:=ture``) in one line, as
ROS's own launch conditions refuse anything but ``true``, ``false``, ``1`` and ``0``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from mentor_core.errors import MentorError, short_repr
from mentor_core.validation import yaml_value

#: s, the shortest period a node's timer may be set to run at (100 Hz): shorter ones would
#: take a whole core and answer nothing more
MIN_PERIOD = 0.01
_SCALARS = (str, int, float, bool)
_FLAGS = {"true": True, "1": True, "yes": True, "false": False, "0": False, "no": False}


def _is_value(value: object) -> bool:
    if value is None or isinstance(value, _SCALARS):
        return True
    return isinstance(value, list) and all(isinstance(v, _SCALARS) for v in value)


def parameter_fault(argv: Sequence[str]) -> str:
    """Why a ``-p name:=value`` rule of ``argv`` (a node's command line) is no parameter
    value (one line), or '' when every rule is fine (or not a rule this checks)."""
    inside = False
    args = list(argv)
    for k, arg in enumerate(args):
        if arg == "--ros-args":
            inside = True
        elif arg == "--":
            inside = False
        elif inside and arg in ("-p", "--param") and k + 1 < len(args):
            name, sep, text = args[k + 1].partition(":=")
            if not sep:
                continue
            try:
                value = yaml_value(text)
            except ValueError as err:
                return f"-p {name}: {short_repr(text)} is not YAML ({err})"
            if not _is_value(value):
                kind = "mapping" if isinstance(value, dict) else "nested list"
                quoted = text.replace("\\", "\\\\").replace('"', '\\"')
                return (
                    f"-p {name}: {text} is a YAML {kind}, not a parameter value; quote it "
                    f"as a string: -p '{name}:=\"{quoted}\"'"
                )
    return ""


def period_fault(name: str, seconds: float) -> str:
    """Why a node parameter ``name`` that sets a timer's period to ``seconds`` (a rate's
    inverse) is refused (one line: below :data:`MIN_PERIOD`, or not a positive number), or
    ''."""
    if not seconds > 0.0 or math.isinf(seconds):
        return f"{name}: {seconds} s is not a period > 0"
    if seconds < MIN_PERIOD:
        return (f"{name}: a period of {seconds:g} s is shorter than the floor of "
                f"{MIN_PERIOD:g} s ({1.0 / MIN_PERIOD:g} Hz)")
    return ""


def launch_flag(name: str, text: str) -> bool:
    """A launch argument ``name:=text`` as a bool: ``true``/``false``, ``1``/``0`` or
    ``yes``/``no`` in any case; MentorError (one line naming it) for anything else."""
    flag = _FLAGS.get(text.strip().lower())
    if flag is None:
        raise MentorError(f"{name}:={text}: expected true or false")
    return flag


def launch_number(name: str, text: str) -> float:
    """A launch argument ``name:=text`` as a float; MentorError (one line naming it) for
    anything that is not a finite number."""
    try:
        number = float(text)
    except ValueError:
        number = math.nan
    if not math.isfinite(number):
        raise MentorError(f"{name}:={text}: expected a number")
    return number


def launch_numbers(name: str, text: str) -> list[float]:
    """A launch argument ``name:=text`` as a list of finite floats (``[0.0, -0.5]``);
    MentorError (one line naming it) for anything else."""
    try:
        numbers = [float(v) for v in yaml_value(text)]
    except (TypeError, ValueError):
        numbers = [math.nan]
    if not all(math.isfinite(v) for v in numbers):
        raise MentorError(f"{name}:={text}: expected a list of numbers like [0.0, 0.0]")
    return numbers


def launch_count(name: str, text: str) -> int:
    """A launch argument ``name:=text`` as a whole number >= 0; MentorError (one line naming
    it) for anything else."""
    try:
        count = int(text)
    except ValueError:
        count = -1
    if count < 0:
        raise MentorError(f"{name}:={text}: expected a whole number >= 0")
    return count
