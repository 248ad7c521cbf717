"""``mentor-train``: train a MENTOR planner (single- or dual-stage) into a run directory.

    mentor-train --robot swarm --framework dual --config quick --seed 1 --out runs/swarm-dual
    mentor-train ... --resume          # continue a stopped run; ends identical to an unbroken one
    mentor-train ... --workers 2       # local process pool (workers die with the run)
    mentor-train ... --ray local       # a private local Ray; --ray auto or HOST:PORT: a cluster

``--config`` takes a YAML file or the name of a shipped config (``quick``, ``paper``). A run
directory's ``config.yaml`` is such a file, with the run's seed: ``mentor-train --robot R
--framework F --config runs/x/config.yaml --out runs/y`` trains run x again (``--seed``
overrides the seed). ``--set KEY=VALUE`` (repeatable) changes one key of the config on top,
a dotted key path and a YAML value: ``--set n_scenarios=40 --set
evolution.mutation.recurrent_rate=0.05``; the run's ``config.yaml`` records the result.
``mentor-train --print-schema`` prints the JSON schema of a config file
(for editors and CI checks). Progress: a live bar on a terminal, one line per generation in a
log (stderr not a terminal).
"""

from __future__ import annotations

import argparse
import contextlib
import json
import sys
from collections.abc import Sequence
from pathlib import Path

from mentor_core.cli.arguments import Parser, fail, seed
from mentor_core.cli.stopping import EXIT_SIGTERM, Terminated, sigterm_raises
from mentor_core.errors import MentorError
from mentor_core.training.config import (
    SHIPPED,
    TrainerConfig,
    config_schema,
    load_config_file,
    shipped_config,
    with_overrides,
)
from mentor_core.training.evaluators import make_evaluator
from mentor_core.training.memory_bound import check_memory
from mentor_core.training.progress import GenerationProgress, RefinementLines
from mentor_core.training.run_directory import open_run
from mentor_core.training.trainer import make_problem, train


def resolve_config(
    robot: str, framework: str, config: str | None, overrides: Sequence[str] = ()
) -> TrainerConfig:
    """The config a command line asks for, with --set, --robot and --framework applied."""
    return resolve_run(robot, framework, config, overrides)[0]


