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
from collections.abc import Mapping
from dataclasses import field
from importlib import resources
from pathlib import Path
from typing import Annotated, Any, Literal

import yaml
from pydantic import Field, field_validator, model_validator

from mentor_core.errors import ConfigError
from mentor_core.evolution.mutation import MutationConfig
from mentor_core.evolution.network import ACTIVATIONS
from mentor_core.evolution.species import SpeciationConfig
from mentor_core.validation import (
    Float,
    Int,
    Str,
    config_dataclass,
    fault,
    read_yaml,
    to_plain,
    validate,
)

Robot = Literal["ugv", "swarm"]

#: Table I of the paper: node addition per edge, edge addition per hidden or output node (one
#: new in-edge; the paper: per node pair, see ``mutation``), weight mutation per edge.
PAPER_TABLE_I: Mapping[str, Mapping[str, float]] = {
    "ugv": {"node_add": 0.05, "edge_add": 0.03, "weight": 0.25},
    "swarm": {"node_add": 0.08, "edge_add": 0.5, "weight": 0.25},
}


@config_dataclass
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

    population_size: Annotated[Int, Field(ge=2)] = 100
    generations: Annotated[Int, Field(ge=1)] = 50
    elitism: Annotated[Float, Field(ge=0.0, lt=1.0)] = 0.02
    crossover_rate: Annotated[Float, Field(ge=0.0, le=1.0)] = 0.85
    tournament_size: Annotated[Int, Field(ge=1)] = 2
    global_fraction: Annotated[Float, Field(ge=0.0, lt=1.0)] = 0.1
    hidden_activation: Str = "sigmoid"
    output_activation: Str = "sigmoid"
    initial_weight_sigma: Annotated[Float, Field(gt=0.0)] = 1.0
    mutation: MutationConfig = field(default_factory=MutationConfig)
    speciation: SpeciationConfig = field(default_factory=SpeciationConfig)

    @field_validator("hidden_activation", "output_activation")
    @classmethod
    def _known_activation(cls, value: str) -> str:
        if value not in ACTIVATIONS:
            known = ", ".join(sorted(ACTIVATIONS))
            raise ValueError(f"unknown activation {value!r} (known: {known})")
        return value

    @model_validator(mode="after")
    def _room_for_the_niches(self) -> EvolutionConfig:
        n = self.population_size
        n_elite = max(1, round(self.elitism * n)) if self.elitism > 0 else 0
        n_global = round(self.global_fraction * n)
        if n_elite + n_global >= n:
            raise fault(
                "global_fraction",
                f"elites ({n_elite}) and global offspring ({n_global}) leave no room for the "
                f"niches in a population of {n}",
            )
        return self

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
        return validate(cls, d, source)

    @classmethod
    def from_yaml(cls, path: str | Path) -> EvolutionConfig:
        """Load a YAML file; a missing, empty or non-YAML file raises
        :class:`~mentor_core.errors.FileFormatError`."""
        return cls.from_dict(read_yaml(path), source=path)

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
        plain: dict[str, Any] = to_plain(self)
        return plain

    def to_yaml(self) -> str:
        """YAML text that :meth:`from_yaml` reads back to an equal config."""
        return str(yaml.safe_dump(self.to_dict(), sort_keys=False))
