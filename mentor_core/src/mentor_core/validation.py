"""Validation of configs and data files with pydantic: strict types, one-line errors.

A config is a frozen dataclass made by :func:`config_dataclass` (a pydantic dataclass): its
fields are typed with :data:`Int`, :data:`Float`, :data:`Str`, :data:`Bool` and pydantic
``Field`` bounds, and checks across fields raise :func:`fault`. Whether built in code or from a
file's mapping (:func:`validate`), a bad value raises one :class:`ConfigError` line naming the
file and the key path (``config.yaml: evolution.mutation.weight_rate: must be <= 1, got 1.5``).
Types are strict: a whole-number field takes no float, no text and no boolean (``12.5``,
``"12"``, ``true``); a number field takes an integer but no boolean, text, NaN or infinity.

:func:`read_yaml` reads every YAML file of the library (configs, robot and world files) with
YAML 1.2 numbers (``1e12`` is a number, not text as in YAML 1.1) and refuses an empty file.

Foundation level: imports only ``mentor_core.errors`` (and pydantic, yaml).
"""

from __future__ import annotations

import dataclasses
import re
import reprlib
import types
import typing
from collections.abc import Callable
from pathlib import Path
from typing import Annotated, Any, TypeVar, dataclass_transform, get_args, get_origin

import yaml
from pydantic import ConfigDict, Field, Strict, TypeAdapter, ValidationError
from pydantic.dataclasses import dataclass as pydantic_dataclass
from pydantic_core import ArgsKwargs, PydanticCustomError

from mentor_core.errors import ConfigError, FileFormatError, one_line

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
_REPR_MAX = 60
_REPR = reprlib.Repr()
_REPR.maxstring = _REPR.maxother = _REPR.maxlong = _REPR_MAX


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


def short_repr(value: object) -> str:
    """``repr(value)`` cut to :data:`_REPR_MAX` characters, built within that bound (a value
    may be huge: reprlib shows only the first items of each level)."""
    try:
        text = _REPR.repr(value)
    except (ValueError, RecursionError):  # an int past Python's 4300 digits
        text = f"<{type(value).__name__}>"
    return text if len(text) <= _REPR_MAX else text[: _REPR_MAX - 3] + "..."


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


#: the largest YAML file read, in bytes (the shipped configs, robot files and bag metadata
#: are a few kB; a world of thousands of obstacles is well under this)
YAML_MAX_BYTES = 8 * 1024 * 1024
#: the deepest nesting of mappings and lists a YAML document may have, aliases expanded (the
#: shipped files nest at most 5 deep; Python's recursion limit is met near 300)
YAML_MAX_DEPTH = 64
#: the most values a YAML document may hold with its aliases expanded: an "alias bomb" of a
#: few hundred bytes expands to billions, which every reader of the data would then walk
YAML_MAX_VALUES = 1_000_000


class _Loader(yaml.SafeLoader):
    """PyYAML's safe loader reading YAML 1.2's core schema, within bounds.

    * Scalars resolve as in YAML 1.2 (and ROS's yaml-cpp): ``1e12`` and ``5e-2`` are numbers
      (text in YAML 1.1), ``1_2``, ``0b1``, ``1:30``, ``yes`` and ``on`` are text (YAML 1.1's
      12, 1, 90 and true), ``012`` is twelve, and dates stay text.
    * A mapping with a key twice is refused (YAML 1.2 forbids it; PyYAML keeps the last).
    * A document nested deeper than :data:`YAML_MAX_DEPTH`, holding more than
      :data:`YAML_MAX_VALUES` values with its aliases expanded, or referring to itself is
      refused before anything is built from it.
    """

    def __init__(self, stream: Any) -> None:
        super().__init__(stream)
        self._depth = 0

    def compose_node(self, parent: Any, index: Any) -> Any:
        # the composer recurses per level: refused long before Python's recursion limit
        self._depth += 1
        try:
            if self._depth > YAML_MAX_DEPTH:
                at = self.peek_event()  # type: ignore[no-untyped-call]
                raise _too_much(f"nested deeper than {YAML_MAX_DEPTH} levels", at)
            return super().compose_node(parent, index)
        finally:
            self._depth -= 1

    def get_single_node(self) -> Any:
        node = super().get_single_node()
        if node is not None:
            _check_expanded(node)
        return node

    def construct_mapping(self, node: Any, deep: bool = False) -> Any:
        if isinstance(node, yaml.MappingNode):
            seen: set[Any] = set()
            for key_node, _ in node.value:
                if key_node.tag == "tag:yaml.org,2002:merge":
                    continue
                key = self.construct_object(key_node, deep=True)
                try:
                    duplicate = key in seen
                    seen.add(key)
                except TypeError:  # an unhashable key: PyYAML refuses it itself
                    continue
                if duplicate:
                    raise yaml.constructor.ConstructorError(
                        None, None, f"duplicate key {short_repr(key)}", key_node.start_mark
                    )
        return super().construct_mapping(node, deep=deep)


