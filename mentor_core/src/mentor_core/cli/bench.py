"""``mentor-bench``: evolved planners, classic baselines and the oracle on unseen world families.

    mentor-bench runs/ugv-dual/best_genome.json --robot ugv --out bench/ugv
    mentor-bench a.json b.json --robot swarm --split test --pairs-per-family 40 --out bench/sw
    mentor-bench --robot ugv --families rooms,maze --pairs-per-family 5     # baselines only
    mentor-bench planners/ugv-paper-dual-s1.json --robot ugv --deployment shipped
    mentor-bench planners/swarm-paper-dual-s1.json --robot swarm --deployment shipped \
        --set stages.turn_gain=null                 # as deployed but for the gain on the turn

Runs each genome (as trained, or as ``--deployment`` with ``--set`` on top), the baselines
(``vfh``, ``bug``) and the oracle on the seeded world families of a split (validation by
default; the test split is for reporting only), prints success / SPL per family under the
paper's 50 s and under a limit scaled to each pair's shortest path (a deployment with a scan
map or a collision guard runs each baseline plain, with each and with both too, so that the
part they carry shows), then each evolved planner
head to head with the best baseline per family (``report.head_to_head``) and its paths against
that baseline's on the pairs both reached (``report.path_efficiency``), and with ``--out`` writes
``bench.json`` (format ``mentor-bench``), ``bench.md`` and its figures there; ``mentor-report
--bench bench.json`` includes them in a report.
"""

from __future__ import annotations

import argparse
import functools
import sys
import time
from pathlib import Path
from typing import Any

import matplotlib

from mentor_core.atomic import write_json_atomic, write_text_atomic
from mentor_core.benchmark.contenders import (
    HAND_WRITTEN,
    Contender,
    behind_collision_guard,
    evolved,
    hand_written,
    on_scan_map,
    pursuit_of,
)
from mentor_core.benchmark.document import bench_document, load_bench, settings
from mentor_core.benchmark.parallel import run_parallel
from mentor_core.benchmark.runner import LIMITS, ContenderResult, run_contender
from mentor_core.benchmark.suite import (
    LIMIT_KEYS,
    MAX_PAIRS_PER_FAMILY,
    SPLITS,
    Suite,
    build_suite,
    reference_profile,
    shipped_limits,
)
from mentor_core.cli.arguments import (
    Parser,
    add_deployment_arguments,
    deployment_files,
    deployment_of,
)
from mentor_core.cli.outputs import check_folder
from mentor_core.controller.collision_guard import CollisionGuardStage
from mentor_core.controller.deployment import Deployment
from mentor_core.errors import MentorError, one_line
from mentor_core.report.bench import bench_markdown
from mentor_core.report.head_to_head import baseline_choice, head_to_head_markdown
from mentor_core.report.path_efficiency import efficiency_markdown
from mentor_core.sim.families import FAMILIES
from mentor_core.sim.robots import RobotProfile, get_profile

