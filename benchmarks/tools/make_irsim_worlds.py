"""Draw the IR-SIM worlds of issue 59 from their seeds and write them as YAML.

    python benchmarks/tools/make_irsim_worlds.py --out benchmarks/irsim_worlds

Every world of both robots on both splits (:mod:`mentor_core.irsim.worlds`: three static
families, six dynamic ones; 60 static and 90 dynamic test pairs a robot, 15 and 30 on the
validation split) as ``OUT/SPLIT/ROBOT-FAMILY-INDEX.yaml``. The same seeds give the same
files; ``--check`` only compares them with those written (exit 1 when one differs).
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from pathlib import Path

import yaml

from mentor_core.irsim.world_file import SPLITS
from mentor_core.irsim.worlds import ROBOT_CODES, make_world, world_names


class _Dumper(yaml.SafeDumper):
    """Blocks, with lists of numbers, shapes and agents in flow style (one line each)."""


def _mapping(dumper: yaml.SafeDumper, data: dict) -> yaml.Node:
    flow = "shape" in data
    return dumper.represent_mapping("tag:yaml.org,2002:map", data, flow_style=flow or None)


_Dumper.add_representer(dict, _mapping)


def render(document: dict) -> str:
    """A world's YAML text (:class:`_Dumper`)."""
    return yaml.dump(document, Dumper=_Dumper, sort_keys=False, default_flow_style=None,
                     width=99)


def main(argv: Sequence[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--out", type=Path, default=Path("benchmarks/irsim_worlds"))
    p.add_argument("--robots", default=",".join(ROBOT_CODES))
    p.add_argument("--check", action="store_true", help="compare, do not write")
    args = p.parse_args(argv)
    differ = 0
    for robot in args.robots.split(","):
        for split in SPLITS:
            for family, index in world_names(robot, split):
                path = args.out / split / f"{robot}-{family}-{index}.yaml"
                text = render(make_world(robot, family, split, index))
                if args.check:
                    same = path.is_file() and path.read_text() == text
                    differ += not same
                    print(f"{path}: {'same' if same else 'DIFFERS'}", flush=True)
                    continue
                path.parent.mkdir(parents=True, exist_ok=True)
                path.write_text(text)
                print(f"wrote {path}", flush=True)
    return 1 if differ else 0


if __name__ == "__main__":
    sys.exit(main())
