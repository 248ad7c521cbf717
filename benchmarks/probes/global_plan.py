"""The plain planner against the planner with a global plan, on hand-made structured worlds.

    python benchmarks/probes/global_plan.py OUT_DIR [--genome G] [--robot ugv] [--pairs 8]
    python benchmarks/probes/global_plan.py OUT_DIR --bench test --families rooms,traps,maze

With ``--bench SPLIT`` the worlds and pairs are the generalisation benchmark's
(``mentor_core.benchmark.suite``, ``--pairs`` per family) instead of the hand-made ones.

Writes one world file per world into OUT_DIR (rooms with doorways, dead-end traps, a slalom
of walls, a perfect maze of 2 m cells; 12 m for the UGV, the same layouts scaled to 4 m for
the Swarm-Robot), with ``--pairs`` start/goal pairs each (in the traps four placed by
hand, from inside a trap to behind it; the rest sampled with seed 0, at least a third of the
arena apart),
then runs ``mentor-eval GENOME --robot R --world FILE --global-plan --out FILE.json`` on each
and prints one line per world and a total: success, collisions and timeouts of the plain run
and of the run along the global plan. The proper benchmark (world families, splits, SPL) is
``mentor_core.benchmark``'s; this is a quick look at a handful of worlds.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
from collections.abc import Iterator
from pathlib import Path

import numpy as np

from mentor_core.benchmark.suite import build_suite
from mentor_core.cli.evaluate import main as mentor_eval
from mentor_core.sim.robots import RobotProfile, get_profile
from mentor_core.sim.scenarios import sample_scenarios
from mentor_core.sim.world import Scenario, World, save_world

ROOT = Path(__file__).resolve().parents[2]
T = 0.2  # wall thickness at 12 m, m


def _wall(x0: float, y0: float, x1: float, y1: float) -> list[float]:
    """A wall of thickness T along the segment (x0, y0)-(x1, y1) (axis-aligned)."""
    h = T / 2
    return [min(x0, x1) - h, min(y0, y1) - h, max(x0, x1) + h, max(y0, y1) + h]


def _maze(n: int, cell: float) -> list[list[float]]:
    """The walls of a perfect maze of ``n x n`` cells (depth-first carving from cell (0, 0),
    neighbours in a fixed order turned by a seeded generator), one wall per closed edge."""
    rng = np.random.default_rng(0)
    open_edges: set[tuple[tuple[int, int], tuple[int, int]]] = set()
    seen, stack = {(0, 0)}, [(0, 0)]
    while stack:
        x, y = stack[-1]
        nexts = [(x + dx, y + dy) for dx, dy in ((1, 0), (0, 1), (-1, 0), (0, -1))]
        nexts = [c for c in nexts if 0 <= c[0] < n and 0 <= c[1] < n and c not in seen]
        if not nexts:
            stack.pop()
            continue
        c = nexts[int(rng.integers(len(nexts)))]
        open_edges.add((min((x, y), c), max((x, y), c)))
        seen.add(c)
        stack.append(c)
    walls = []
    for x in range(n):
        for y in range(n):
            if x + 1 < n and ((x, y), (x + 1, y)) not in open_edges:
                walls.append(_wall((x + 1) * cell, y * cell, (x + 1) * cell, (y + 1) * cell))
            if y + 1 < n and ((x, y), (x, y + 1)) not in open_edges:
                walls.append(_wall(x * cell, (y + 1) * cell, (x + 1) * cell, (y + 1) * cell))
    return walls


def layouts() -> dict[str, list[list[float]]]:
    """Obstacle boxes of each world in a 12 m arena (walls overlap at their corners)."""
    return {
        # four rooms, a 1.4 m door in each inner wall half
        "rooms": [
            _wall(6, 0, 6, 2.3), _wall(6, 3.7, 6, 8.3), _wall(6, 9.7, 6, 12),
            _wall(0, 6, 2.3, 6), _wall(3.7, 6, 8.3, 6), _wall(9.7, 6, 12, 6),
        ],
        # two U-shaped dead ends facing each other's open sides
        "traps": [
            _wall(4, 2, 4, 6), _wall(1.5, 2, 4, 2), _wall(1.5, 6, 4, 6),
            _wall(8, 6, 8, 10), _wall(8, 6, 10.5, 6), _wall(8, 10, 10.5, 10),
        ],
        # walls from alternate sides, a 1.6 m gap at the other end of each
        "slalom": [
            _wall(3, 0, 3, 10.4), _wall(6, 1.6, 6, 12), _wall(9, 0, 9, 10.4),
        ],
        # a perfect maze of 6 x 6 cells of 2 m (one way between any two cells, dead ends)
        "maze": _maze(6, 2.0),
    }


#: start (x, y, theta) / goal (x, y) pairs placed by hand (12 m), before the sampled ones:
#: from inside each trap to behind its back wall, and from outside into the other
HAND_PAIRS = {
    "traps": [
        ((2.5, 4.0, 0.0), (6.0, 4.0)),
        ((0.8, 4.0, 0.0), (6.5, 3.0)),
        ((9.5, 8.0, np.pi), (6.0, 8.0)),
        ((11.2, 8.0, np.pi), (5.5, 9.0)),
    ],
}


def worlds(size: float) -> dict[str, World]:
    """The layouts scaled to an arena of side ``size`` (m), clipped to it."""
    scale = size / 12.0
    return {
        name: World(size, np.clip(np.array(boxes) * scale, 0.0, size), name=name)
        for name, boxes in layouts().items()
    }


def _cases(
    args: argparse.Namespace, profile: RobotProfile, size: float
) -> Iterator[tuple[str, World, list[Scenario]]]:
    """(name, world, pairs) of each world to run: the hand-made ones, or the benchmark's."""
    if args.bench:
        suite = build_suite(profile, args.bench, args.families.split(","), args.pairs)
        by_world: dict[str, list[Scenario]] = {}
        for pair in suite.pairs:
            by_world.setdefault(pair.scenario.world.name, []).append(pair.scenario)
        for name, pairs in by_world.items():
            yield name, pairs[0].world, pairs
        return
    for name, world in worlds(size).items():
        rng = np.random.default_rng(0)
        scale = size / 12.0
        pairs = [
            Scenario(world, (x * scale, y * scale, th), (gx * scale, gy * scale))
            for (x, y, th), (gx, gy) in HAND_PAIRS.get(name, [])
        ]
        pairs += sample_scenarios(
            world, profile, args.pairs - len(pairs), rng, min_distance=size / 3
        )
        yield name, world, pairs


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("out", type=Path)
    p.add_argument("--robot", default="ugv", choices=("ugv", "swarm"))
    p.add_argument(
        "--genome", type=Path, help="default: bags/regression/<robot>_reference_genome.json"
    )
    p.add_argument("--pairs", type=int, default=8)
    p.add_argument("--time-limit", type=float, default=50.0)
    p.add_argument("--lookahead", type=float, help="m (default: mentor-eval's)")
    p.add_argument("--bench", choices=("validation", "test"), help="the benchmark's split")
    p.add_argument("--families", default="rooms,traps,maze", help="with --bench")
    args = p.parse_args()
    profile = get_profile(args.robot)
    genome = args.genome or ROOT / "bags" / "regression" / f"{args.robot}_reference_genome.json"
    size = 12.0 if args.robot == "ugv" else 4.0
    args.out.mkdir(parents=True, exist_ok=True)
    totals = np.zeros((2, 3), dtype=int)
    n_total = 0
    print(f"{'world':<8} {'plain R/C/T':>12} {'global plan R/C/T':>18}")
    for name, world, pairs in _cases(args, profile, size):
        path = args.out / f"{name}.yaml"
        save_world(path, world, pairs)
        result = args.out / f"{name}.json"
        with contextlib.redirect_stdout(io.StringIO()):  # its tables: in the JSON too
            code = mentor_eval([
                str(genome), "--robot", args.robot, "--world", str(path), "--global-plan",
                "--time-limit", str(args.time_limit), "--out", str(result),
                *(["--lookahead", str(args.lookahead)] if args.lookahead else []),
            ])  # fmt: skip
        if code != 0:
            raise SystemExit(f"mentor-eval failed on {path}")
        cells = []
        for k, run in enumerate(json.loads(result.read_text())["runs"]):
            outcome = np.array(
                [(r["reached"], r["collided"], r["timed_out"]) for r in run["results"]]
            ).sum(axis=0)
            totals[k] += outcome
            cells.append("/".join(str(int(v)) for v in outcome))
        n_total += len(pairs)
        print(f"{name:<8} {cells[0]:>12} {cells[1]:>18}", flush=True)
    share = totals[:, 0] / n_total
    print(f"{'total':<8} {'/'.join(map(str, totals[0])):>12} {'/'.join(map(str, totals[1])):>18}")
    print(f"success: plain {share[0]:.0%}, global plan {share[1]:.0%} of {n_total} pairs")


if __name__ == "__main__":
    main()
