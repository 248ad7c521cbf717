"""The niches a training config forms: species and the largest niche's share per generation.

    python benchmarks/probes/niche_sizes.py --robot ugv --config original --generations 20 \
        --set evolution.speciation.threshold=1.5 --set evolution.speciation.target_species=5

Trains one dual-stage run of ``--config`` (``mentor-train``, seed ``--seed``, ``--generations``
split evenly between the stages, ``--set`` on top) into ``--out`` (a temporary folder by
default) and prints, per generation, the number of species and the largest niche's share of
the population (``history.csv``), then the least, mean and largest share from generation 3 on.
The paper reports the largest niche at 25-35 % of the population for the UGV and at most 25 %
for the Swarm-Robot (issue 55; experiment E088).
"""

from __future__ import annotations

import argparse
import csv
import statistics
import sys
import tempfile
from pathlib import Path

from mentor_core.cli.train import main as train_main


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--robot", default="ugv")
    p.add_argument("--config", default="original")
    p.add_argument("--seed", default="1")
    p.add_argument("--generations", type=int, default=20)
    p.add_argument("--set", action="append", default=[], dest="settings")
    p.add_argument("--out", type=Path)
    args = p.parse_args(argv)
    out = args.out or Path(tempfile.mkdtemp(prefix="niches-")) / "run"
    keys = [f"generations={args.generations}", f"stage1_generations={args.generations // 2}",
            *args.settings]  # fmt: skip
    code = train_main(["--robot", args.robot, "--framework", "dual", "--config", args.config,
                       "--seed", args.seed, *[x for k in keys for x in ("--set", k)],
                       "--out", str(out), "--quiet"])  # fmt: skip
    if code:
        return code
    with (out / "history.csv").open(newline="") as f:
        rows = list(csv.DictReader(f))
    for r in rows:
        print(f"generation {r['generation']:>3}: {r['species']:>3} species, largest "
              f"{float(r['largest_niche_share']):.0%}")
    shares = [float(r["largest_niche_share"]) for r in rows[3:]]
    if shares:
        print(f"largest share from generation 3: least {min(shares):.2f}, mean "
              f"{statistics.fmean(shares):.2f}, most {max(shares):.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
