"""Speciation: compatibility distance (paper eq. 1) and assignment to species.

Each species is a niche kept by one representative genome. A genome joins the species whose
representative lies nearest, if it lies within the distance threshold (``assignment:
nearest``, as neat-python), or the first species by id within the threshold (``assignment:
first``, as Stanley & Miikkulainen 2002); otherwise it founds a new one. First-match lets the
oldest species absorb everything within reach: in paper-scale runs one species then held up
to 98 % of the population in single generations, against the paper's "no niche above about
a third".

A species lives while it has members, so a rising threshold (:func:`adjust_threshold`) only
stops new species forming: the count cannot fall back to ``target_species`` once the
population has split (experiment E088). With ``merge``, each generation first merges the
species whose representatives lie within the threshold of an older species' representative,
so the count follows the target both ways.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Annotated, Literal, get_args

import numpy as np
from numpy.typing import NDArray
from pydantic import Field, model_validator

from mentor_core.errors import ConfigError
from mentor_core.evolution.genome import Genome
from mentor_core.validation import Float, Int, config_dataclass, fault

Assignment = Literal["nearest", "first"]
ASSIGNMENTS: tuple[str, ...] = get_args(Assignment)
_Coefficient = Annotated[Float, Field(ge=0.0)]
_Threshold = Annotated[Float, Field(gt=0.0)]


@config_dataclass
class SpeciationConfig:
    """Distance coefficients (paper: [c1, c2, c3] = [1, 1, 0.4]) and threshold control.

    ``threshold`` is the starting compatibility threshold; with ``target_species`` set,
    :func:`adjust_threshold` moves it by ``threshold_step`` per generation towards that many
    species, never below ``threshold_min``. ``assignment`` picks the species a genome joins
    (module docstring): ``"nearest"`` or ``"first"``. ``merge`` merges the species whose
    representatives lie within the threshold of an older one's before genomes are assigned
    (module docstring; off: species only split, as in NEAT).
    """

    c1: _Coefficient = 1.0
    c2: _Coefficient = 1.0
    c3: _Coefficient = 0.4
    threshold: _Threshold = 3.0
    target_species: Annotated[Int, Field(ge=1)] | None = None
    threshold_step: _Coefficient = 0.3
    threshold_min: _Threshold = 0.3
    assignment: Assignment = "nearest"
    merge: bool = False

    @model_validator(mode="after")
    def _threshold_above_its_floor(self) -> SpeciationConfig:
        if self.threshold < self.threshold_min:
            raise fault(
                "threshold", f"{self.threshold} is below threshold_min {self.threshold_min}"
            )
        return self


def distance(a: Genome, b: Genome, c1: float = 1.0, c2: float = 1.0, c3: float = 0.4) -> float:
    """Compatibility distance, paper eq. 1 (the paper's second ``c1`` is a typo for ``c2``).

    ``D = c1 E / N + c2 J / N + c3 W``: ``E`` excess genes (innovation beyond the other
    genome's largest), ``J`` disjoint genes (the other unmatched genes), ``N`` the gene count of
    the larger genome (at least 1), ``W`` the mean absolute weight difference of matching genes
    (0 if none): NEAT's W-bar, the paper's symbol; its text says "summation", which would make
    the distance grow with the genome's size (docs/algorithm.md, Distance). Disabled genes count
    like enabled ones.
    """
    return _gene_distance(_genes(a), _genes(b), c1, c2, c3)


#: a genome's connection genes as (innovation numbers, weights), in gene order
_Genes = tuple[NDArray[np.int64], NDArray[np.float64]]


def _genes(genome: Genome) -> _Genes:
    inn = np.fromiter((c.innovation for c in genome.connections), dtype=np.int64)
    weights = np.fromiter((c.weight for c in genome.connections), dtype=np.float64)
    return inn, weights


def _gene_distance(a: _Genes, b: _Genes, c1: float, c2: float, c3: float) -> float:
    """:func:`distance` of two genomes' :func:`_genes`."""
    (inn_a, w_a), (inn_b, w_b) = a, b
    _, ia, ib = np.intersect1d(inn_a, inn_b, assume_unique=True, return_indices=True)
    max_a = int(inn_a.max()) if inn_a.size else -1
    max_b = int(inn_b.max()) if inn_b.size else -1
    # the unmatched genes: the matched ones' places deleted (setdiff1d's result, cheaper)
    lone_a = np.delete(inn_a, ia)
    lone_b = np.delete(inn_b, ib)
    excess = int(np.count_nonzero(lone_a > max_b) + np.count_nonzero(lone_b > max_a))
    disjoint = lone_a.size + lone_b.size - excess
    n = max(inn_a.size, inn_b.size, 1)
    w_bar = float(np.mean(np.abs(w_a[ia] - w_b[ib]))) if ia.size else 0.0
    return c1 * excess / n + c2 * disjoint / n + c3 * w_bar


def speciate(
    genomes: Sequence[Genome],
    representatives: Mapping[int, Genome],
    threshold: float,
    cfg: SpeciationConfig,
    next_id: int,
) -> tuple[NDArray[np.int64], dict[int, Genome], int]:
    """Assign each genome (in order) a species id.

    A genome joins the species whose representative is nearest (``cfg.assignment ==
    "nearest"``; lowest id on ties) or the first by ascending id (``"first"``), provided the
    distance is ``< threshold``; otherwise it founds species ``next_id`` as its representative
    (later genomes may join it). The new
    representative of each species with members is the member closest to its old
    representative (first such member on ties). Species without members are dropped. With
    ``cfg.merge``, a representative within ``threshold`` of an older (lower id) kept one is
    dropped first, and its species' genomes join whichever species they now lie nearest.
    Returns ``(labels, representatives, next_id)``.
    """
    if not (np.isfinite(threshold) and threshold > 0.0):
        raise ConfigError(f"must be finite and > 0, got {threshold!r}", key="threshold")
    if representatives and next_id <= max(representatives):
        raise ConfigError(
            f"{next_id} is not above the existing species ids {sorted(representatives)}",
            key="next_id",
        )
    # each representative's genes once, not once per genome compared with it
    reps = {sid: _genes(rep) for sid, rep in sorted(representatives.items())}
    if cfg.merge:
        reps = _merged(reps, threshold, cfg)
    labels = np.empty(len(genomes), dtype=np.int64)
    best: dict[int, tuple[float, int]] = {}  # species -> (distance to old rep, genome index)
    for k, genome in enumerate(genomes):
        genes = _genes(genome)
        species_id, gap = _closest(genes, reps, threshold, cfg)
        if species_id < 0:
            species_id, gap = next_id, 0.0
            reps[species_id] = genes
            next_id += 1
        labels[k] = species_id
        if species_id not in best or gap < best[species_id][0]:
            best[species_id] = (gap, k)
    new_reps = {sid: genomes[best[sid][1]] for sid in sorted(best)}
    return labels, new_reps, next_id


def _merged(reps: Mapping[int, _Genes], threshold: float, cfg: SpeciationConfig) -> dict[
        int, _Genes]:  # fmt: skip
    """``reps`` (ascending id) without each one that lies within ``threshold`` of an older
    one kept."""
    kept: dict[int, _Genes] = {}
    for sid, genes in reps.items():
        if all(_gene_distance(genes, k, cfg.c1, cfg.c2, cfg.c3) >= threshold
               for k in kept.values()):  # fmt: skip
            kept[sid] = genes
    return kept


def _closest(
    genes: _Genes, reps: Mapping[int, _Genes], threshold: float, cfg: SpeciationConfig
) -> tuple[int, float]:
    """(species id, distance) a genome of ``genes`` joins under ``cfg.assignment``; (-1, 0)
    for none."""
    found, found_gap = -1, 0.0
    for sid, rep in reps.items():  # ascending id
        gap = _gene_distance(genes, rep, cfg.c1, cfg.c2, cfg.c3)
        if gap < threshold and (found < 0 or gap < found_gap):
            found, found_gap = sid, gap
            if cfg.assignment == "first":
                break
    return found, found_gap


def adjust_threshold(threshold: float, n_species: int, cfg: SpeciationConfig) -> float:
    """Threshold for the next generation: raised when there are more species than
    ``cfg.target_species`` (coarser niches), lowered (to at least ``threshold_min``) when there
    are fewer, unchanged when on target or when no target is set.
    """
    if cfg.target_species is None or n_species == cfg.target_species:
        return threshold
    if n_species > cfg.target_species:
        return threshold + cfg.threshold_step
    return max(cfg.threshold_min, threshold - cfg.threshold_step)
