"""The single-stage and dual-stage MENTOR trainers (paper section III-D).

* single-stage: performance F only, for all generations;
* dual-stage: stage 1 maximises (F, G) with NSGA-II ranking for ``stage1_generations``; stage 2
  maximises F only ("direct rank based proportionate selection" = single-objective ranking),
  starting from the best ``stage2_seed_fraction`` of stage 1's final population by F.

Both frameworks see the same scenarios and the same number of evaluations (population size x
generations), so their histories share one axis. With ``refinement.iterations`` set (not in
the paper), the best genome written at the end is the evolved best with its weights refined
(:mod:`~mentor_core.training.refinement`). A run is a directory (see
:class:`~mentor_core.training.run_files.RunPaths`); a checkpoint is written atomically after
every generation and ``resume`` (``mentor-train --resume``) continues from it, ending identical
to an unbroken run with the same seed. A run directory has one writer at a time
(:mod:`mentor_core.training.run_directory`; ``docs/runs.md``).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import yaml

from mentor_core.atomic import write_json_atomic, write_text_atomic
from mentor_core.errors import FileFormatError, is_version, one_line
from mentor_core.evolution.genome import Genome
from mentor_core.evolution.loop import Evolution, Mode
from mentor_core.files.genome_file import save_genome
from mentor_core.objectives.complexity import flops_ratio
from mentor_core.objectives.novelty import most_novel, sparseness
from mentor_core.sim.robots import RobotProfile, sensor_record
from mentor_core.sim.scenarios import DoEConfig
from mentor_core.training.config import TrainerConfig
from mentor_core.training.config_problems import make_problem, refinement_problem
from mentor_core.training.evaluators import Evaluator, InProcessEvaluator
from mentor_core.training.problem import OBJECTIVE_NAMES, Evaluation, NavigationProblem
from mentor_core.training.refinement import Progress, Refinement, RefinementConfig, refine
from mentor_core.training.run_directory import RunDirectory, open_run
from mentor_core.training.run_files import (
    GenerationRecord,
    RunPaths,
    history_csv,
    history_from_csv,
    load_json,
    pareto_json,
    population_json,
)
from mentor_core.validation import read_yaml, to_plain, yaml_value

CHECKPOINT_FORMAT = "mentor-train-checkpoint"
CHECKPOINT_VERSION = 1
# config keys added after checkpoint version 1 came out, with the value their absence meant
_CONFIG_KEYS_ADDED: dict[str, Any] = {
    "training_worlds": 1, "step_max": None, "step_min": None, "clearance_margin": None,
    "doe": DoEConfig().to_dict(), "families": [], "family_pairs": 5,
    "feedback_action": False, "memory_units": 0, "pair_distances": "paper", "time_budget": None,
    "goal_distance": "euclidean", "turn_commitment": False, "turn_frame": "body",
    "novelty_neighbours": None, "novelty_archive_growth": 5, "success_credit": "time",
    "guide": "none", "guide_share": 1.0, "rotation_shim_deg": None, "control_period": None,
    "proximity_scale": None, "view_margin": None, "refinement": to_plain(RefinementConfig()),
    "second_objective": "experience_gain",
}
# the same for keys of the evolution's mutation and speciation settings
_MUTATION_KEYS_ADDED: dict[str, Any] = {"recurrent_rate": 0.0}
_SPECIATION_KEYS_ADDED: dict[str, Any] = {"merge": False}


def _saved_config(state: dict[str, Any]) -> dict[str, Any]:
    """A checkpoint's config with the keys added since it was written (their old meaning)."""
    saved = {**_CONFIG_KEYS_ADDED, **(state.get("config") or {})}
    evolution = saved.get("evolution")
    if isinstance(evolution, dict):
        for key, added in (("mutation", _MUTATION_KEYS_ADDED),
                           ("speciation", _SPECIATION_KEYS_ADDED)):  # fmt: skip
            if isinstance(evolution.get(key), dict):
                evolution = {**evolution, key: {**added, **evolution[key]}}
        saved["evolution"] = evolution
    return saved