#: where the baselines' action limits come from (``--baseline-limits``)
LIMIT_SOURCES = ("reference", "shipped")


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of mentor-bench."""
    p = Parser(prog="mentor-bench", description=__doc__.split("\n")[0])
    p.add_argument("genomes", nargs="*", type=Path, help="genome JSON files (best_genome.json)")
    p.add_argument("--robot", required=True, help="robot profile (ugv, swarm)")
    p.add_argument("--split", default="validation", choices=tuple(SPLITS),
                   help="seed split (validation; test only to report)")  # fmt: skip
    p.add_argument("--families", help=f"comma-separated (default all: {','.join(FAMILIES)})")
    p.add_argument("--pairs-per-family", type=int, default=20, help="start/goal pairs (20)")
    p.add_argument("--baselines", default=",".join(n for n, (k, _) in HAND_WRITTEN.items()
                                                   if k == "baseline"),
                   help="comma-separated baselines, or 'none' (default vfh,bug)")  # fmt: skip
    p.add_argument("--baseline-limits", default="auto",
                   help="comma-separated: the action limits the baselines act within, "
                        "'reference' (the benchmark's reference planner's, frozen) and/or "
                        "'shipped' (those of the robot's shipped training config, as its "
                        "shipped planners; named <baseline>-shipped); default 'auto': the "
                        "reference, and the shipped ones too where they differ from it")
    p.add_argument("--no-oracle", action="store_true", help="leave the oracle out")
    add_deployment_arguments(p, "each genome")
    p.add_argument("--pursuit", action="store_true",
                   help="also run a pure pursuit of the goal the networks are shown in their "
                        "place, under the same deployment, as pursuit-<label> (no learning: "
                        "what the network adds); one per distinct planner setting")
    p.add_argument("--label", action="append", help="a label per genome (default: its path)")
    p.add_argument("--out", type=Path,
                   help="write bench.json, bench.md and figures into this new or empty folder")
    p.add_argument("--force", action="store_true",
                   help="write into an --out folder that holds files (an earlier benchmark's); "
                        "never an input's folder or a training run directory")
    p.add_argument("--baselines-chosen-on", type=Path, metavar="BENCH_JSON",
                   help="also hold each planner head to head against the baseline variant "
                        "that was best in each family and column in that run (the "
                        "validation split's, with the same baselines)")
    p.add_argument("--workers", type=int, default=1,
                   help="processes running planners and families side by side (default 1); "
                        "the results are the same for any number")  # fmt: skip
    return p


def _setup(args: argparse.Namespace) -> tuple[Suite, list[Contender]]:
    """The suite and the planners the command line names (in every worker the same);
    MentorError for bad arguments (FileFormatError / ConfigError naming a genome file)."""
    if not 1 <= args.pairs_per_family <= MAX_PAIRS_PER_FAMILY:
        raise MentorError(f"--pairs-per-family must be in 1..{MAX_PAIRS_PER_FAMILY}, got "
                          f"{args.pairs_per_family}")  # fmt: skip
    families = None if args.families is None else [
        f.strip() for f in args.families.split(",") if f.strip()]
    robot = get_profile(args.robot)
    contenders = _contenders(args, robot)
    try:
        suite = build_suite(robot, args.split, families, args.pairs_per_family)
    except ValueError as err:
        raise MentorError(f"--families: {one_line(err)}") from None
    return suite, contenders


def _contenders(args: argparse.Namespace, robot: RobotProfile) -> list[Contender]:
    """The genomes, baselines and oracle the command line names; MentorError (or
    FileFormatError / ConfigError naming the genome file) for bad ones."""
    labels = args.label or [str(g) for g in args.genomes]
    if len(labels) != len(args.genomes):
        raise MentorError("give one --label per genome")
    if len(set(labels)) != len(labels):
        raise MentorError("two planners have the same label; give --label")
    names = [] if args.baselines == "none" else [b for b in args.baselines.split(",") if b]
    for name in names:
        if name not in HAND_WRITTEN or HAND_WRITTEN[name][0] != "baseline":
            known = ", ".join(n for n, (k, _) in HAND_WRITTEN.items() if k == "baseline")
            raise MentorError(f"--baselines: unknown baseline {name!r} (known: {known})")
    reference = reference_profile(robot)
    baselines = [hand_written(n, limits, n + suffix)
                 for suffix, limits in _baseline_limits(args.baseline_limits, robot, reference)
                 for n in names]  # fmt: skip
    if args.pursuit and not args.genomes:
        raise MentorError("--pursuit takes the place of a genome's network: give a genome")
    deployment = deployment_of(args, robot.name)[0]
    genomes = [evolved(path, robot, label, deployment)
               for label, path in zip(labels, args.genomes, strict=True)]  # fmt: skip
    chosen = genomes + (_pursuits(genomes) if args.pursuit else [])
    chosen += _variants(baselines, robot, deployment)
    chosen = chosen if args.no_oracle else [*chosen, hand_written("oracle", reference)]
    if not chosen:
        raise MentorError("nothing to run: give a genome, a baseline or leave the oracle in")
    return chosen


def _pursuits(genomes: list[Contender]) -> list[Contender]:
    """A pure pursuit in the place of each genome whose profile, stages and plan differ from
    an earlier one's (seeds of one config share them: their pursuits would be the same)."""
    seen: set[str] = set()
    chosen = []
    for c in genomes:
        key = repr((settings(c.profile, c.stages), c.guide))
        if key not in seen:
            seen.add(key)
            chosen.append(pursuit_of(c))
    return chosen


