"""Write the robot files of the UGV experiments (benchmarks/experiments/) into a folder.

    .venv/bin/python benchmarks/tools/robot_variants.py OUT_DIR

Each file is the shipped robot file with one robot changed, for ``ablation.py --robots FILE``:

* ``ugv_straight.yaml``: the UGV with each sensor pair facing straight out of its edge (the
  paper's layout as the brief reads it: 0, 0, 90, 90, 180, 180, 270, 270 deg);
* ``swarm_x3.yaml``: the Swarm-Robot with every length (body, mounts, range, steps, speed,
  goal radius, arenas) scaled by 3, a robot of the UGV's size;
* ``swarm_x3_ugv_sensors.yaml``: that robot with the UGV's body and its straight pairs, at
  a 1.8 m range (``--profile sensor_range=4.0`` gives the UGV's).
"""

from __future__ import annotations

import argparse
import copy
from pathlib import Path
from typing import Any

import yaml

from mentor_core.sim.robots import shipped_profiles_path

SCALED = ("length", "width", "sensor_range", "step_min", "step_max", "rated_speed",
          "goal_radius", "train_arena", "test_arena")  # fmt: skip


def variants(doc: dict[str, Any]) -> dict[str, dict[str, Any]]:
    """The variant documents by file name, from the shipped robot file's document."""
    straight = copy.deepcopy(doc)
    for mount in straight["robots"]["ugv"]["sensors"]:
        facing = 90.0 * round(mount["angle_deg"] / 90.0)
        mount["angle_deg"] = facing - 360.0 if facing > 180.0 else facing  # as first shipped
    scaled = copy.deepcopy(doc)
    swarm = scaled["robots"]["swarm"]
    for key in SCALED:
        swarm[key] *= 3.0
    for mount in swarm["sensors"]:
        mount["x"] *= 3.0
        mount["y"] *= 3.0
    with_ugv = copy.deepcopy(scaled)
    ugv = straight["robots"]["ugv"]
    with_ugv["robots"]["swarm"].update(
        length=ugv["length"], width=ugv["width"], sensors=copy.deepcopy(ugv["sensors"]),
        sensor_range=1.8,
    )
    return {
        "ugv_straight.yaml": straight,
        "swarm_x3.yaml": scaled,
        "swarm_x3_ugv_sensors.yaml": with_ugv,
    }


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("out", type=Path)
    args = p.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    doc = yaml.safe_load(shipped_profiles_path().read_text(encoding="utf-8"))
    for name, variant in variants(doc).items():
        (args.out / name).write_text(yaml.safe_dump(variant, sort_keys=False), encoding="utf-8")
        print(args.out / name)


if __name__ == "__main__":
    main()
