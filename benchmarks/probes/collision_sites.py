"""Where the collisions of a ``mentor-eval`` run happen: at a wall's end, along a wall, at a box.

    python benchmarks/probes/collision_sites.py EVAL_JSON [--wall-length 2.0] [--end 0.05]

Reads the evaluation file ``mentor-eval --out`` writes (its world and every episode's
trajectory) and, for each episode that ended in a collision, finds the obstacle nearest to the
robot's last pose (the last collision-free sample): a box whose long side is at least
``--wall-length`` m is a wall, and a contact within ``--end`` m of a wall's end is at its end;
the arena's border counts on its own. It also gives the bearing of that nearest point from the
robot's heading (deg, 0 ahead, positive to the left). Prints one JSON object: per genome and in
all, the counts by site and the sorted bearings.
"""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path
from typing import Any

import numpy as np


def collision_site(
    pose: tuple[float, float, float], obstacles: np.ndarray, size: float, wall_length: float,
    end: float,
) -> tuple[str, float | None]:
    """``(site, bearing deg)`` of the obstacle nearest to ``pose``; bearing None at the border."""
    x, y, theta = pose
    border = min(x, y, size - x, size - y)
    if obstacles.shape[0] == 0:
        return "border", None
    px = np.clip(x, obstacles[:, 0], obstacles[:, 2])
    py = np.clip(y, obstacles[:, 1], obstacles[:, 3])
    k = int(np.argmin(np.hypot(px - x, py - y)))
    if border < math.hypot(px[k] - x, py[k] - y):
        return "border", None
    x0, y0, x1, y1 = obstacles[k]
    if max(x1 - x0, y1 - y0) < wall_length:
        site = "box"
    else:
        along = (px[k], x0, x1) if x1 - x0 >= y1 - y0 else (py[k], y0, y1)
        site = "wall_end" if min(along[0] - along[1], along[2] - along[0]) < end else "wall_side"
    bearing = math.degrees(math.atan2(py[k] - y, px[k] - x) - theta)
    return site, (bearing + 180.0) % 360.0 - 180.0


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("eval", type=Path, help="mentor-eval --out file")
    p.add_argument("--wall-length", type=float, default=2.0, help="m (2.0)")
    p.add_argument("--end", type=float, default=0.05, help="m (0.05)")
    args = p.parse_args()
    data = json.loads(args.eval.read_text(encoding="utf-8"))
    obstacles = np.asarray(data["world"]["obstacles"], dtype=np.float64).reshape(-1, 4)
    size = float(data["world"]["size"])
    report: dict[str, Any] = {"eval": str(args.eval), "genomes": {}}
    total: dict[str, int] = {}
    bearings: list[float] = []
    for run in data["runs"]:
        counts: dict[str, int] = {}
        for result in run["results"]:
            if not result["collided"]:
                continue
            last = result["trajectory"][-1]
            site, bearing = collision_site(
                (last[0], last[1], last[2]), obstacles, size, args.wall_length, args.end
            )
            counts[site] = counts.get(site, 0) + 1
            total[site] = total.get(site, 0) + 1
            if bearing is not None:
                bearings.append(round(bearing, 1))
        report["genomes"][run["genome"]] = counts
    report["all"] = total
    report["bearings_deg"] = sorted(bearings)
    print(json.dumps(report, indent=2))


if __name__ == "__main__":
    main()
