"""Run one benchmark script against two checkouts of mentor_core, alternately, and print ratios.

    .venv/bin/python benchmarks/perf/side_by_side.py --before /path/to/old/checkout [--pairs 4]
        [--keys seconds_per_generation_workers1 ...] -- benchmarks/perf/generation_bench.py [args]

The script (a path in this checkout) runs with this checkout's Python; ``PYTHONPATH`` puts the
library of ``--before`` or of this checkout first, each with its own numba cache in the
temporary directory. Runs
alternate before/after ``--pairs`` times (after one warm-up run each that fills the caches),
so load from other jobs falls on both alike. The script must print one JSON object. Prints
JSON: every pair's values of ``--keys``, their medians, and the before/after ratio of each
pair with the median and range over the pairs; ``same_objectives`` compares the scripts'
``objectives_sha256`` (when they print one).
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parents[2]


def run(name: str, checkout: Path, script: list[str]) -> dict[str, object]:
    """One run of ``script`` with ``checkout``'s library first on the path; its JSON."""
    env = dict(os.environ)
    env["PYTHONPATH"] = str(checkout / "mentor_core" / "src")
    env["NUMBA_CACHE_DIR"] = str(Path(tempfile.gettempdir()) / f"mentor-side-by-side-{name}")
    done = subprocess.run(
        [sys.executable, *script], env=env, cwd=HERE, check=True, capture_output=True, text=True
    )
    text = done.stdout
    result: dict[str, object] = json.loads(text[text.index("{") :])
    return result


def main() -> None:
    """Parse the arguments, run the pairs and print JSON."""
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--before", type=Path, required=True, help="checkout of the old code")
    p.add_argument("--pairs", type=int, default=4)
    p.add_argument(
        "--keys", nargs="+",
        default=["seconds_per_generation_workers1", "seconds_experience_gain",
                 "experience_gain_share_workers1", "cpu_seconds_per_generation_workers1",
                 "cpu_seconds_experience_gain", "cpu_experience_gain_share_workers1"],
    )  # fmt: skip
    p.add_argument("script", nargs=argparse.REMAINDER, help="-- script.py [its arguments]")
    args = p.parse_args()
    script = args.script[1:] if args.script[:1] == ["--"] else args.script
    checkouts = {"before": args.before.resolve(), "after": HERE}
    for name, checkout in checkouts.items():
        run(name, checkout, script)  # warm-up: compile into the cache
    pairs = []
    for _ in range(args.pairs):
        pair = {name: run(name, checkout, script) for name, checkout in checkouts.items()}
        pairs.append({
            name: {key: result.get(key) for key in [*args.keys, "objectives_sha256"]}
            for name, result in pair.items()
        })  # fmt: skip
        print(json.dumps(pairs[-1]), file=sys.stderr, flush=True)
    summary: dict[str, object] = {}
    for key in args.keys:
        ratios = [
            float(pair["before"][key]) / float(pair["after"][key])  # type: ignore[arg-type]
            for pair in pairs
        ]
        summary[key] = {
            "before_median": statistics.median(float(p["before"][key]) for p in pairs),  # type: ignore[arg-type]
            "after_median": statistics.median(float(p["after"][key]) for p in pairs),  # type: ignore[arg-type]
            "ratio_before_over_after": ratios,
            "ratio_median": statistics.median(ratios),
            "ratio_range": [min(ratios), max(ratios)],
        }
    same = all(pair["before"]["objectives_sha256"] == pair["after"]["objectives_sha256"]
               for pair in pairs)  # fmt: skip
    print(json.dumps({"pairs": pairs, "summary": summary, "same_objectives": same}, indent=1))


if __name__ == "__main__":
    main()
