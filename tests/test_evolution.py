"""Evolution (ask/tell): shapes, modes, stats, best, reseed, reporters, state round trip."""

from __future__ import annotations

import io
import json

import numpy as np
import pytest

from mentor_core.errors import FileFormatError
from mentor_core.evolution.config import EvolutionConfig
from mentor_core.evolution.genome import Genome
from mentor_core.evolution.loop import Evolution
from mentor_core.evolution.network import FeedForwardNetwork
from mentor_core.evolution.ranking import scalar_fitness
from mentor_core.evolution.reporting import (
    GenerationStats,
    HistoryReporter,
    Reporter,
    StdOutReporter,
)
from mentor_core.evolution.species import SpeciationConfig

X = np.array([[0.0, 0.0], [0.0, 1.0], [1.0, 0.0], [1.0, 1.0]])


def small_config(**kw: object) -> EvolutionConfig:
    d: dict[str, object] = {"population_size": 20, "generations": 5}
    d.update(kw)
    return EvolutionConfig.from_dict(d)


def two_objectives(genomes: list[Genome]) -> np.ndarray:
    """(F, G): mean output on X, and the network's number of enabled connections."""
    rows = []
    for g in genomes:
        out = FeedForwardNetwork.from_genome(g).activate(X)[:, 0]
        rows.append([float(out.mean()), float(len(g.enabled_connections))])
    return np.array(rows)


class Recorder(Reporter):
    def __init__(self) -> None:
        self.events: list[tuple[str, int]] = []

    def start_generation(self, generation: int) -> None:
        self.events.append(("start", generation))

    def end_generation(self, stats: GenerationStats) -> None:
        self.events.append(("end", stats.generation))

    def found_solution(self, generation: int, genome: Genome, objectives: np.ndarray) -> None:
        self.events.append(("solution", generation))

    def info(self, message: str) -> None:
        self.events.append(("info", -1))


def test_initial_population_is_minimal() -> None:
    evo = Evolution(small_config(), n_inputs=2, n_outputs=1, seed=0)
    pop = evo.ask()
    assert len(pop) == 20
    assert all(len(g.connections) == 3 and not g.hidden_nodes for g in pop)
    assert evo.ask() == pop  # same until tell
    assert len({tuple(c.weight for c in g.connections) for g in pop}) == 20
    assert evo.labels is None and evo.fitness is None
    with pytest.raises(RuntimeError):
        evo.best()


def test_tell_stats() -> None:
    evo = Evolution(small_config(), 2, 1, seed=1, objectives=2)
    pop = evo.ask()
    obj = two_objectives(pop)
    stats = evo.tell(obj)
    assert stats.generation == 0 and evo.generation == 1
    assert stats.evaluations == 20 and evo.evaluations == 20
    assert stats.mode == "multi"
    assert stats.best_objectives == tuple(obj.max(axis=0))
    assert stats.mean_objectives == pytest.approx(tuple(obj.mean(axis=0)))
    assert len(stats.labels) == 20
    assert sum(stats.niche_sizes.values()) == 20
    assert stats.species_count == len(stats.niche_sizes)
    assert set(stats.niche_targets) == set(stats.niche_sizes)
    assert stats.largest_niche_share == max(stats.niche_sizes.values()) / 20
    assert stats.best_index == int(np.argmax(obj[:, 0]))
    assert evo.evaluated_population == pop
    assert np.array_equal(evo.fitness, scalar_fitness(obj))  # type: ignore[arg-type]
    assert len(evo.ask()) == 20 and evo.ask() != pop
    assert GenerationStats.from_dict(json.loads(json.dumps(stats.to_dict()))) == stats


def test_single_mode_ranks_by_column_zero() -> None:
    evo = Evolution(small_config(), 2, 1, seed=2, objectives=2)
    obj = two_objectives(evo.ask())
    stats = evo.tell(obj, mode="single")
    assert stats.mode == "single"
    assert np.array_equal(evo.fitness, scalar_fitness(obj[:, :1]))  # type: ignore[arg-type]
    # single mode accepts one column even if the run has two objectives
    evo.tell(obj[:, :1], mode="single")
    assert evo.generation == 2


def test_tell_rejects_bad_input() -> None:
    evo = Evolution(small_config(), 2, 1, seed=0, objectives=2)
    ok = np.ones((20, 2))
    with pytest.raises(ValueError, match="shape"):
        evo.tell(np.ones((19, 2)))
    with pytest.raises(ValueError, match="columns"):
        evo.tell(np.ones((20, 3)))
    bad = ok.copy()
    bad[3, 1] = np.nan
    with pytest.raises(ValueError, match="finite"):
        evo.tell(bad)
    with pytest.raises(ValueError, match="mode"):
        evo.tell(ok, mode="both")  # type: ignore[arg-type]
    assert evo.generation == 0  # nothing changed
    with pytest.raises(ValueError):
        Evolution(small_config(), 2, 1, seed=0, objectives=0)


def test_best_is_best_of_all_generations() -> None:
    evo = Evolution(small_config(), 2, 1, seed=3)
    evo.tell(np.full(20, 1.0).reshape(-1, 1) + np.eye(20)[5, :, None] * 9)
    best_genome = evo.evaluated_population[5]
    evo.tell(np.full((20, 1), 2.0))
    genome, values = evo.best()
    assert genome == best_genome
    assert values.tolist() == [10.0]


def test_threshold_follows_target_species() -> None:
    cfg = small_config(speciation={"threshold": 0.5, "target_species": 1, "threshold_step": 0.25})
    evo = Evolution(cfg, 2, 1, seed=4)
    stats = evo.tell(np.ones((20, 1)))
    # 20 random minimal genomes at threshold 0.5 give several species: threshold goes up
    assert stats.species_count > 1
    assert stats.threshold == evo.threshold == 0.75


