"""The paper's DoE: LHS, composite worlds without overlap, free start/goal pairs, same seed."""

from __future__ import annotations

import hashlib
import math

import numpy as np
import pytest

from mentor_core.errors import ConfigError
from mentor_core.sim.robots import get_profile
from mentor_core.sim.scenarios import (
    CLEARANCE_FACTOR,
    DoEConfig,
    latin_hypercube,
    sample_scenarios,
    sample_world,
    training_scenarios,
)
from mentor_core.sim.world import Scenario, World


def test_latin_hypercube_has_one_point_per_slice() -> None:
    u = latin_hypercube(20, 4, np.random.default_rng(0))
    assert u.shape == (20, 4)
    assert ((u >= 0.0) & (u < 1.0)).all()
    for column in u.T:
        assert sorted(np.floor(column * 20).astype(int)) == list(range(20))


@pytest.mark.parametrize("size", [12.0, 5.0])
def test_sample_world_is_composite_and_gapped(size: float) -> None:
    cfg = DoEConfig()
    world = sample_world(size, np.random.default_rng(7), cfg)
    b = world.obstacles
    sides = np.concatenate([b[:, 2] - b[:, 0], b[:, 3] - b[:, 1]])
    assert sides.min() >= cfg.size_fraction[0] * size - 1e-12
    assert sides.max() <= cfg.size_fraction[1] * size + 1e-12
    gap = cfg.gap_fraction * size
    for i in range(len(b)):
        for j in range(i + 1, len(b)):
            ox = min(b[i, 2], b[j, 2]) - max(b[i, 0], b[j, 0])
            oy = min(b[i, 3], b[j, 3]) - max(b[i, 1], b[j, 1])
            assert ox <= -gap + 1e-9 or oy <= -gap + 1e-9
    # per quadrant (by centroid): crowded_grids quadrants crowded, the others sparse
    cx, cy = (b[:, 0] + b[:, 2]) / 2, (b[:, 1] + b[:, 3]) / 2
    quadrant = (cx >= size / 2).astype(int) + 2 * (cy >= size / 2).astype(int)
    counts = sorted(np.bincount(quadrant, minlength=4).tolist())
    lo, hi = cfg.sparse_count
    assert all(lo <= c <= hi for c in counts[:2])
    lo, hi = cfg.crowded_count
    assert all(lo <= c <= hi for c in counts[2:])


def test_doe_config_rejects_bad_values() -> None:
    with pytest.raises(ConfigError, match="crowded_grids"):
        DoEConfig(crowded_grids=5)
    with pytest.raises(ConfigError, match="size_fraction"):
        DoEConfig(size_fraction=(0.2, 0.49))
    with pytest.raises(ConfigError, match="sparse_count"):
        DoEConfig(sparse_count=(3, 1))


def test_walled_worlds_have_long_walls_with_passages() -> None:
    """Walls in the DoE: their number, length, thickness; a passage between walls and beside
    a free wall's ends; no box left too close to a wall; both kinds of wall appear."""
    size = 12.0
    cfg = DoEConfig(wall_count=(1, 3))
    passage = cfg.wall_passage_fraction * size
    anchored = free = 0
    for seed in range(30):
        world = sample_world(size, np.random.default_rng(seed), cfg)
        b = world.obstacles
        long_side = np.maximum(b[:, 2] - b[:, 0], b[:, 3] - b[:, 1])
        is_wall = long_side >= cfg.wall_length_fraction[0] * size - 1e-9
        walls, boxes = b[is_wall], b[~is_wall]
        assert 1 <= len(walls) <= 3 and (b[: len(walls)] == walls).all()  # walls come first
        short_side = np.minimum(walls[:, 2] - walls[:, 0], walls[:, 3] - walls[:, 1])
        np.testing.assert_allclose(short_side, cfg.wall_thickness_fraction * size)
        assert (long_side[is_wall] <= cfg.wall_length_fraction[1] * size + 1e-9).all()
        for i, w in enumerate(walls):
            touches = min(w[0], w[1]) <= 1e-9 or max(w[2], w[3]) >= size - 1e-9
            anchored += touches
            free += not touches
            if not touches:
                assert min(w[0], w[1]) >= passage - 1e-9
                assert max(w[2], w[3]) <= size - passage + 1e-9
            for other in walls[i + 1 :]:
                apart_x = max(other[0] - w[2], w[0] - other[2])
                apart_y = max(other[1] - w[3], w[1] - other[3])
                assert max(apart_x, apart_y) >= passage - 1e-9
            gap = cfg.gap_fraction * size
            for box in boxes:
                assert max(box[0] - w[2], w[0] - box[2], box[1] - w[3], w[1] - box[3]) >= gap
    assert anchored > 5 and free > 5