@dataclass(frozen=True)
class TrainResult:
    """What :func:`train` returns: the run directory, its history and the best genome."""

    paths: RunPaths
    history: list[GenerationRecord]
    best_genome: Genome
    best_objectives: tuple[float, float]
    generations_run: int = 0  # by this call (0: the run was finished already)
    rebuilt: tuple[Path, ...] = ()  # final files a finished run lacked, written again


Callback = Callable[[GenerationRecord], None]


class _Run:
    """The mutable state of one training run (kept out of the configs)."""

    def __init__(self, config: TrainerConfig, seed: int, problem: NavigationProblem) -> None:
        self.config = config
        self.seed = seed
        self.problem = problem
        ranked = 2 if config.novelty_neighbours is None else 3  # (F, G) or (F, G, novelty)
        self.evolution = Evolution(
            config.evolution, problem.n_inputs, problem.n_outputs, seed=seed, objectives=ranked
        )
        self.generation = 0
        self.history: list[GenerationRecord] = []
        # behaviours of past generations' most novel genomes (novelty search only)
        self.archive = np.zeros((0, 2 * len(problem.scenarios)), dtype=np.float64)
        self.refine_progress: Progress | None = None
        self.refinement: NavigationProblem | None = None  # its scenarios, when it refines

    def ranked_objectives(
        self, evaluation: Evaluation, mode: Mode, genomes: Sequence[Genome]
    ) -> np.ndarray:
        """What the evolution is told: (F, G), or (F, simplicity) where the config ranks the
        negated complexity beside F (``second_objective``); and with novelty search each
        genome's novelty against the population and the archive, which then takes the most
        novel; where F is ranked alone ("single"), the novelty column is NaN (not computed)
        as G's is."""
        told = evaluation.objectives
        if mode == "multi" and self.config.second_objective == "simplicity":
            told = told.copy()
            told[:, 1] = [-flops_ratio(g) for g in genomes]
        k = self.config.novelty_neighbours
        if k is None:
            return told
        if mode == "single":
            return np.column_stack([told, np.full(len(told), np.nan)])
        novelty = sparseness(evaluation.behaviour, self.archive, k)
        added = evaluation.behaviour[most_novel(novelty, self.config.novelty_archive_growth)]
        self.archive = np.concatenate([self.archive, added], axis=0)
        return np.column_stack([told, novelty])

    def stage_of(self, generation: int) -> tuple[int, Mode, bool]:
        """(stage index, mode, is this the stage's last generation) of a generation."""
        start = 0
        for index, (mode, count) in enumerate(self.config.stages()):
            if generation < start + count:
                return index, mode, generation == start + count - 1
            start += count
        raise IndexError(generation)

    def to_state(self) -> dict[str, Any]:
        return {
            "format": CHECKPOINT_FORMAT,
            "version": CHECKPOINT_VERSION,
            "seed": self.seed,
            "config": self.config.to_dict(),
            "sensors": sensor_record(self.problem.profile),
            "generation": self.generation,
            "evolution": self.evolution.to_state(),
            "history": history_csv(self.history),
            **({"novelty_archive": self.archive.tolist()} if len(self.archive) else {}),
        }

    def load_state(self, state: Any, path: Path) -> None:
        if not isinstance(state, dict) or state.get("format") != CHECKPOINT_FORMAT:
            raise FileFormatError(path, f"not a {CHECKPOINT_FORMAT} file")
        if not is_version(state.get("version"), CHECKPOINT_VERSION):
            raise FileFormatError(path, f"unsupported version {state.get('version')!r}")
        saved = _saved_config(state)
        if saved != self.config.to_dict() or state.get("seed") != self.seed:
            raise FileFormatError(path, "checkpoint was written by a different config or seed")
        sensors = state.get("sensors")  # absent in checkpoints written before the record
        if sensors is not None and sensors != sensor_record(self.problem.profile):
            raise FileFormatError(path, "checkpoint was written with other robot sensors")
        try:
            self.evolution = Evolution.from_state(state["evolution"])
            self.generation = int(state["generation"])
            self.history = history_from_csv(state["history"])
            archive = np.asarray(state.get("novelty_archive", []), dtype=np.float64)
            self.archive = archive.reshape(-1, self.archive.shape[1])
        except (KeyError, TypeError, ValueError) as err:
            raise FileFormatError(path, f"corrupt checkpoint ({one_line(err)})") from None


