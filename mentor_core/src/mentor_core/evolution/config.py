"""Evolution configuration: one frozen dataclass, validated, loaded from YAML or a dict.

Like neat-python's ``config.py``, a configuration rejects unknown keys (a typo fails loudly with
a :class:`~mentor_core.errors.ConfigError` naming the key and the file) and a saved
configuration reloads to equal values (``EvolutionConfig.from_dict(c.to_dict()) == c``).
Run state (innovation tracker, the adjusted compatibility threshold, the generator) never lives
here; it is in :class:`~mentor_core.evolution.loop.Evolution`.

:meth:`EvolutionConfig.paper` gives the paper's Table I ("Neuro-evolution Parameters") for the
UGV and the Swarm-Robot cases; ``configs/ugv_paper.yaml`` and ``configs/swarm_paper.yaml`` hold
the same values, ``configs/xor.yaml`` the XOR benchmark's.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Any, Literal

import yaml

from mentor_core.errors import ConfigError, FileFormatError, is_number
from mentor_core.evolution.mutation import MutationConfig
from mentor_core.evolution.network import ACTIVATIONS
from mentor_core.evolution.species import SpeciationConfig

Robot = Literal["ugv", "swarm"]

#: Table I of the paper: node addition per edge, edge addition per hidden or output node (one
#: new in-edge; the paper: per node pair, see ``mutation``), weight mutation per edge.
PAPER_TABLE_I: Mapping[str, Mapping[str, float]] = {
    "ugv": {"node_add": 0.05, "edge_add": 0.03, "weight": 0.25},
    "swarm": {"node_add": 0.08, "edge_add": 0.5, "weight": 0.25},
}


def _is_int(value: object) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)


def _coerce(value: Any, default: Any, key: str, path: str | None) -> Any:
    """Check ``value`` against the type of a field's ``default``; ints are accepted as floats."""
    if isinstance(default, bool):
        if not isinstance(value, bool):
            raise ConfigError(f"expected true/false, got {value!r}", key=key, path=path)
        return value
    if isinstance(default, int):
        if not _is_int(value):
            raise ConfigError(f"expected an integer, got {value!r}", key=key, path=path)
        return value
    if isinstance(default, float):
        if not is_number(value):
            raise ConfigError(f"expected a number, got {value!r}", key=key, path=path)
        if not math.isfinite(float(value)):
            raise ConfigError(f"expected a finite number, got {value!r}", key=key, path=path)
        return float(value)
    if isinstance(default, str):
        if not isinstance(value, str):
            raise ConfigError(f"expected a string, got {value!r}", key=key, path=path)
        return value
    if isinstance(default, tuple):
        if not isinstance(value, list | tuple):
            raise ConfigError(f"expected a list, got {value!r}", key=key, path=path)
        return tuple(value)
    if default is None:  # optional field: accept a number, an integer or null
        if value is not None and not is_number(value):
            raise ConfigError(f"expected a number or null, got {value!r}", key=key, path=path)
        return value
    return value


def _field_defaults(cls: type) -> dict[str, Any]:
    defaults: dict[str, Any] = {}
    for f in dataclasses.fields(cls):
        if f.default is not dataclasses.MISSING:
            defaults[f.name] = f.default
        elif f.default_factory is not dataclasses.MISSING:
            defaults[f.name] = f.default_factory()
        else:
            defaults[f.name] = dataclasses.MISSING
    return defaults


def _section_from_dict(cls: type, d: object, section: str, path: str | None) -> Any:
    """Build the nested dataclass ``cls`` (MutationConfig, SpeciationConfig) from a mapping."""
    if not isinstance(d, Mapping):
        raise ConfigError(f"expected a mapping, got {d!r}", key=section, path=path)
    defaults = _field_defaults(cls)
    kwargs: dict[str, Any] = {}
    for key, value in d.items():
        name = f"{section}.{key}"
        if key not in defaults:
            raise ConfigError(
                f"unknown key (known: {', '.join(sorted(defaults))})", key=name, path=path
            )
        default = defaults[key]
        kwargs[key] = value if default is dataclasses.MISSING else _coerce(
            value, default, name, path
        )
    try:
        return cls(**kwargs)
    except ConfigError as err:  # the section's own validation: name the nested key
        if err.key is None:
            raise ConfigError(str(err), key=section, path=path) from None
        message = str(err).removeprefix(f"{err.key}: ")
        raise ConfigError(message, key=f"{section}.{err.key}", path=path) from None
    except (TypeError, ValueError) as err:
        raise ConfigError(str(err), key=section, path=path) from None


