"""The figures of docs/irsim.md: trajectories of a few IR-SIM episodes, and one as an
animation (a GIF drawn frame by frame with matplotlib: IR-SIM's own recorder needs a figure
it draws while stepping, which headless runs leave out).

    python benchmarks/tools/irsim_figures.py --out docs

The shipped dual-stage planners (seed 1, as deployed, IR-SIM seed 1) on the first pair of
one test world of each kind; writes ``OUT/irsim_trajectories.png`` and
``OUT/irsim_crowd.gif`` (a UGV among 15 agents: pair 2 of ``ugv-crowd-0``), each well under
1 MB.
"""

from __future__ import annotations

import argparse
import io
import sys
from collections.abc import Sequence
from pathlib import Path

from matplotlib.figure import Figure
from PIL import Image

from mentor_core.atomic import write_bytes_atomic
from mentor_core.controller.deployment import load_deployment
from mentor_core.irsim.drivers import genome_driver
from mentor_core.irsim.episode import EpisodeResult, run_episode
from mentor_core.irsim.figures import draw_episode, save_episodes
from mentor_core.irsim.world_file import IrsimWorld, load_world

ROOT = Path(__file__).resolve().parents[2]
SHOWN = ("ugv-pillar_hall-0", "ugv-cluttered_office-0", "ugv-crowd-0", "ugv-stopper-0",
         "swarm-slanted_furniture-0", "swarm-crossing-0")  # fmt: skip


def episode(name: str, pair: int = 0) -> tuple[IrsimWorld, EpisodeResult]:
    """Pair ``pair`` of test world ``name`` by its robot's seed-1 shipped planner, recorded."""
    world = load_world(ROOT / "benchmarks" / "irsim_worlds" / "test" / f"{name}.yaml")
    genome = ROOT / "planners" / f"{world.robot}-paper-dual-s1.json"
    spec = genome_driver(genome, world.robot, world.size,
                         load_deployment("shipped", world.robot)[0])  # fmt: skip
    return world, run_episode(world, pair, spec, seed=1, record=True)


def animation(path: Path, world: IrsimWorld, result: EpisodeResult, every: int = 2) -> None:
    """The episode as a GIF, one frame each ``every`` IR-SIM steps."""
    assert result.trajectory is not None and result.agents is not None
    frames = []
    for end in range(2, len(result.trajectory) + 1, every):
        part = EpisodeResult(**{**result.__dict__, "trajectory": result.trajectory[:end],
                                "agents": result.agents[:end]})  # fmt: skip
        fig = Figure(figsize=(3.0, 3.1))
        draw_episode(fig.subplots(), world, part)
        fig.tight_layout()
        buffer = io.BytesIO()
        fig.savefig(buffer, dpi=60)
        frames.append(Image.open(buffer).convert("P", palette=Image.Palette.ADAPTIVE))
    out = io.BytesIO()
    frames[0].save(out, format="GIF", save_all=True, append_images=frames[1:], duration=120,
                   loop=0, optimize=True)  # fmt: skip
    write_bytes_atomic(path, out.getvalue())


def main(argv: Sequence[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--out", type=Path, default=Path("docs"))
    args = p.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    shown = [episode(name) for name in SHOWN]
    for world, r in shown:
        print(f"{world.name} pair 0: {r.outcome} after {r.time:.1f} s", flush=True)
    save_episodes(args.out / "irsim_trajectories.png", shown)
    world, crowd = episode("ugv-crowd-0", 2)
    print(f"{world.name} pair 2: {crowd.outcome} after {crowd.time:.1f} s", flush=True)
    animation(args.out / "irsim_crowd.gif", world, crowd)
    return 0


if __name__ == "__main__":
    sys.exit(main())