def _variants(
    baselines: list[Contender], robot: RobotProfile, deployment: Deployment
) -> list[Contender]:
    """``baselines``, then each behind the deployment's collision guard (if it has one), then
    each of those on its scan map (if it has one), in that order."""
    chosen = list(baselines)
    guards = [s for s in deployment.build() if isinstance(s, CollisionGuardStage)]
    if guards:
        chosen += [behind_collision_guard(c, guards[0]) for c in chosen]
    if deployment.scan_map is not None:
        plan = deployment.scan_map
        chosen += [on_scan_map(c, plan.guide(c.profile)) for c in chosen]
    return chosen


def _baseline_limits(
    text: str, robot: RobotProfile, reference: RobotProfile
) -> list[tuple[str, RobotProfile]]:
    """``(name suffix, limits)`` of each ``--baseline-limits`` source (``auto``: the
    reference, and the shipped limits where any of them differs from it); MentorError for
    an unknown or repeated source, or ``shipped`` for a robot without a shipped config."""
    if text == "auto":
        try:
            shipped = shipped_limits(robot)
        except ValueError:  # a robot without a shipped config
            return [("", reference)]
        differ = any(getattr(shipped, k) != getattr(reference, k) for k in LIMIT_KEYS)
        return [("", reference), ("-shipped", shipped)] if differ else [("", reference)]
    sources = [s.strip() for s in text.split(",") if s.strip()]
    unknown = [s for s in sources if s not in LIMIT_SOURCES]
    if unknown or not sources or len(set(sources)) != len(sources):
        raise MentorError(f"--baseline-limits: expected distinct sources of "
                          f"{', '.join(LIMIT_SOURCES)}, got {text!r}")  # fmt: skip
    if "shipped" not in sources:
        return [("", reference)]
    try:
        shipped = shipped_limits(robot)
    except ValueError as err:
        raise MentorError(f"--baseline-limits shipped: {one_line(err)}") from None
    chosen = {"reference": ("", reference), "shipped": ("-shipped", shipped)}
    return [chosen[s] for s in sources]


def _baseline_choice(
    path: Path | None, robot: str, contenders: list[Contender], families: tuple[str, ...]
) -> dict[str, Any] | None:
    """``bench.json``'s ``baseline_choice`` from the run in ``path`` (None: none);
    FileFormatError naming the file, MentorError when it is of another robot, lacks one of
    ``families`` or names a baseline this run lacks."""
    if path is None:
        return None
    other = load_bench(path)
    if other["robot"] != robot:
        raise MentorError(f"--baselines-chosen-on {path}: a run of {other['robot']!r}, "
                          f"not {robot!r}")  # fmt: skip
    try:
        choice = baseline_choice(other, "paper")
    except ValueError as err:
        raise MentorError(f"--baselines-chosen-on {path}: {one_line(err)}") from None
    absent = [f for f in families if f not in choice]
    if absent:
        raise MentorError(f"--baselines-chosen-on {path}: no {', '.join(absent)} in that run")
    mine = {c.name for c in contenders if c.kind == "baseline"}
    missing = sorted({n for row in choice.values() for n in row.values()} - mine)
    if missing:
        raise MentorError(f"--baselines-chosen-on {path}: its {', '.join(missing)} is not in "
                          "this run (give the same --baselines, --baseline-limits and "
                          "--deployment)")  # fmt: skip
    return {"source": str(path), "split": other["split"], "choice": choice}