def test_walls_leave_the_papers_worlds_alone_and_travel_in_configs() -> None:
    rng_a, rng_b = np.random.default_rng(3), np.random.default_rng(3)
    assert sample_world(12.0, rng_a) == sample_world(12.0, rng_b, DoEConfig(wall_count=(0, 0)))
    walled = DoEConfig(wall_count=(1, 2), wall_length_fraction=(0.4, 0.5))
    assert DoEConfig.from_dict(walled.to_dict()) == walled
    assert DoEConfig.from_dict({"wall_count": [1, 2], "wall_length_fraction": [0.4, 0.5]}) \
        == walled
    for bad, key in (({"walls": 2}, "doe.walls"), ({"wall_count": 2}, "doe.wall_count"),
                     ({"wall_count": [2, 1]}, "doe.wall_count"),
                     ({"wall_count": [1.5, 2]}, "doe.wall_count"),
                     ({"wall_length_fraction": [0.5, 0.9]}, "doe.wall_length_fraction"),
                     ({"wall_anchor_share": "half"}, "doe.wall_anchor_share"),
                     ({"wall_passage_fraction": 0.5}, "doe.wall_passage_fraction")):
        with pytest.raises(ConfigError, match=key.replace(".", r"\.")) as err:
            DoEConfig.from_dict(bad, "my.yaml")
        assert "my.yaml" in str(err.value)


@pytest.mark.parametrize("robot", ["ugv", "swarm"])
def test_sampled_scenarios_are_free_and_in_range(robot: str) -> None:
    profile = get_profile(robot)
    scenarios = training_scenarios(profile, seed=3)
    assert len(scenarios) == profile.train_scenarios
    world = scenarios[0].world
    assert world.size == profile.train_arena
    starts = np.array([s.start for s in scenarios])
    goals = np.array([s.goal for s in scenarios])
    clearance = CLEARANCE_FACTOR * profile.half_diagonal
    assert world.free_at(starts[:, :2], clearance).all()
    assert world.free_at(goals, clearance).all()
    dist = np.hypot(*(goals - starts[:, :2]).T)
    assert dist.min() >= 2 * profile.goal_radius
    assert dist.max() <= profile.uncapped_distance
    assert all(profile.time_budget(s.start[:2], s.goal) < profile.time_budget_cap
               for s in scenarios)
    assert ((starts[:, 2] > -math.pi) & (starts[:, 2] <= math.pi)).all()
    assert len(set(np.round(starts[:, 2], 6))) == len(scenarios)


def _digest(scenarios: list[Scenario]) -> str:
    h = hashlib.sha256(scenarios[0].world.obstacles.tobytes())
    h.update(np.array([s.start + s.goal for s in scenarios]).tobytes())
    return h.hexdigest()


def test_same_seed_same_scenarios_other_seed_differs() -> None:
    ugv = get_profile("ugv")
    first = _digest(training_scenarios(ugv, seed=11))
    assert _digest(training_scenarios(ugv, seed=11)) == first
    assert _digest(training_scenarios(ugv, seed=12)) != first
    # the world does not depend on n, and fewer scenarios are a prefix of more
    few, many = training_scenarios(ugv, 11, n=5), training_scenarios(ugv, 11, n=30)
    assert few == many[:5]


def test_training_scenarios_spread_over_several_worlds() -> None:
    ugv = get_profile("ugv")
    one = training_scenarios(ugv, 11, n=7)
    three = training_scenarios(ugv, 11, n=7, worlds=3)
    worlds = [sc.world for sc in three]
    assert [w.name for w in worlds] == (
        ["ugv-train-seed11"] * 3 + ["ugv-train-seed11-world1"] * 2
        + ["ugv-train-seed11-world2"] * 2
    )
    assert worlds[0] == one[0].world  # the first world is the one-world DoE's
    assert worlds[3] != worlds[0] and worlds[5] != worlds[3]
    assert _digest(training_scenarios(ugv, 11, n=7, worlds=3)) == _digest(three)
    for bad in ({"worlds": 0}, {"n": 2, "worlds": 3}):
        with pytest.raises(ValueError, match="world"):
            training_scenarios(ugv, 11, **bad)  # type: ignore[arg-type]


def test_sample_scenarios_bad_requests() -> None:
    profile = get_profile("ugv")
    world = World(12.0)
    rng = np.random.default_rng(0)
    with pytest.raises(ValueError, match="half diagonal"):
        sample_scenarios(world, profile, 3, rng, clearance=0.1)
    with pytest.raises(ValueError, match="distance range"):
        sample_scenarios(world, profile, 3, rng, min_distance=5.0, max_distance=4.0)
    with pytest.raises(ValueError, match="found only 0 of 3"):
        sample_scenarios(World(3.0), profile, 3, rng, min_distance=5.0, max_distance=6.0)
    assert sample_scenarios(world, profile, 0, rng) == []