def train(
    config: TrainerConfig,
    out_dir: str | Path | RunDirectory,
    *,
    seed: int = 0,
    evaluator: Evaluator | None = None,
    resume: bool = False,
    callbacks: Sequence[Callback] = (),
    stop_after: int | None = None,
    refine_progress: Progress | None = None,
    source: str = "trainer config",
    profile: RobotProfile | None = None,
) -> TrainResult:
    """Train a planner; returns when all generations ran (or ``stop_after`` generations).

    Steps per generation: ask the evolution for its population; evaluate it (F, G); tell the
    evolution (ranking by (F, G) in stage 1 of dual-stage, by F otherwise), which speciates,
    sizes the niches and breeds; at the end of dual stage 1, reseed from its best by F;
    record the history row; write the history, after the last generation the final files, and
    the checkpoint, each atomically; call the callbacks. The best genome is refined before it
    is written when the config asks (``refine_progress`` is called after each iteration; the
    refinement's scenarios are drawn before the first generation, and its copies spread over
    ``evaluator``'s workers).

    ``out_dir`` is opened with :func:`~mentor_core.training.run_directory.open_run` (locked
    for the whole run; ``resume`` continues the run in it), unless it is a directory opened
    so already (then with the same ``resume``; the caller closes it). The final files come
    before the final checkpoint, so a run interrupted anywhere completes on ``resume``; a
    finished run is left as it is, and one whose final files are missing (written by an
    older version, or deleted) gets them again from its final checkpoint.

    ``source`` names the config (its file) in the ConfigErrors of its problem and its
    refinement. ``profile`` is the robot's profile the problem and the refinement are drawn
    for, as :func:`make_problem` takes it (default the shipped one); ValueError, before
    anything is written, when the refinement's planner profile is not that of the
    ``evaluator``'s problem (one made with another ``profile``).
    """
    if evaluator is not None:
        problem = evaluator.problem
    else:
        problem = make_problem(config, profile, source=source)
    # before anything is written: it can fail
    refinement = refinement_problem(config, source, profile)
    if refinement is not None and refinement.profile != problem.profile:
        raise ValueError(
            "the refinement's robot profile is not the evaluator's problem's: give train "
            "the profile its problem was made with (profile=), or set refinement.iterations 0"
        )
    if isinstance(out_dir, RunDirectory):
        if out_dir.resume != resume:
            raise ValueError(f"resume={resume} but the run directory was opened otherwise")
        return _train(config, out_dir, seed, problem, evaluator, callbacks, stop_after,
                      refine_progress, refinement)
    with open_run(out_dir, resume=resume) as run_dir:
        return _train(config, run_dir, seed, problem, evaluator, callbacks, stop_after,
                      refine_progress, refinement)


