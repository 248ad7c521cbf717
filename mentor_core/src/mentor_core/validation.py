"""Validation of configs and data files with pydantic: strict types, one-line errors.

A config is a frozen dataclass made by :func:`config_dataclass` (a pydantic dataclass): its
fields are typed with :data:`Int`, :data:`Float`, :data:`Str`, :data:`Bool` and pydantic
``Field`` bounds, and checks across fields raise :func:`fault`. Whether built in code or from a
file's mapping (:func:`validate`), a bad value raises one :class:`ConfigError` line naming the
file and the key path (``config.yaml: evolution.mutation.weight_rate: must be <= 1, got 1.5``).
Types are strict: a whole-number field takes no float, no text and no boolean (``12.5``,
``"12"``, ``true``); a number field takes an integer but no boolean, text, NaN or infinity.

:func:`read_yaml`, :func:`read_yaml_extending`, :func:`yaml_value`, :func:`with_settings` and
:func:`merge_mappings`
are :mod:`mentor_core.yaml_reading`'s, named here too since every config is read with them.

Foundation level: imports only ``mentor_core.errors`` and ``mentor_core.yaml_reading`` (and
pydantic).
"""

from __future__ import annotations

import dataclasses
import types
import typing
from collections.abc import Callable
from pathlib import Path
from typing import Annotated, Any, TypeVar, dataclass_transform, get_args, get_origin

from pydantic import ConfigDict, Field, Strict, TypeAdapter, ValidationError
from pydantic.dataclasses import dataclass as pydantic_dataclass
from pydantic_core import ArgsKwargs, PydanticCustomError

from mentor_core.errors import ConfigError, short_repr
from mentor_core.yaml_reading import (
    merge_mappings,
    read_yaml,
    read_yaml_extending,
    with_settings,
    yaml_value,
)

#: a whole number: 12.5, "12" and true are refused
Int = Annotated[int, Strict()]
#: a finite number (an integer is taken as a float): true, text, NaN and infinity are refused
Float = Annotated[float, Strict()]
#: text: a number or a boolean is refused
Str = Annotated[str, Strict()]
#: true or false: 1 and "yes" are refused
Bool = Annotated[bool, Strict()]

#: every config: unknown keys refused, no NaN or infinity; a field's docstring (the text below
#: it) is its description in the JSON schema
CONFIG = ConfigDict(extra="forbid", allow_inf_nan=False, use_attribute_docstrings=True)

T = TypeVar("T")
_CUSTOM = "mentor_config"


@dataclass_transform(frozen_default=True, field_specifiers=(dataclasses.field, Field))
def config_dataclass(cls: type[T]) -> type[T]:
    """``cls`` as a frozen pydantic dataclass (:data:`CONFIG`) whose constructor raises one
    :class:`ConfigError` line naming the key, not pydantic's ValidationError."""
    built: Any = pydantic_dataclass(frozen=True, config=CONFIG)(cls)
    validator = built.__pydantic_validator__

    def __init__(self: Any, *args: Any, **kwargs: Any) -> None:
        try:
            validator.validate_python(ArgsKwargs(args, kwargs), self_instance=self)
        except ValidationError as err:
            raise config_error(err, root=built) from None

    __init__.__qualname__ = f"{built.__qualname__}.__init__"
    built.__init__ = __init__
    return typing.cast(type[T], built)


def fault(key: str, message: str) -> PydanticCustomError:
    """The error a check across fields raises (in a ``model_validator``) for field ``key``:
    reported as ``<section>.<key>: <message>``."""
    return PydanticCustomError(_CUSTOM, "{message}", {"key": key, "message": message})


def validate(
    cls: type[T], data: object, path: str | Path | None = None, prefix: str = ""
) -> T:
    """``cls`` built from ``data`` (a file's mapping); ConfigError naming ``path`` and the key
    path of the first fault (and how many more there are), after ``prefix`` (the section
    ``data`` is in the file, e.g. ``doe``)."""
    built: Any = cls  # a pydantic dataclass
    try:
        return typing.cast(T, built.__pydantic_validator__.validate_python(data))
    except ValidationError as err:
        raise config_error(err, path, root=cls, prefix=prefix) from None


def to_plain(obj: object) -> Any:
    """A config as plain YAML/JSON values (tuples as lists), field by field in order."""
    built: Any = type(obj)  # a pydantic dataclass
    return built.__pydantic_serializer__.to_python(obj, mode="json")


def json_schema(cls: type[Any]) -> dict[str, Any]:
    """The JSON schema (draft 2020-12) of a config dataclass, for editors."""
    return TypeAdapter(cls).json_schema()


