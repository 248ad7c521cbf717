"""Speciation: compatibility distance (paper eq. 1), assignment by representative and
threshold, and threshold steering towards a target species count."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from mentor_core.errors import ConfigError
from mentor_core.evolution.genome import Genome, genome_from_edges, minimal_genome, validate_genome
from mentor_core.evolution.innovation import InnovationTracker
from mentor_core.evolution.mutation import MutationConfig, mutate
from mentor_core.evolution.species import SpeciationConfig, adjust_threshold, distance, speciate

# 2 inputs (0, 1), bias 2, outputs 3, 4: innovation k is the k-th of these edges
PAIRS = [(0, 3), (1, 3), (2, 3), (0, 4), (1, 4), (2, 4)]


def genome(weights: dict[int, float], disabled: frozenset[int] = frozenset()) -> Genome:
    """A genome holding exactly the innovations in ``weights`` (numbered as in PAIRS)."""
    base = genome_from_edges(2, 2, [])
    conns = [
        dataclasses.replace(
            genome_from_edges(2, 2, [(*PAIRS[k], w)]).connections[0],
            innovation=k,
            enabled=k not in disabled,
        )
        for k, w in weights.items()
    ]
    g = base.with_connections(conns)
    validate_genome(g)
    return g


# a: innovations {0, 1, 2, 4, 5}, b: {0, 1, 3}
A = genome({0: 1.0, 1: -0.5, 2: 3.0, 4: 0.1, 5: 7.0})
B = genome({0: 0.5, 1: 0.5, 3: -2.0})


def test_distance_on_hand_built_pair() -> None:
    """E = 2 (4, 5 beyond b's max 3), J = 2 (2 and 3), N = 5, W = (0.5 + 1.0) / 2."""
    assert distance(A, B) == pytest.approx(1.0 * 2 / 5 + 1.0 * 2 / 5 + 0.4 * 0.75, abs=1e-12)
    assert distance(A, B, 2.0, 3.0, 1.0) == pytest.approx(0.8 + 1.2 + 0.75, abs=1e-12)
    assert distance(A, B, 1.0, 0.0, 0.0) == pytest.approx(2 / 5)  # excess alone
    assert distance(A, B, 0.0, 1.0, 0.0) == pytest.approx(2 / 5)  # disjoint alone
    assert distance(A, B, 0.0, 0.0, 1.0) == pytest.approx(0.75)  # weights alone


def test_excess_and_disjoint_are_told_apart() -> None:
    # a: {0, 5}, b: {0, 1, 2}: 5 is excess (beyond 2), 1 and 2 are disjoint (below 5)
    a = genome({0: 1.0, 5: 1.0})
    b = genome({0: 1.0, 1: 1.0, 2: 1.0})
    assert distance(a, b, 1.0, 0.0, 0.0) == pytest.approx(1 / 3)
    assert distance(a, b, 0.0, 1.0, 0.0) == pytest.approx(2 / 3)


def test_distance_symmetric_zero_with_itself_and_counts_disabled_genes() -> None:
    assert distance(A, B) == distance(B, A)
    assert distance(A, A) == 0.0 and distance(B, B) == 0.0
    a_off = genome({0: 1.0, 1: -0.5, 2: 3.0, 4: 0.1, 5: 7.0}, disabled=frozenset({0, 4}))
    assert distance(a_off, B) == distance(A, B)
    assert distance(a_off, A) == 0.0


def test_distance_of_empty_genomes() -> None:
    empty = genome({})
    assert distance(empty, empty) == 0.0
    assert distance(empty, B) == pytest.approx(1.0)  # all three genes excess, N = 3
    assert distance(B, empty) == pytest.approx(1.0)


def test_speciation_by_representative_and_threshold() -> None:
    near_a = genome({0: 1.1, 1: -0.5, 2: 3.0, 4: 0.1, 5: 7.0})  # W-only gap 0.4 * 0.02
    near_b = genome({0: 0.5, 1: 0.6, 3: -2.0})
    cfg = SpeciationConfig()
    labels, reps, next_id = speciate([A, B, near_a, near_b], {}, 1.0, cfg, next_id=7)
    assert labels.tolist() == [7, 8, 7, 8]
    assert next_id == 9
    assert reps == {7: A, 8: B}  # founders are at distance 0 from themselves
    # a tiny threshold splits every distinct genome into its own species
    labels, reps, next_id = speciate([A, B, near_a, near_b], {}, 1e-6, cfg, next_id=0)
    assert labels.tolist() == [0, 1, 2, 3] and next_id == 4 and len(reps) == 4
    # a huge one lumps them together
    labels, _, _ = speciate([A, B, near_a, near_b], {}, 100.0, cfg, next_id=0)
    assert labels.tolist() == [0, 0, 0, 0]


def test_joins_the_closest_species_within_threshold_or_the_first_by_id() -> None:
    g = genome({0: 1.0, 1: -0.5, 2: 3.0, 4: 0.1, 5: 7.0})
    far = genome({0: 3.0, 1: -0.5, 2: 3.0, 4: 0.1, 5: 7.0})  # W = 2 / 5: D = 0.16
    nearest, first = SpeciationConfig(), SpeciationConfig(assignment="first")
    assert nearest.assignment == "nearest"
    labels, _, _ = speciate([g], {2: far, 5: g}, 1.0, nearest, next_id=6)
    assert labels.tolist() == [5]
    labels, _, _ = speciate([g], {2: far, 5: g}, 1.0, first, next_id=6)
    assert labels.tolist() == [2]
    for cfg in (nearest, first):  # out of reach of the first: both pick the one in reach
        labels, _, _ = speciate([g], {2: far, 5: g}, 0.1, cfg, next_id=6)
        assert labels.tolist() == [5]
    # equally near: the lower id
    labels, _, _ = speciate([g], {3: g, 1: g}, 1.0, nearest, next_id=6)
    assert labels.tolist() == [1]


def test_distance_equal_to_threshold_founds_a_new_species() -> None:
    a = genome({0: 0.0})
    b = genome({0: 1.0})
    cfg = SpeciationConfig(c3=0.5)
    assert distance(a, b, cfg.c1, cfg.c2, cfg.c3) == 0.5
    labels, _, _ = speciate([b], {0: a}, 0.5, cfg, next_id=1)
    assert labels.tolist() == [1]  # "within" is strict: D < threshold


def test_new_representative_is_member_closest_to_old_and_empty_species_drop() -> None:
    old = genome({0: 1.0, 1: 1.0})
    m1 = genome({0: 2.0, 1: 1.0})  # W = 0.5
    m2 = genome({0: 1.2, 1: 1.0})  # W = 0.1, the closest
    m3 = genome({0: 1.2, 1: 1.0})  # a tie with m2: the first wins
    lonely = genome({3: 1.0, 4: 1.0, 5: 1.0})
    labels, reps, next_id = speciate([m1, m2, m3], {1: old, 4: lonely}, 1.0, SpeciationConfig(), 5)
    assert labels.tolist() == [1, 1, 1]
    assert list(reps) == [1] and reps[1] is m2
    assert next_id == 5


def test_speciate_refuses_bad_threshold_and_stale_next_id() -> None:
    cfg = SpeciationConfig()
    with pytest.raises(ConfigError, match="threshold"):
        speciate([A], {}, 0.0, cfg, 0)
    with pytest.raises(ConfigError, match="threshold"):
        speciate([A], {}, float("nan"), cfg, 0)
    with pytest.raises(ConfigError, match="next_id"):
        speciate([A], {3: B}, 1.0, cfg, 3)


def test_speciation_of_an_evolved_population_is_consistent() -> None:
    tracker = InnovationTracker(3 + 1 + 2)
    rng = np.random.default_rng(0)
    pop = [minimal_genome(3, 2, tracker, rng) for _ in range(20)]
    for _ in range(3):
        pop = [mutate(g, MutationConfig(node_rate=0.2, edge_rate=0.1), tracker, rng) for g in pop]
        tracker.new_generation()
    for assignment in ("first", "nearest"):
        cfg = SpeciationConfig(assignment=assignment)
        labels, reps, _ = speciate(pop, {}, 1.5, cfg, next_id=0)
        assert set(labels.tolist()) == set(reps)
        founders: dict[int, Genome] = {}
        for g, label in zip(pop, labels.tolist(), strict=True):
            gaps = {sid: distance(g, f) for sid, f in founders.items()}
            if label not in founders:  # founders so far were all out of reach
                assert all(gap >= 1.5 for gap in gaps.values())
                founders[label] = g
            elif assignment == "first":  # every earlier species was out of reach
                assert gaps[label] < 1.5
                assert all(gap >= 1.5 for sid, gap in gaps.items() if sid < label)
            else:  # none is nearer
                assert gaps[label] < 1.5 and gaps[label] == min(gaps.values())
        assert len(founders) > 1


@pytest.mark.parametrize(
    ("n_species", "expected"), [(12, 3.3), (8, 2.7), (10, 3.0)]
)
def test_threshold_moves_towards_target_species_count(n_species: int, expected: float) -> None:
    cfg = SpeciationConfig(target_species=10, threshold_step=0.3)
    assert adjust_threshold(3.0, n_species, cfg) == pytest.approx(expected)


def test_threshold_floor_and_no_target() -> None:
    cfg = SpeciationConfig(target_species=10, threshold_step=0.3, threshold_min=0.5)
    assert adjust_threshold(0.6, 1, cfg) == 0.5
    assert adjust_threshold(0.5, 1, cfg) == 0.5
    assert adjust_threshold(3.0, 50, SpeciationConfig()) == 3.0  # no target set


def test_steering_reaches_target_on_real_population() -> None:
    """Lowering the threshold when too few species yields more species, and vice versa."""
    tracker = InnovationTracker(3 + 1 + 2)
    rng = np.random.default_rng(1)
    pop = [minimal_genome(3, 2, tracker, rng, weight_sigma=2.0) for _ in range(30)]
    cfg = SpeciationConfig(target_species=6, threshold=5.0, threshold_step=0.2)
    threshold = cfg.threshold
    counts = []
    for _ in range(40):
        labels, _, _ = speciate(pop, {}, threshold, cfg, next_id=0)
        counts.append(len(set(labels.tolist())))
        threshold = adjust_threshold(threshold, counts[-1], cfg)
    assert counts[0] < 6  # started coarse
    assert abs(np.mean(counts[-10:]) - 6) <= 2  # settled around the target


def test_merge_folds_a_younger_species_within_the_threshold_into_the_older() -> None:
    old = genome({0: 1.0, 1: 1.0})
    young = genome({0: 1.5, 1: 1.0})  # W = 0.25: D = 0.1 from old
    member = genome({0: 1.4, 1: 1.0})  # nearer young (D = 0.04) than old (D = 0.08)
    split, merging = SpeciationConfig(), SpeciationConfig(merge=True)
    labels, reps, _ = speciate([member], {1: old, 2: young}, 0.5, split, next_id=3)
    assert labels.tolist() == [2]  # without merge a species lives while it has members
    labels, reps, _ = speciate([member], {1: old, 2: young}, 0.5, merging, next_id=3)
    assert labels.tolist() == [1] and list(reps) == [1]  # young lay within 0.5 of old
    labels, _, _ = speciate([member], {1: old, 2: young}, 0.09, merging, next_id=3)
    assert labels.tolist() == [2]  # beyond the threshold both species stay


def test_with_merge_the_species_count_follows_the_target_both_ways() -> None:
    """A population split into many species returns to the target once the threshold rises;
    without merge the count stays where the split left it (experiment E088)."""
    tracker = InnovationTracker(3 + 1 + 2)
    rng = np.random.default_rng(2)
    pop = [minimal_genome(3, 2, tracker, rng, weight_sigma=2.0) for _ in range(40)]
    counts = {}
    for merge in (False, True):
        cfg = SpeciationConfig(target_species=4, threshold=0.3, threshold_step=0.1, merge=merge)
        threshold, reps, next_id, seen = cfg.threshold, {}, 0, []
        for _ in range(40):
            _, reps, next_id = speciate(pop, reps, threshold, cfg, next_id)
            seen.append(len(reps))
            threshold = adjust_threshold(threshold, seen[-1], cfg)
        counts[merge] = seen
    assert counts[False][0] > 10 and counts[True][0] > 10  # both split at 0.3
    assert min(counts[False]) > 10  # and without merge never come back
    assert abs(np.mean(counts[True][-10:]) - 4) <= 1


@pytest.mark.parametrize(
    "kw",
    [{"target_species": 0}, {"threshold": 0.2, "threshold_min": 0.3}, {"c1": -1.0},
     {"threshold_step": float("nan")}, {"assignment": "closest"}],
)
def test_config_refuses_bad_values(kw: dict[str, float]) -> None:
    with pytest.raises(ConfigError):
        SpeciationConfig(**kw)  # type: ignore[arg-type]
