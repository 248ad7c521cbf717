"""Pin what every experiment config and robot file in ``benchmarks/configs`` resolves to.

    python benchmarks/tools/pin_configs.py          # write benchmarks/configs/pinned.json
    python benchmarks/tools/pin_configs.py --check  # exit 1 naming each config that moved

An experiment config ``extends`` a shipped config (or another experiment's) and lists its
departures, and so does a robot file of variants (``robots_*.yaml``, ``extends: shipped``),
so a change to a shipped file changes every experiment built on it. The pins (sha256 of
each resolved config or robot profiles) make that change visible: ``tests/test_config.py`` fails
naming the configs that moved. Then either write the old values into those configs (they
train what the experiments in ``benchmarks/experiments/`` measured) or, where the experiment
should follow the new shipped config, pin again with this script.
"""

from __future__ import annotations

import argparse
import dataclasses
import hashlib
import json
import sys
from pathlib import Path

from mentor_core.sim.robots import load_profiles
from mentor_core.training.config import TrainerConfig

CONFIGS = Path(__file__).resolve().parents[1] / "configs"
PINS = CONFIGS / "pinned.json"


def experiment_configs() -> list[Path]:
    """The training configs and robot files (``robots_*.yaml``) of ``benchmarks/configs``."""
    return sorted(CONFIGS.glob("*.yaml"))


def digest(path: Path) -> str:
    """sha256 of what ``path`` resolves to (a config, or a robot file's profiles), as
    canonical JSON."""
    if path.name.startswith("robots_"):
        plain = {k: _set_fields(v) for k, v in load_profiles(path).items()}
    else:
        plain = TrainerConfig.from_yaml(path).to_dict()
    return hashlib.sha256(json.dumps(plain, sort_keys=True, default=repr).encode()).hexdigest()


def _set_fields(profile: object) -> dict[str, object]:
    """A profile's fields but those at their default, so that a new planner setting with a
    default (one a robot file cannot set) moves no pin."""
    assert dataclasses.is_dataclass(profile) and not isinstance(profile, type)
    plain = dataclasses.asdict(profile)
    return {f.name: plain[f.name] for f in dataclasses.fields(profile)
            if f.default is dataclasses.MISSING or plain[f.name] != f.default}  # fmt: skip


def moved() -> list[str]:
    """Names of the configs whose resolved config is not the pinned one (or has no pin)."""
    pins = json.loads(PINS.read_text(encoding="utf-8"))
    return [p.name for p in experiment_configs() if pins.get(p.name) != digest(p)]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--check", action="store_true", help="compare, write nothing")
    args = parser.parse_args(argv)
    if args.check:
        names = moved()
        for name in names:
            print(f"{CONFIGS / name}: resolves to another config than its pin", file=sys.stderr)
        return 1 if names else 0
    pins = {p.name: digest(p) for p in experiment_configs()}
    PINS.write_text(json.dumps(pins, indent=1, sort_keys=True) + "\n", encoding="utf-8")
    print(f"pinned {len(pins)} configs in {PINS}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