def config_error(
    err: ValidationError, path: str | Path | None = None, root: Any = None, prefix: str = ""
) -> ConfigError:
    """The first fault of ``err`` as one ConfigError line: key path (``a.b[2].c`` after
    ``prefix``), what is wrong and the value given; ``root`` (the validated type) lets an
    unknown key list the known ones."""
    errors = err.errors(include_url=False)
    first = errors[0]
    loc = list(first["loc"])
    ctx = first.get("ctx") or {}
    if first["type"] == _CUSTOM:
        loc.append(str(ctx["key"]))
        message = str(ctx["message"])
    else:
        loc, message = _message(first, root, loc)
    if len(errors) > 1:
        message += f" (and {len(errors) - 1} more fault{'s' if len(errors) > 2 else ''})"
    return ConfigError(message, key=_key([prefix, *loc] if prefix else loc) or None, path=path)


def _key(loc: list[Any]) -> str:
    out = ""
    for part in loc:
        out += f"[{part}]" if isinstance(part, int) else (f".{part}" if out else str(part))
    return out


_MESSAGES: dict[str, Callable[[dict[str, Any]], str]] = {
    "int_type": lambda e: "expected a whole number",
    "float_type": lambda e: "expected a number",
    "finite_number": lambda e: "expected a finite number",
    "string_type": lambda e: "expected text",
    "bool_type": lambda e: "expected true or false",
    "dataclass_type": lambda e: "expected a mapping",
    "greater_than": lambda e: f"must be > {e['ctx']['gt']}",
    "greater_than_equal": lambda e: f"must be >= {e['ctx']['ge']}",
    "less_than": lambda e: f"must be < {e['ctx']['lt']}",
    "less_than_equal": lambda e: f"must be <= {e['ctx']['le']}",
}


def _message(e: Any, root: Any, loc: list[Any]) -> tuple[list[Any], str]:
    """(key path, message) of one pydantic error."""
    kind = e["type"]
    if kind in ("unexpected_keyword_argument", "extra_forbidden"):
        known = _field_names(_type_at(root, loc[:-1]))
        return loc, "unknown key" + (f" (known: {', '.join(known)})" if known else "")
    if kind in ("missing", "missing_argument"):
        if loc and isinstance(loc[-1], int):  # a list too short for its tuple
            size = len(get_args(_unwrap(_type_at(root, loc[:-1]))))
            return loc[:-1], f"expected {_values(size)}, got {short_repr(e['input'])}"
        return loc, "missing key"
    if kind in ("too_long", "too_short"):
        ctx = e["ctx"]
        size = ctx.get("max_length") if kind == "too_long" else ctx.get("min_length")
        at_least = "at least " if kind == "too_short" else ""
        return loc, f"expected {at_least}{_values(size)}, got {short_repr(e['input'])}"
    make = _MESSAGES.get(kind)
    if make is not None:
        text = make(e)
    else:
        text = str(e["msg"]).removeprefix("Value error, ").replace("Input should be", "must be")
        text = text[:1].lower() + text[1:]
    return loc, f"{text}, got {short_repr(e['input'])}"


def _values(n: int) -> str:
    return f"{n} value" if n == 1 else f"{n} values"


def _type_at(root: Any, loc: list[Any]) -> Any:
    """The type at key path ``loc`` inside the dataclass ``root`` (None when unknown)."""
    tp = root
    for part in loc:
        tp = _unwrap(tp)
        if get_origin(tp) is dict:  # a mapping's value, whatever its key
            tp = get_args(tp)[1]
        elif isinstance(part, int):
            args = [a for a in get_args(tp) if a is not Ellipsis]
            if not args:
                return None
            tp = args[min(part, len(args) - 1)]
        elif dataclasses.is_dataclass(tp) and isinstance(tp, type):
            tp = typing.get_type_hints(tp, include_extras=True).get(part)
        else:
            return None
    return tp


def _field_names(tp: Any) -> list[str]:
    tp = _unwrap(tp)
    if dataclasses.is_dataclass(tp) and isinstance(tp, type):
        return [f.name for f in dataclasses.fields(tp)]
    return []


def _unwrap(tp: Any) -> Any:
    """``X`` of ``Annotated[X, ...]`` and of ``X | None``."""
    while True:
        origin = get_origin(tp)
        if origin is Annotated:
            tp = get_args(tp)[0]
        elif origin in (typing.Union, types.UnionType):
            rest = [a for a in get_args(tp) if a is not type(None)]
            if len(rest) != 1:
                return tp
            tp = rest[0]
        else:
            return tp


__all__ = [
    "CONFIG",
    "Bool",
    "Float",
    "Int",
    "Str",
    "config_dataclass",
    "config_error",
    "fault",
    "json_schema",
    "merge_mappings",
    "read_yaml",
    "read_yaml_extending",
    "to_plain",
    "validate",
    "with_settings",
    "yaml_value",
]