def _too_much(problem: str, at: Any) -> yaml.YAMLError:
    mark = getattr(at, "start_mark", None)
    return yaml.composer.ComposerError(None, None, problem, mark)


def _check_expanded(root: Any) -> None:
    """Refuse a node graph (aliases are shared nodes) that expands past the bounds or into a
    cycle; iterative, memoised per node, so an alias bomb costs its size, not its expansion."""
    size: dict[int, int] = {}
    depth: dict[int, int] = {}
    stack: list[tuple[Any, bool]] = [(root, False)]
    open_nodes: set[int] = set()
    while stack:
        node, done = stack.pop()
        key = id(node)
        children = _children(node)
        if done:
            open_nodes.discard(key)
            size[key] = 1 + sum(size[id(c)] for c in children)
            depth[key] = 1 + max((depth[id(c)] for c in children), default=0)
            if size[key] > YAML_MAX_VALUES:
                raise _too_much(
                    f"more than {YAML_MAX_VALUES:,} values with its aliases expanded", node
                )
            if depth[key] > YAML_MAX_DEPTH:
                raise _too_much(
                    f"nested deeper than {YAML_MAX_DEPTH} levels with its aliases expanded", node
                )
            continue
        if key in size:
            continue
        if key in open_nodes:
            raise _too_much("an alias refers to a value that holds it", node)
        open_nodes.add(key)
        stack.append((node, True))
        stack.extend((c, False) for c in children if id(c) not in size)


def _children(node: Any) -> list[Any]:
    if isinstance(node, yaml.SequenceNode):
        return list(node.value)
    if isinstance(node, yaml.MappingNode):
        return [n for pair in node.value for n in pair]
    return []


def _core_schema(loader: type[yaml.SafeLoader]) -> None:
    """Give ``loader`` YAML 1.2's core schema resolvers (in place of YAML 1.1's)."""
    loader.yaml_implicit_resolvers = {}
    rules = {
        "bool": (r"true|True|TRUE|false|False|FALSE", "tTfF"),
        "null": (r"~|null|Null|NULL|", ["~", "n", "N", ""]),
        "int": (r"[-+]?[0-9]+|0o[0-7]+|0x[0-9a-fA-F]+", "-+0123456789"),
        "float": (
            r"[-+]?(?:\.[0-9]+|[0-9]+(?:\.[0-9]*)?)(?:[eE][-+]?[0-9]+)?"
            r"|[-+]?\.(?:inf|Inf|INF)|\.(?:nan|NaN|NAN)",
            "-+.0123456789",
        ),
        "merge": (r"<<", "<"),
    }
    for name, (pattern, first) in rules.items():
        loader.add_implicit_resolver(
            f"tag:yaml.org,2002:{name}", re.compile(f"^(?:{pattern})$"), list(first)
        )
    loader.add_constructor("tag:yaml.org,2002:int", _construct_int)


def _construct_int(loader: yaml.SafeLoader, node: Any) -> int:
    text = str(loader.construct_scalar(node))
    sign = -1 if text.startswith("-") else 1
    digits = text.lstrip("+-")
    base = {"0o": 8, "0x": 16}.get(digits[:2], 10)
    try:
        return sign * int(digits[2:] if base != 10 else digits, base)
    except ValueError:  # past Python's 4300 digits
        raise yaml.constructor.ConstructorError(
            None, None, f"a whole number of {len(digits)} digits", node.start_mark
        ) from None


_core_schema(_Loader)


def read_yaml_extending(
    path: str | Path, named: Callable[[str], Path], inherit_not: tuple[str, ...] = ()
) -> Any:
    """The YAML document of ``path`` (:func:`read_yaml`) with its ``extends`` chain resolved.

    ``extends: REF`` names the base: a file when REF ends in ``.yaml`` or ``.yml`` (its path
    relative to this file), else the file ``named(REF)`` returns (it raises ValueError, with
    the message to show, for a name it does not know). The base's mapping is updated by this
    file's (:func:`merge_mappings`: mappings key by key, anything else replaced); ``extends``
    and the base's keys in ``inherit_not`` are dropped. A chain may be as long as needed.
    FileFormatError naming the file (this one or a base) that is missing, empty or not YAML;
    ConfigError naming the file whose ``extends`` is bad or closes a cycle."""
    return _extending(Path(path), named, inherit_not, ())


