"""The memory a training run asks for, checked against the machine's before the run starts.

A population of ``N`` genomes evaluated on ``S`` scenarios holds about ``N (g + s S)`` bytes
beyond the problem itself: ``g`` per genome (its genes, its ranking, its share of the
checkpoint's text) and ``s`` per genome and scenario (the batched episode's trajectories and
readings). Peak resident memory of ``mentor-train --robot ugv --framework dual --config
quick --set generations=2 --set stage1_generations=1 --set refinement.iterations=0`` on
2026-12-05 (experiment E085): 234 MB at N = 200, S = 10; 279 MB at N = 800, S = 10; 433 MB at
N = 800, S = 40; so ``g`` is about 11 kB and ``s`` about 6.4 kB. The bound doubles both, for
margin and for networks grown over a run, and refuses a run whose share would pass the
machine's physical memory: ``population_size: 1e8`` is one line before any work, not a swap
storm.
"""

from __future__ import annotations

import os

from mentor_core.errors import ConfigError

#: bytes per genome beyond its scenarios (twice the measured 11 kB)
GENOME_BYTES = 22_000
#: bytes per genome and scenario (twice the measured 6.4 kB)
SCENARIO_BYTES = 13_000


def run_bytes(population: int, scenarios: int) -> int:
    """The bytes a population of ``population`` genomes on ``scenarios`` scenarios asks for,
    ``N (g + s S)`` (module docstring)."""
    return population * (GENOME_BYTES + SCENARIO_BYTES * scenarios)


def machine_bytes() -> int | None:
    """The machine's physical memory in bytes (None where the system does not say)."""
    try:
        return os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError, AttributeError):
        return None


def check_memory(
    population: int, scenarios: int, source: str, available: int | None = None
) -> None:
    """ConfigError naming ``source`` and ``evolution.population_size`` when :func:`run_bytes`
    passes ``available`` bytes (default: :func:`machine_bytes`; no check when unknown)."""
    limit = machine_bytes() if available is None else available
    if limit is None:
        return
    need = run_bytes(population, scenarios)
    if need > limit:
        most = limit // (GENOME_BYTES + SCENARIO_BYTES * scenarios)
        raise ConfigError(
            f"{population} genomes on {scenarios} scenarios need about {need / 2**30:.1f} GiB, "
            f"more than this machine's {limit / 2**30:.1f} GiB (at most {most} genomes here)",
            key="evolution.population_size",
            path=source,
        )


__all__ = ["GENOME_BYTES", "SCENARIO_BYTES", "check_memory", "machine_bytes", "run_bytes"]