def test_reseed_fills_with_mutated_copies() -> None:
    evo = Evolution(small_config(mutation={"weight_rate": 1.0}), 2, 1, seed=5, objectives=2)
    evo.tell(two_objectives(evo.ask()))
    seeds = evo.evaluated_population[:3]
    evo.reseed(seeds)
    pop = evo.ask()
    assert len(pop) == 20
    assert pop[:3] == seeds
    assert all(g not in seeds for g in pop[3:])
    with pytest.raises(ValueError):
        evo.reseed([])
    other = Evolution(small_config(), 3, 1, seed=0)
    with pytest.raises(ValueError, match="inputs"):
        evo.reseed(other.ask()[:1])


def test_reporters_get_events_in_order() -> None:
    rec, hist = Recorder(), HistoryReporter()
    evo = Evolution(small_config(), 2, 1, seed=6, reporters=[rec, hist])
    evo.ask()
    evo.ask()
    evo.tell(np.ones((20, 1)))
    evo.ask()
    evo.tell(np.ones((20, 1)))
    evo.reseed(evo.population[:2])
    assert rec.events == [("start", 0), ("end", 0), ("start", 1), ("end", 1), ("info", -1)]
    assert [s.generation for s in hist.history] == [0, 1]
    assert json.loads(hist.to_json())[1]["evaluations"] == 40


def test_run_stops_at_threshold() -> None:
    rec = Recorder()
    evo = Evolution(small_config(population_size=30), 2, 1, seed=7, reporters=[rec])

    def mean_output(genomes: list[Genome]) -> np.ndarray:
        return two_objectives(genomes)[:, :1]

    result = evo.run(mean_output, generations=30, fitness_threshold=0.95, mode="single")
    assert result.solved
    assert result.best_objectives[0] >= 0.95
    assert ("solution", result.generations - 1) in rec.events
    assert result.evaluations == 30 * result.generations == len(result.history) * 30


def test_run_default_generations_from_config() -> None:
    evo = Evolution(small_config(generations=3), 2, 1, seed=8, objectives=2)
    result = evo.run(two_objectives)
    assert result.generations == 3 and not result.solved
    assert [s.generation for s in result.history] == [0, 1, 2]


def test_state_is_json_and_continues_identically() -> None:
    a = Evolution(small_config(), 2, 1, seed=9, objectives=2)
    for _ in range(3):
        a.tell(two_objectives(a.ask()))
    state = json.loads(json.dumps(a.to_state(), allow_nan=False))
    b = Evolution.from_state(state)
    assert b.ask() == a.ask()
    assert b.rng.bit_generator.state == a.rng.bit_generator.state
    assert b.tracker.to_state() == a.tracker.to_state()
    assert b.representatives == a.representatives
    assert b.history == a.history
    assert b.best()[0] == a.best()[0]
    for _ in range(3):
        sa = a.tell(two_objectives(a.ask()))
        sb = b.tell(two_objectives(b.ask()))
        assert sa == sb
    assert a.ask() == b.ask()
    assert a.to_state() == b.to_state()


def test_from_state_rejects_bad_state() -> None:
    evo = Evolution(small_config(), 2, 1, seed=0)
    state = evo.to_state()
    with pytest.raises(FileFormatError, match="version"):
        Evolution.from_state({**state, "version": 99}, source="ck.json")
    with pytest.raises(FileFormatError, match=r"ck\.json"):
        Evolution.from_state({**state, "population": state["population"][:5]}, "ck.json")
    broken = dict(state)
    del broken["tracker"]
    with pytest.raises(FileFormatError, match="bad evolution state"):
        Evolution.from_state(broken, "ck.json")
    with pytest.raises(FileFormatError, match="bit generator"):
        Evolution.from_state({**state, "rng": {"bit_generator": "os.system"}}, "ck.json")
    with pytest.raises(FileFormatError):
        Evolution.from_state([], "ck.json")  # type: ignore[arg-type]


def test_seeds_give_different_populations() -> None:
    cfg = small_config(speciation=SpeciationConfig().__dict__)
    a = Evolution(cfg, 2, 1, seed=0).ask()
    b = Evolution(cfg, 2, 1, seed=1).ask()
    assert a != b
    assert Evolution(cfg, 2, 1, seed=0).ask() == a


def test_a_generation_ranking_column_0_alone_takes_nan_in_the_others() -> None:
    evo = Evolution(EvolutionConfig(population_size=10), 3, 2, seed=0, objectives=2)
    n = len(evo.ask())
    values = np.column_stack([np.arange(n, dtype=float), np.full(n, np.nan)])
    with pytest.raises(ValueError, match="finite"):
        evo.tell(values, mode="multi")
    bad = values.copy()
    bad[0, 0] = np.nan
    with pytest.raises(ValueError, match="finite"):
        evo.tell(bad, mode="single")
    values[-1, 1] = 7.0  # the best's G
    stats = evo.tell(values, mode="single")
    assert np.isnan(stats.mean_objectives[1])
    state = json.loads(json.dumps(evo.to_state(), allow_nan=False))
    again = Evolution.from_state(state)
    np.testing.assert_array_equal(again.evaluated_objectives, values)
    assert again.best()[1].tolist() == [n - 1.0, 7.0]
    stream = io.StringIO()
    StdOutReporter(stream).end_generation(stats)
    assert "mean [4.5, -]" in stream.getvalue()  # a G not computed shows as "-"
