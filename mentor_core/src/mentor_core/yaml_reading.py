"""Reading YAML: every YAML file of the library (configs, robot, world and map files, a bag's
``metadata.yaml``) and every ``--set`` value, with YAML 1.2's core schema, within bounds.

:func:`read_yaml` refuses, with one FileFormatError line naming the file, a missing,
unreadable, empty or too large file, a document that is no YAML, holds a key twice, nests too
deep or expands past :data:`YAML_MAX_VALUES` values through its aliases (``docs/files.md``).
:func:`read_yaml_extending` resolves a config's ``extends`` chain.

Foundation level: imports only ``mentor_core.errors`` (and yaml).
"""

from __future__ import annotations

import copy
import re
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any

import yaml

from mentor_core.errors import ConfigError, FileFormatError, one_line, short_repr

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
    stack: list[tuple[Any, list[Any] | None]] = [(root, None)]  # (node, its children once open)
    open_nodes: set[int] = set()
    while stack:
        node, children = stack.pop()
        key = id(node)
        if children is not None:
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
        children = _children(node)
        stack.append((node, children))
        stack.extend((c, None) for c in children if id(c) not in size)


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


def with_settings(
    data: dict[str, Any], settings: Sequence[str], source: str = "--set",
    own_options: Mapping[str, str] | None = None,
) -> dict[str, Any]:
    """A copy of ``data`` (a config's mapping) with each ``KEY=VALUE`` of ``settings`` set in
    turn: ``KEY`` a dotted key path (``n_scenarios``, ``evolution.mutation.recurrent_rate``),
    ``VALUE`` read as YAML 1.2 (``40``, ``0.05``, ``[1, 2]``, ``null``); mappings on the way
    are created where missing (an unknown key is then the validation's fault). ConfigError
    naming ``source`` for a setting without ``=`` or a key, a value that is not YAML, or a
    key that ``own_options`` (key -> option) says a command line sets otherwise."""
    out = copy.deepcopy(data)
    for item in settings:
        key, eq, text = item.partition("=")
        path = key.strip().split(".")
        if not eq or not all(path):
            raise ConfigError(f"expected KEY=VALUE (a dotted key path), got {item!r}", None,
                              source)  # fmt: skip
        if own_options and path[0] in own_options:
            raise ConfigError(f"set with {own_options[path[0]]}, not {source}", key, source)
        try:
            value = yaml_value(text)
        except ValueError as err:
            raise ConfigError(f"{text!r} is not a YAML value ({err})", key, source) from None
        node = out
        for name in path[:-1]:
            if not isinstance(node.get(name), dict):
                node[name] = {}
            node = node[name]
        node[path[-1]] = value
    return out


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
    "YAML_MAX_BYTES",
    "YAML_MAX_DEPTH",
    "YAML_MAX_VALUES",
    "merge_mappings",
    "read_yaml",
    "read_yaml_extending",
    "with_settings",
    "yaml_value",
]