def table(results: list[ContenderResult], families: tuple[str, ...], limit: str) -> str:
    """The success / SPL table of one limit, a row per family, a column per planner."""
    width = max(12, *(len(r.contender.name) for r in results))
    lines = [f"{'family':<14}" + "".join(f"{r.contender.name:>{width + 2}}" for r in results)]
    for group in [*families, "overall"]:
        cells = []
        for r in results:
            s = r.scores[limit][group]
            cells.append(f"{s['success']:>{width - 6}.0%} / {s['spl']:.2f}")
        lines.append(f"{group:<14}" + "".join(f"  {c}" for c in cells))
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    """Entry point; returns the exit status (2 on bad input)."""
    args = build_parser().parse_args(argv)
    matplotlib.use("Agg")

    def progress(line: str) -> None:
        print(f"mentor-bench: {line}", file=sys.stderr, flush=True)

    try:
        if args.workers < 1:
            raise MentorError(f"--workers must be >= 1, got {args.workers}")
        if args.out is not None:
            inputs = [*args.genomes, *filter(None, [args.baselines_chosen_on]),
                      *deployment_files(args)]
            check_folder("--out", args.out, inputs, args.force)
        began = time.perf_counter()
        suite, contenders = _setup(args)
        chosen = _baseline_choice(args.baselines_chosen_on, args.robot, contenders,
                                  suite.families)  # fmt: skip
        progress(f"{len(suite.pairs)} pairs of {args.robot} on the {args.split} split in "
                 f"{len({p.scenario.world.name for p in suite.pairs})} worlds "
                 f"({time.perf_counter() - began:.1f} s)")  # fmt: skip
        if args.workers > 1:
            progress(f"{len(contenders)} planners x {len(suite.families)} families on "
                     f"{args.workers} worker processes")  # fmt: skip
            results = run_parallel(functools.partial(_setup, args), args.workers, progress,
                                   built=(suite, contenders))  # fmt: skip
        else:
            results = []
            for k, contender in enumerate(contenders):
                progress(f"[{k + 1}/{len(contenders)}] {contender.name} ({contender.kind})")
                results.append(run_contender(suite, contender, progress))
        for limit in LIMITS:
            title = "50 s" if limit == "paper" else "scaled to the shortest path"
            print(f"success / SPL, {args.robot}, {args.split} split, limit {title}")
            print(table(results, suite.families, limit))
            print()
        doc = bench_document(suite, results, args.pairs_per_family)
        if chosen is not None:
            doc["baseline_choice"] = chosen
        versus = head_to_head_markdown(doc, "paper")
        if versus:
            print(f"head to head with the best baseline, {args.robot}, {args.split} split, "
                  "limit 50 s")
            print("\n".join(versus))
        if versus and chosen is not None:
            print(f"head to head with the baseline best on the {chosen['split']} split "
                  f"({chosen['source']}), limit 50 s")
            print("\n".join(head_to_head_markdown(doc, "paper", chosen["choice"])))
        paths = efficiency_markdown(doc, "paper")
        if paths:
            print(f"paths on the pairs both reached with the baseline of the highest SPL "
                  f"(efficiency · median taken / shortest · detours), {args.robot}, "
                  f"{args.split} split, limit 50 s")
            print("\n".join(paths))
        if args.out is not None:
            args.out.mkdir(parents=True, exist_ok=True)
            md = bench_markdown(doc, args.out, heading="#")
            write_text_atomic(args.out / "bench.md", "\n".join(md))
            write_json_atomic(args.out / "bench.json", doc)
            progress(f"wrote {args.out / 'bench.json'} and {args.out / 'bench.md'}")
    except (MentorError, OSError) as err:
        print(f"mentor-bench: {one_line(err)}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