def _train(
    config: TrainerConfig,
    run_dir: RunDirectory,
    seed: int,
    problem: NavigationProblem,
    evaluator: Evaluator | None,
    callbacks: Sequence[Callback],
    stop_after: int | None,
    refine_progress: Progress | None,
    refinement: NavigationProblem | None,
) -> TrainResult:
    """:func:`train` in an opened run directory, with the refinement's scenarios."""
    paths = run_dir.paths
    run = _Run(config, seed, problem)
    run.refine_progress = refine_progress
    run.refinement = refinement
    config_text = yaml.safe_dump({"seed": seed, **config.to_dict()})
    if paths.checkpoint.exists():  # open_run lets only a resume come this far
        run.load_state(load_json(paths.checkpoint), paths.checkpoint)
    elif paths.config.exists():  # stopped before its first checkpoint: start it again
        _check_config_file(paths.config, config_text)
    _write_text_if_changed(paths.config, config_text)
    own_evaluator = evaluator is None
    evaluator = evaluator or InProcessEvaluator(problem)
    total = config.generations
    done = 0
    try:
        while run.generation < total and (stop_after is None or done < stop_after):
            t0 = time.perf_counter()
            stage, mode, stage_end = run.stage_of(run.generation)
            genomes = run.evolution.ask()
            # G where it is ranked or written; a generation ranking F alone needs only its
            # best's (the run's best genome keeps its objectives), the rest would fill the
            # history only and cost more than the simulation
            final = run.generation == total - 1
            evaluation = evaluator.evaluate(genomes, "all" if mode == "multi" or final else "best")
            stats = run.evolution.tell(run.ranked_objectives(evaluation, mode, genomes), mode=mode)
            if stage_end and mode == "multi":
                # stage 1 -> 2: keep the Pareto set, then seed stage 2 from the best by F
                write_json_atomic(paths.pareto, pareto_json(genomes, evaluation, stage))
                keep = max(1, math.ceil(config.stage2_seed_fraction * len(genomes)))
                order = np.argsort(-evaluation.objectives[:, 0], kind="stable")[:keep]
                run.evolution.reseed([genomes[int(i)] for i in order])
            complexity = np.array([flops_ratio(g) for g in genomes])
            best = int(np.argmax(evaluation.objectives[:, 0]))
            sizes = stats.niche_sizes
            record = GenerationRecord(
                generation=run.generation,
                stage=stage,
                mode=mode,
                evaluations=(run.generation + 1) * len(genomes),
                best_F=float(evaluation.objectives[best, 0]),
                mean_F=float(evaluation.objectives[:, 0].mean()),
                best_G=float(evaluation.objectives[:, 1].max()),
                mean_G=float(evaluation.objectives[:, 1].mean()),
                species=len(sizes),
                largest_niche_share=max(sizes.values()) / max(1, sum(sizes.values())),
                niche_sizes=dict(sizes),
                best_success_rate=float(evaluation.success_rate[best]),
                mean_complexity=float(complexity.mean()),
                best_complexity=float(complexity[best]),
                seconds=time.perf_counter() - t0,
            )
            run.history.append(record)
            run.generation += 1
            done += 1
            # everything of this generation before its checkpoint: a run stopped in between
            # runs the generation again on resume and writes the same files again
            write_text_atomic(paths.history, history_csv(run.history))
            if run.generation == total:
                _write_final_files(run, paths, genomes, evaluation, list(stats.labels),
                                   evaluator)
            # compact: several MB a generation, for the trainer to read, not for people
            write_json_atomic(paths.checkpoint, run.to_state(), indent=None)
            for callback in callbacks:
                callback(record)
        rebuilt = _complete(run, paths, evaluator) if run.generation >= total else ()
    except BaseException:
        if own_evaluator:  # interrupted: drop the work not started
            evaluator.terminate()
        raise
    if own_evaluator:
        evaluator.close()

    best_genome, best_obj = run.evolution.best()
    return TrainResult(
        paths=paths,
        history=list(run.history),
        best_genome=best_genome,
        best_objectives=(float(best_obj[0]), float(best_obj[1]) if len(best_obj) > 1 else 0.0),
        generations_run=done,
        rebuilt=rebuilt,
    )