def _section_to_dict(obj: Any) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for f in dataclasses.fields(obj):
        value = getattr(obj, f.name)
        out[f.name] = list(value) if isinstance(value, tuple) else value
    return out


@dataclass(frozen=True)
class EvolutionConfig:
    """Parameters of one MENTOR evolution run (defaults: the paper's Table I, UGV case).

    population_size: genomes per generation (N).
    generations: number of generations of a run.
    elitism: share of N passed unchanged (``round(elitism * N)``, at least 1 when > 0).
    crossover_rate: probability that a child is bred by crossover rather than copied.
    tournament_size: genomes per tournament in intra-species selection.
    global_fraction: share of N bred from the species champions (global reproduction).
    hidden_activation / output_activation: names in ``network.ACTIVATIONS``.
    initial_weight_sigma: standard deviation of the initial connection weights.
    mutation / speciation: the operators' own configurations.
    """

    population_size: int = 100
    generations: int = 50
    elitism: float = 0.02
    crossover_rate: float = 0.85
    tournament_size: int = 2
    global_fraction: float = 0.1
    hidden_activation: str = "sigmoid"
    output_activation: str = "sigmoid"
    initial_weight_sigma: float = 1.0
    mutation: MutationConfig = field(default_factory=MutationConfig)
    speciation: SpeciationConfig = field(default_factory=SpeciationConfig)

    def __post_init__(self) -> None:
        _validate({f.name: getattr(self, f.name) for f in dataclasses.fields(self)}, None)

    # ------------------------------------------------------------------ constructors
    @classmethod
    def paper(cls, robot: Robot) -> EvolutionConfig:
        """The paper's Table I for ``robot`` ("ugv" or "swarm"); other keys keep defaults."""
        if robot not in PAPER_TABLE_I:
            raise ConfigError(f"unknown robot {robot!r} (known: ugv, swarm)", key="robot")
        table = PAPER_TABLE_I[robot]
        mutation = dataclasses.replace(
            MutationConfig(),
            weight_rate=table["weight"],
            node_rate=table["node_add"],
            edge_rate=table["edge_add"],
        )
        return cls(
            population_size=100,
            generations=50,
            elitism=0.02,
            crossover_rate=0.85,
            mutation=mutation,
        )

    @classmethod
    def from_dict(cls, d: Mapping[str, Any], source: str | Path = "<dict>") -> EvolutionConfig:
        """Build from a mapping (e.g. parsed YAML); unknown keys and bad values raise
        :class:`ConfigError` naming the key and ``source``. Missing keys keep their defaults."""
        path = str(source)
        if not isinstance(d, Mapping):
            raise ConfigError(f"expected a mapping at the top level, got {d!r}", path=path)
        defaults = _field_defaults(cls)
        kwargs: dict[str, Any] = {}
        for key, value in d.items():
            if not isinstance(key, str) or key not in defaults:
                raise ConfigError(
                    f"unknown key (known: {', '.join(sorted(defaults))})", key=str(key), path=path
                )
            if key == "mutation":
                kwargs[key] = _section_from_dict(MutationConfig, value, key, path)
            elif key == "speciation":
                kwargs[key] = _section_from_dict(SpeciationConfig, value, key, path)
            else:
                kwargs[key] = _coerce(value, defaults[key], key, path)
        _validate({**defaults, **kwargs}, path)  # errors name the file
        return cls(**kwargs)

    @classmethod
    def from_yaml(cls, path: str | Path) -> EvolutionConfig:
        """Load a YAML file; a missing file or bad YAML raises :class:`FileFormatError`."""
        try:
            text = Path(path).read_text(encoding="utf-8")
        except FileNotFoundError:
            raise FileFormatError(path, "no such file") from None
        except OSError as err:
            raise FileFormatError(path, f"cannot read: {err.strerror}") from None
        try:
            data = yaml.safe_load(text)
        except yaml.YAMLError as err:
            mark = getattr(err, "problem_mark", None)
            where = f" at line {mark.line + 1}" if mark is not None else ""
            raise FileFormatError(path, f"invalid YAML{where}") from None
        if data is None:
            data = {}
        return cls.from_dict(data, source=path)

    @classmethod
    def packaged(cls, name: str) -> EvolutionConfig:
        """Load a configuration shipped in ``mentor_core/configs`` (``"xor"``, ``"ugv_paper"``,
        ``"swarm_paper"``)."""
        ref = resources.files("mentor_core").joinpath("configs", f"{name}.yaml")
        with resources.as_file(ref) as file:
            return cls.from_yaml(file)

    # ------------------------------------------------------------------ output
    def to_dict(self) -> dict[str, Any]:
        """Plain dict (YAML/JSON-serialisable); ``from_dict(to_dict())`` gives an equal config."""
        out: dict[str, Any] = {}
        for f in dataclasses.fields(self):
            value = getattr(self, f.name)
            out[f.name] = (
                _section_to_dict(value) if dataclasses.is_dataclass(value) else value
            )
        return out

    def to_yaml(self) -> str:
        """YAML text that :meth:`from_yaml` reads back to an equal config."""
        return str(yaml.safe_dump(self.to_dict(), sort_keys=False))


