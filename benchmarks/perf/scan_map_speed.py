"""How long the planners take on their scan map (``mentor-bench --set scan_map={}``: the
genome on its scan map, VFH+ as ``mapped-vfh``), as one JSON object for
``benchmarks/perf/side_by_side.py``.

    .venv/bin/python benchmarks/perf/scan_map_speed.py [--pairs-per-family 8]
        [--genome ugv=PATH --genome swarm=PATH]

Per robot, the seconds of one run of the genome (default: the shipped regression reference
genomes) and of mapped VFH+ on their scan map, validation split, after a warm-up run on one
pair per family. ``objectives_sha256`` hashes every episode's outcome and trajectory, so two
checkouts that decide alike print the same hash.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import time

import numpy as np
from generalisation_bench import chosen_genomes

from mentor_core.benchmark.contenders import evolved, hand_written, on_scan_map
from mentor_core.benchmark.runner import run_contender
from mentor_core.benchmark.suite import build_suite, shipped_limits
from mentor_core.controller.deployment import load_deployment
from mentor_core.sim.robots import get_profile


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--pairs-per-family", type=int, default=8)
    p.add_argument("--genome", action="append", default=[], metavar="ROBOT=PATH")
    args = p.parse_args(argv)
    genomes = chosen_genomes(args.genome)
    out: dict[str, object] = {}
    digest = hashlib.sha256()
    for name, path in genomes.items():
        robot = get_profile(name)
        mapped, _ = load_deployment("none", name, ["scan_map={}"])  # the plan's defaults
        assert mapped.scan_map is not None
        vfh = hand_written("vfh", shipped_limits(robot))
        contenders = [evolved(path, robot, deployment=mapped),
                      on_scan_map(vfh, mapped.scan_map.guide(vfh.profile))]  # fmt: skip
        for c in contenders:  # warm-up: numba kernels compiled or loaded
            run_contender(build_suite(robot, "validation", pairs_per_family=1), c)
        suite = build_suite(robot, "validation", pairs_per_family=args.pairs_per_family)
        for label, c in zip(("evolved", "vfh"), contenders, strict=True):
            began = time.perf_counter()
            o = run_contender(suite, c).outcomes
            out[f"seconds_{name}_{label}"] = time.perf_counter() - began
            for field in (o.reached, o.collided, o.steps, o.time, *o.trajectories):
                digest.update(np.ascontiguousarray(field).tobytes())
    out["objectives_sha256"] = digest.hexdigest()
    print(json.dumps(out))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