def _extending(
    path: Path, named: Callable[[str], Path], drop: tuple[str, ...], chain: tuple[Path, ...]
) -> Any:
    data = read_yaml(path)
    if not isinstance(data, dict) or "extends" not in data:
        return data
    data = dict(data)
    ref = data.pop("extends")
    if not isinstance(ref, str) or not ref:
        raise ConfigError(
            f"must be a name or a YAML file's path, got {short_repr(ref)}", "extends", path
        )
    here = path.resolve()
    if ref.endswith((".yaml", ".yml")):
        file = path.parent / ref
        if file.resolve() in (*chain, here):
            names = " -> ".join(str(p) for p in (*chain, here, file.resolve()))
            raise ConfigError(f"extends itself ({names})", "extends", path)
    else:
        try:
            file = named(ref)
        except ValueError as err:
            raise ConfigError(str(err), "extends", path) from None
    base = _extending(file, named, drop, (*chain, here))
    if not isinstance(base, dict):
        raise ConfigError(f"{ref} is not a mapping", "extends", path)
    base = {key: value for key, value in base.items() if key not in drop}
    merge_mappings(base, data)
    return base


def merge_mappings(base: dict[str, Any], extra: dict[str, Any]) -> None:
    """Update ``base`` in place by ``extra``: a mapping in both merged key by key (the same
    way down), anything else (a value, a list, null) replacing ``base``'s."""
    for key, value in extra.items():
        if isinstance(value, dict) and isinstance(base.get(key), dict):
            merge_mappings(base[key], value)
        else:
            base[key] = value


def yaml_value(text: str) -> Any:
    """``text`` read as one YAML 1.2 value (``0.05``, ``[1, 2]``, ``null``, ``rooms``), within
    the bounds of :func:`read_yaml`; ValueError when it is not YAML or over a bound."""
    if len(text) > YAML_MAX_BYTES:
        raise ValueError(f"larger than {YAML_MAX_BYTES // 2**20} MiB")
    try:
        return _load(text)
    except _YamlFault as err:
        raise ValueError(err.problem) from None


def read_yaml(path: str | Path) -> Any:
    """The YAML document of ``path`` (YAML 1.2's core schema, within :data:`YAML_MAX_BYTES`,
    :data:`YAML_MAX_DEPTH` and :data:`YAML_MAX_VALUES`); FileFormatError naming the file when
    it is missing, unreadable, too large, not YAML, over a bound, holds a key twice or is
    empty."""
    source = Path(path)
    try:
        with source.open("rb") as handle:
            raw = handle.read(YAML_MAX_BYTES + 1)
    except FileNotFoundError:
        raise FileFormatError(source, "no such file") from None
    except IsADirectoryError:
        raise FileFormatError(source, "is a directory, not a YAML file") from None
    except OSError as err:
        raise FileFormatError(source, f"cannot read ({err.strerror})") from None
    if len(raw) > YAML_MAX_BYTES:
        raise FileFormatError(source, f"larger than {YAML_MAX_BYTES // 2**20} MiB; not read")
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError:
        raise FileFormatError(source, "not UTF-8 text") from None
    try:
        data = _load(text)
    except _YamlFault as err:
        raise FileFormatError(source, f"not valid YAML{err.where} ({err.problem})") from None
    if data is None:
        raise FileFormatError(source, "empty file (no YAML document in it)")
    return data


class _YamlFault(ValueError):
    """Why a text is no YAML document :func:`_load` takes, and where (`` at line N`` or '')."""

    def __init__(self, where: str, problem: str) -> None:
        super().__init__(f"{where} ({problem})")
        self.where = where
        self.problem = problem


def _load(text: str) -> Any:
    """``text``'s YAML document (:class:`_Loader`); _YamlFault when it is none."""
    try:
        return yaml.load(text, Loader=_Loader)  # a SafeLoader subclass: no arbitrary objects
    except yaml.YAMLError as err:
        mark = getattr(err, "problem_mark", None)
        where = f" at line {mark.line + 1}" if mark is not None else ""
        raise _YamlFault(where, getattr(err, "problem", None) or one_line(err)) from None
    except RecursionError:  # the bounds come first; this only keeps it one line
        raise _YamlFault("", f"nested deeper than {YAML_MAX_DEPTH} levels") from None


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
    "short_repr",
    "to_plain",
    "validate",
    "yaml_value",
]