def resolve_run(
    robot: str, framework: str, config: str | None, overrides: Sequence[str] = ()
) -> tuple[TrainerConfig, int | None]:
    """:func:`resolve_config` and the seed the config file names (a run's ``config.yaml``
    does), else None."""
    name = config or "paper"
    seed = None
    if name in SHIPPED:
        base = shipped_config(robot, name)
    else:
        base, seed = load_config_file(Path(name), robot)
    data = with_overrides(base.to_dict(), overrides)
    data.update(robot=robot, framework=framework)
    source = f"{name} with --set" if overrides else name
    return TrainerConfig.from_dict(data, source=source), seed


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of mentor-train."""
    p = Parser(prog="mentor-train", description=__doc__.split("\n")[0])
    p.add_argument("--robot", choices=("ugv", "swarm"), help="robot profile (required)")
    p.add_argument("--framework", choices=("single", "dual"), help="(required)")
    p.add_argument("--config", help="YAML file or shipped name: quick | paper | original "
                   "(default paper)")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", dest="overrides",
                   help="change one config key on top of --config (repeatable): a dotted key "
                        "path and a YAML value, e.g. --set evolution.mutation.recurrent_rate=0.05")
    p.add_argument("--seed", type=seed, default=None,
                   help="evolution seed, >= 0 (default: the config file's seed, as in a run's "
                        "config.yaml, else 0)")
    p.add_argument("--out", type=Path, help="run directory (required)")
    p.add_argument("--resume", action="store_true",
                   help="continue the run in --out (stopped anywhere: ends as an unbroken run; "
                        "docs/runs.md)")
    p.add_argument("--workers", type=int, default=None,
                   help="local worker processes (default: in process); with --ray, the CPUs "
                        "of a local Ray and the chunks per generation (default: all)")
    p.add_argument("--ray", metavar="ADDRESS",
                   help="evaluate on Ray: 'local' (a private Ray on this machine), 'auto' (join "
                        "the running cluster, as Ray finds it) or HOST:PORT (join that cluster)")
    p.add_argument("--quiet", action="store_true", help="no progress bar or lines")
    p.add_argument("--print-schema", action="store_true",
                   help="print the JSON schema of a config file on stdout and exit")
    return p


def main(argv: list[str] | None = None) -> int:
    """Entry point; returns the exit status."""
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.print_schema:
        print(json.dumps(config_schema(), indent=2))
        return 0
    missing = [f"--{k}" for k in ("robot", "framework", "out") if getattr(args, k) is None]
    if missing:
        parser.error(f"the following arguments are required: {', '.join(missing)}")
    with sigterm_raises():
        return _run(args)


def _stopped(args: argparse.Namespace) -> str:
    """What an interrupted run stopped besides itself, for its last line."""
    if args.ray == "local":
        return "; the local Ray shut down"
    if args.ray:
        return "; left the Ray cluster"
    return "; worker processes stopped" if (args.workers or 0) > 1 else ""


def _run(args: argparse.Namespace) -> int:
    opened = False  # the run directory is ours: a fault from here on leaves a run to resume
    try:
        config, saved_seed = resolve_run(args.robot, args.framework, args.config, args.overrides)
        if args.seed is None:
            args.seed = 0 if saved_seed is None else saved_seed
        source = args.config or "paper"
        problem = make_problem(config, source=source)
        check_memory(config.evolution.population_size, len(problem.scenarios),
                     f"{source} with --set" if args.overrides else source)  # fmt: skip
        # the run directory first: a second writer is refused before any worker starts
        with open_run(args.out, resume=args.resume) as run_dir:
            opened = True
            print(
                f"mentor-train: {config.robot} {config.framework}-stage, "
                f"{config.evolution.population_size} genomes x {config.generations} "
                f"generations, {len(problem.scenarios)} scenarios, seed {args.seed} -> "
                f"{args.out}",
                file=sys.stderr,
            )
            with (
                make_evaluator(problem, args.workers, args.ray) as evaluator,
                contextlib.ExitStack() as stack,
            ):
                if args.ray:
                    print(f"mentor-train: evaluating on {evaluator.describe()}", file=sys.stderr)
                progress = GenerationProgress(config.generations)
                result = train(
                    config,
                    run_dir,
                    seed=args.seed,
                    evaluator=evaluator,
                    resume=args.resume,
                    callbacks=[] if args.quiet else [stack.enter_context(progress)],
                    refine_progress=None if args.quiet else RefinementLines(),
                    source=source,
                )
    except KeyboardInterrupt as stop:
        how = "terminated (SIGTERM)" if isinstance(stop, Terminated) else "interrupted"
        then = (f"continue with --resume --out {args.out}" if opened
                else "before the run started; nothing written")  # fmt: skip
        print(f"mentor-train: {how}{_stopped(args)}; {then}", file=sys.stderr)
        return EXIT_SIGTERM if isinstance(stop, Terminated) else 130
    except OSError as err:  # a full disk, a folder made read-only: the files so far are whole
        resume = f"; continue the run with --resume --out {args.out}" if opened else ""
        return fail("mentor-train", f"{err}{resume}")
    except MentorError as err:
        return fail("mentor-train", err)
    if result.rebuilt:
        names = ", ".join(p.name for p in result.rebuilt)
        print(f"mentor-train: wrote the finished run's {names} again", file=sys.stderr)
    elif result.generations_run == 0:
        print(f"mentor-train: {args.out} holds a finished run; nothing to do", file=sys.stderr)
    f, g = result.best_objectives
    # F and G are the evolved genome's; the refined one's goals and path credit are in its
    # metadata and the refine lines
    refined = " as evolved, its weights refined since" if config.refinement.iterations else ""
    print(f"mentor-train: best F {f:.3f} (G {g:.3f}){refined}; genome "
          f"{result.paths.best_genome}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
