"""The evolution wing: NEAT genomes and operators, and MENTOR's selection.

Genomes and their innovation numbers, networks (one and batched), mutation, crossover,
speciation, NSGA-II ranking, niche sizing and selection, reproduction, the evolution loop and
its configuration, reporters, and the genome <-> dict codec.

Knows nothing of robots: imports only ``mentor_core.errors``, ``mentor_core.atomic`` and its
own modules.
"""
