"""Whether two ``bench.json`` files hold the same results, planner by planner.

    python benchmarks/tools/same_bench.py before/bench.json after/bench.json \
        --strip mapped-guard-shim-

Compares every contender's outcomes (reached, collided, steps, time, path length, final
distance, trajectory), scores and settings, and the suite (pairs, limits); a contender's
``seconds`` (wall time) is not compared. ``--strip PREFIX`` drops a prefix from the first
file's names (``mentor-bench --deployed`` named the planners it ran as deployed
``mapped-guard-shim-<label>`` until the deployments of experiment E086). Prints one line per
contender and exits 1 when anything differs; where a contender's results differ, how many of
its episodes still end the same way (reached, collided) and how many follow the same
trajectory (experiment E092).
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any


def _contenders(doc: dict[str, Any], strip: str) -> dict[str, dict[str, Any]]:
    out = {}
    for c in doc["contenders"]:
        name = c["name"][len(strip):] if strip and c["name"].startswith(strip) else c["name"]
        out[name] = c
    return out


def compare(before: dict[str, Any], after: dict[str, Any], strip: str = "") -> list[str]:
    """One line per contender (and per differing top-level key) saying whether it is the
    same; a line starting with ``DIFFERS`` for each difference."""
    lines = []
    for key in sorted(set(before) | set(after)):
        if key != "contenders" and before.get(key) != after.get(key):
            lines.append(f"DIFFERS {key}")
    a, b = _contenders(before, strip), _contenders(after, strip)
    for name in sorted(set(a) | set(b)):
        if name not in a or name not in b:
            lines.append(f"DIFFERS {name}: only in {'after' if name in b else 'before'}")
            continue
        faults = [k for k in ("kind", "results", "scores", "settings", "scan_map")
                  if a[name].get(k) != b[name].get(k)]  # fmt: skip
        line = f"DIFFERS {name}: {', '.join(faults)}" if faults else f"same {name}"
        ra, rb = a[name].get("results", []), b[name].get("results", [])
        if "results" in faults and len(ra) == len(rb):
            ends = sum((x["reached"], x["collided"]) == (y["reached"], y["collided"])
                       for x, y in zip(ra, rb, strict=True))  # fmt: skip
            paths = sum(x["trajectory"] == y["trajectory"] for x, y in zip(ra, rb, strict=True))
            line += f" ({ends} of {len(ra)} episodes end the same way, {paths} the same path)"
        lines.append(line)
    return lines


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("before", type=Path)
    p.add_argument("after", type=Path)
    p.add_argument("--strip", default="", help="a prefix dropped from the first file's names")
    args = p.parse_args(argv)
    lines = compare(json.loads(args.before.read_text()), json.loads(args.after.read_text()),
                    args.strip)  # fmt: skip
    print("\n".join(lines))
    return 1 if any(line.startswith("DIFFERS") for line in lines) else 0


if __name__ == "__main__":
    sys.exit(main())
