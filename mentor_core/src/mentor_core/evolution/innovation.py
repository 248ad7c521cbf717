"""Innovation record of a NEAT run: historical markings for connection genes and split nodes.

NEAT (Stanley & Miikkulainen 2002) gives every structural innovation a number so that
crossover can align genes by history. Here the number of a connection gene is a function of
its ``(in_node, out_node)`` pair for the whole run (a recurrent edge of the same pair is
another gene, with its own number), so two genomes that grow the same edge,
whenever they do so, carry the same gene. Splitting an edge gets a fresh node id, except that
the same edge split twice within one generation gets the same node id (and therefore the same
two new connection genes), as in the original NEAT.

The tracker is the one piece of mutable run state on the evolution side; it is checkpointed
through :meth:`InnovationTracker.to_state` / :meth:`InnovationTracker.from_state`.
"""

from __future__ import annotations

from collections.abc import Collection, Mapping
from typing import Any

from mentor_core.errors import FileFormatError, is_version

STATE_FORMAT = "mentor-innovation"
STATE_VERSION = 1


class InnovationTracker:
    """Run-wide map ``(in, out) -> innovation`` and per-generation split cache.

    ``next_node_id`` is the first id a hidden node may take: for a network with ``n_inputs``
    inputs and ``n_outputs`` outputs it is ``n_inputs + 1 + n_outputs`` (inputs, bias, outputs
    come first; see :mod:`mentor_core.evolution.genome`).
    """

    def __init__(self, next_node_id: int, next_innovation: int = 0) -> None:
        _check_count("next_node_id", next_node_id)
        _check_count("next_innovation", next_innovation)
        self._next_node_id = next_node_id
        self._next_innovation = next_innovation
        self._connections: dict[tuple[int, int], int] = {}
        self._recurrent: dict[tuple[int, int], int] = {}  # recurrent genes, their own numbers
        # split cache: connection innovation -> node id, forgotten every generation
        self._splits: dict[int, int] = {}

    @property
    def next_node_id(self) -> int:
        """The id the next fresh hidden node will get."""
        return self._next_node_id

    @property
    def next_innovation(self) -> int:
        """The innovation number the next new ``(in, out)`` pair will get."""
        return self._next_innovation

    def connection(self, in_node: int, out_node: int, recurrent: bool = False) -> int:
        """Innovation number of the edge ``in_node -> out_node`` (new pairs get the next one);
        a recurrent edge is another gene than the forward edge of the same pair."""
        table = self._recurrent if recurrent else self._connections
        key = (int(in_node), int(out_node))
        innovation = table.get(key)
        if innovation is None:
            innovation = self._next_innovation
            self._next_innovation += 1
            table[key] = innovation
        return innovation

    def split(self, connection_innovation: int, taken_nodes: Collection[int]) -> int:
        """Node id for splitting the connection ``connection_innovation``.

        Within one generation the same connection split in several genomes yields the same
        node id; if that id is already in ``taken_nodes`` (the splitting genome has it) a fresh
        id is returned instead and the cache keeps the first one for the other genomes.
        """
        node = self._splits.get(connection_innovation)
        if node is not None and node not in taken_nodes:
            return node
        node = self._fresh_node(taken_nodes)
        self._splits.setdefault(connection_innovation, node)
        return node

    def new_generation(self) -> None:
        """Forget the per-generation split cache (the connection map is kept for the run)."""
        self._splits.clear()

    def to_state(self) -> dict[str, Any]:
        """JSON-serialisable state; :meth:`from_state` rebuilds an equal tracker."""
        state: dict[str, Any] = {
            "format": STATE_FORMAT,
            "version": STATE_VERSION,
            "next_node_id": self._next_node_id,
            "next_innovation": self._next_innovation,
            "connections": [[i, o, n] for (i, o), n in sorted(self._connections.items())],
            "splits": [[c, n] for c, n in sorted(self._splits.items())],
        }
        if self._recurrent:  # absent for feed-forward runs: their checkpoints stay as they were
            state["recurrent"] = [[i, o, n] for (i, o), n in sorted(self._recurrent.items())]
        return state

    @classmethod
    def from_state(cls, d: Mapping[str, Any], source: str = "<state>") -> InnovationTracker:
        """Tracker from :meth:`to_state`'s dict; ``FileFormatError(source, fault)`` if bad."""
        if not isinstance(d, Mapping):
            raise FileFormatError(source, "innovation state is not a mapping")
        if d.get("format") != STATE_FORMAT or not is_version(d.get("version"), STATE_VERSION):
            raise FileFormatError(
                source,
                f"innovation state format/version {d.get('format')!r}/{d.get('version')!r} "
                f"is not {STATE_FORMAT!r}/{STATE_VERSION}",
            )
        try:
            tracker = cls(_int(d["next_node_id"]), _int(d["next_innovation"]))
            for row in d["connections"]:
                i, o, n = (_int(v) for v in row)
                tracker._connections[(i, o)] = n
            for row in d.get("recurrent", ()):
                i, o, n = (_int(v) for v in row)
                tracker._recurrent[(i, o)] = n
            for row in d["splits"]:
                c, n = (_int(v) for v in row)
                tracker._splits[c] = n
        except (KeyError, TypeError, ValueError) as err:
            raise FileFormatError(source, f"bad innovation state: {err!r}") from None
        numbers = [*tracker._connections.values(), *tracker._recurrent.values()]
        too_big = any(n >= tracker._next_innovation for n in numbers)
        if len(set(numbers)) != len(numbers) or too_big:
            raise FileFormatError(source, "innovation numbers repeat or reach next_innovation")
        if any(n >= tracker._next_node_id for n in tracker._splits.values()):
            raise FileFormatError(source, "a split node id reaches next_node_id")
        return tracker

    def _fresh_node(self, taken_nodes: Collection[int]) -> int:
        # ids handed out are never reused, but skip any the caller already holds
        while self._next_node_id in taken_nodes:
            self._next_node_id += 1
        node = self._next_node_id
        self._next_node_id += 1
        return node


def _check_count(name: str, value: int) -> None:
    if isinstance(value, bool) or not isinstance(value, int) or value < 0:
        raise ValueError(f"{name} must be a non-negative int, got {value!r}")


def _int(value: Any) -> int:
    if isinstance(value, bool) or not isinstance(value, int):
        raise TypeError(f"expected an int, got {value!r}")
    return value