def _write_final_files(
    run: _Run,
    paths: RunPaths,
    genomes: Sequence[Genome],
    evaluation: Evaluation,
    labels: Sequence[int],
    evaluator: Evaluator,
) -> None:
    """The final population (``genomes`` as evaluated), the single-stage Pareto set and the
    best genome with its metadata (refined on ``evaluator``'s workers, if the config asks)."""
    config, profile = run.config, run.problem.profile
    write_json_atomic(paths.population, population_json(genomes, evaluation, labels))
    if config.framework == "single":
        write_json_atomic(paths.pareto, pareto_json(genomes, evaluation, 0))
    best_genome, best_obj = run.evolution.best()
    refined = _refined(run, best_genome, evaluator)
    save_genome(
        best_genome if refined is None else refined.genome,
        paths.best_genome,
        metadata={
            "robot": config.robot,
            # what the network was trained with (the evaluator's problem), for planners
            "input_encoding": profile.input_encoding,
            "heading_change_max": profile.heading_change_max,
            "step_max": profile.step_max,
            "step_min": profile.step_min,
            "clearance_margin": profile.clearance_margin,
            "feedback_action": profile.feedback_action,
            "memory_units": profile.memory_units,
            # only when set, so that a genome without it is written as before
            **({} if config.rotation_shim_deg is None
               else {"rotation_shim": math.radians(config.rotation_shim_deg)}),
            **({} if config.control_period is None
               else {"control_period": profile.control_period}),
            **({} if profile.proximity_scale is None
               else {"proximity_scale": profile.proximity_scale}),
            **({} if config.view_margin is None else {"view_margin": config.view_margin}),
            "sensors": sensor_record(profile),
            "framework": config.framework,
            "seed": run.seed,
            # the evolved genome's; a refined one's weights moved since
            "objectives": dict(zip(OBJECTIVE_NAMES, map(float, best_obj), strict=False)),
            **({} if refined is None else {"refinement": {
                "iterations": config.refinement.iterations,
                "scenarios": config.refinement.scenarios,
                "scenario_seed": config.refinement.scenario_seed,
                **({"families": list(config.refinement.families),
                    "family_pairs": config.refinement.family_pairs}
                   if config.refinement.families else {}),
                "accepted": refined.accepted,
                "reached": [refined.reached_before, refined.reached],
                "path_credit": [refined.credit_before, refined.credit],
            }}),
        },
    )


#: the refinement's random stream, apart from the evolution's (same run seed)
_REFINEMENT_STREAM = 1


def _refined(run: _Run, genome: Genome, evaluator: Evaluator) -> Refinement | None:
    """``genome`` refined as the run's config asks (None when it does not), on the run's
    refinement scenarios with the run's seed, each iteration's copies spread over
    ``evaluator``'s workers."""
    if run.refinement is None:
        return None
    rng = np.random.default_rng((run.seed, _REFINEMENT_STREAM))
    return refine(genome, run.refinement, run.config.refinement, rng, run.refine_progress,
                  run.config.evolution.mutation, evaluator.map_chunks)


def _complete(run: _Run, paths: RunPaths, evaluator: Evaluator) -> tuple[Path, ...]:
    """Write what a finished run lacks (a history without its last rows, missing final files:
    a run stopped in its final writes by an older version, or files deleted since); returns
    the files written. The final population is evaluated again for its success and collision
    rates, which the checkpoint does not hold; its objectives must come out as it holds them.
    """
    rebuilt = []
    if _write_text_if_changed(paths.history, history_csv(run.history)):
        rebuilt.append(paths.history)
    finals = [paths.population, paths.best_genome]
    finals += [paths.pareto] if run.config.framework == "single" else []
    missing = [p for p in finals if not p.exists()]
    if missing:
        genomes, labels = run.evolution.evaluated_population, run.evolution.labels
        evaluation = evaluator.evaluate(genomes)
        saved = run.evolution.evaluated_objectives
        if labels is None or saved is None or not np.array_equal(evaluation.objectives, saved):
            raise FileFormatError(
                paths.checkpoint,
                "its final population evaluates otherwise now; cannot write "
                f"{', '.join(p.name for p in missing)} again",
            )
        _write_final_files(run, paths, genomes, evaluation, labels.tolist(), evaluator)
        rebuilt += missing
    return tuple(rebuilt)


def _check_config_file(path: Path, expected_text: str) -> None:
    """Refuse to start again a run whose ``config.yaml`` names another config or seed."""
    saved = read_yaml(path)
    if not isinstance(saved, dict) or {**_CONFIG_KEYS_ADDED, **saved} != yaml_value(
        expected_text
    ):
        raise FileFormatError(path, "was written by a run of a different config or seed")


def _write_text_if_changed(path: Path, text: str) -> bool:
    """Write ``text`` to ``path`` atomically unless it holds it already; whether it wrote."""
    try:
        if path.read_text(encoding="utf-8") == text:
            return False
    except (FileNotFoundError, UnicodeDecodeError):
        pass
    write_text_atomic(path, text)
    return True


__all__ = ["Callback", "TrainResult", "make_problem", "refinement_problem", "train"]
