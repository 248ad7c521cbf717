"""ROS command-line arguments checked before rcl sees them, so that a bad one is one line.

rcl parses every ``-p name:=value`` (``--param``) rule inside ``--ros-args`` as YAML and takes
only a scalar or a list of scalars; anything else (a JSON object such as ``{"who": "review"}``
is a YAML mapping) makes ``rclpy.init`` log an error and raise. :func:`parameter_fault` finds
such a rule first and says how to pass the value as a string.
"""

from __future__ import annotations

from collections.abc import Sequence

import yaml

_SCALARS = (str, int, float, bool)


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
                value = yaml.safe_load(text)
            except yaml.YAMLError:
                return f"-p {name}: {text!r} is not YAML"
            if not _is_value(value):
                kind = "mapping" if isinstance(value, dict) else "nested list"
                quoted = text.replace("\\", "\\\\").replace('"', '\\"')
                return (
                    f"-p {name}: {text} is a YAML {kind}, not a parameter value; quote it "
                    f"as a string: -p '{name}:=\"{quoted}\"'"
                )
    return ""