class _Values:
    """Attribute access to a mapping of field values (so one validator serves both paths)."""

    def __init__(self, values: Mapping[str, Any]) -> None:
        self._values = values

    def __getattr__(self, name: str) -> Any:
        return self._values[name]


def _validate(values: Mapping[str, Any], path: str | None) -> None:
    """Raise :class:`ConfigError` (with ``path``) for the first invalid field value."""
    c = _Values(values)

    def need(ok: bool, key: str, message: str) -> None:
        if not ok:
            raise ConfigError(message, key=key, path=path)

    need(_is_int(c.population_size), "population_size", "expected an integer")
    need(c.population_size >= 2, "population_size", "must be at least 2")
    need(_is_int(c.generations), "generations", "expected an integer")
    need(c.generations >= 1, "generations", "must be at least 1")
    for key in ("elitism", "crossover_rate", "global_fraction", "initial_weight_sigma"):
        value = getattr(c, key)
        need(is_number(value) and math.isfinite(value), key, f"expected a number, got {value!r}")
    need(0.0 <= c.elitism < 1.0, "elitism", "must be in [0, 1)")
    need(0.0 <= c.crossover_rate <= 1.0, "crossover_rate", "must be in [0, 1]")
    need(0.0 <= c.global_fraction < 1.0, "global_fraction", "must be in [0, 1)")
    need(c.initial_weight_sigma > 0.0, "initial_weight_sigma", "must be positive")
    need(_is_int(c.tournament_size), "tournament_size", "expected an integer")
    need(c.tournament_size >= 1, "tournament_size", "must be at least 1")
    for key in ("hidden_activation", "output_activation"):
        value = getattr(c, key)
        need(
            isinstance(value, str) and value in ACTIVATIONS,
            key,
            f"unknown activation {value!r} (known: {', '.join(sorted(ACTIVATIONS))})",
        )
    need(isinstance(c.mutation, MutationConfig), "mutation", "expected a MutationConfig")
    need(isinstance(c.speciation, SpeciationConfig), "speciation", "expected a SpeciationConfig")
    n = c.population_size
    n_elite = max(1, round(c.elitism * n)) if c.elitism > 0 else 0
    n_global = round(c.global_fraction * n)
    need(
        n_elite + n_global < n,
        "global_fraction",
        f"elites ({n_elite}) and global offspring ({n_global}) leave no room for the niches "
        f"in a population of {n}",
    )
