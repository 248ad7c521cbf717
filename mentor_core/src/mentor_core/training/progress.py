"""Progress of a training run: a reporter on the trainer's generation events (``rich``).

On a terminal, :class:`GenerationProgress` draws a live bar (generations done of all, elapsed
and remaining time, the last generation's best/mean F, best G and ranking mode); written to a
log (a file, a pipe, CI) it prints one plain line per generation instead, so that a log holds
the run's history. Like the reporters of ``mentor_core.evolution.reporting`` it only observes:
the trainer calls it after each generation's checkpoint (``train(..., callbacks=[progress])``).
:class:`RefinementLines` prints the refinement's progress after evolution, a line every ten
iterations.
"""

from __future__ import annotations

import math
import sys
from types import TracebackType
from typing import TextIO

from rich.console import Console
from rich.progress import (
    BarColumn,
    MofNCompleteColumn,
    Progress,
    TaskID,
    TextColumn,
    TimeElapsedColumn,
    TimeRemainingColumn,
)

from mentor_core.training.run_files import GenerationRecord

# a generation takes seconds to minutes: estimate the pace over the last hour, not 30 s
_PACE_WINDOW_S = 3600.0


def _gain(rec: GenerationRecord, spec: str) -> str:
    """The best G formatted, or "-" in a generation that does not compute every G."""
    return "-" if math.isnan(rec.best_G) else format(rec.best_G, spec)


def generation_line(rec: GenerationRecord, total: int) -> str:
    """One generation's numbers on one line (what the log gets)."""
    return (
        f"gen {rec.generation + 1:>3}/{total} {rec.mode:<6} evals {rec.evaluations:>6} | "
        f"F best {rec.best_F:8.3f} mean {rec.mean_F:8.3f} | G best {_gain(rec, '9.3f'):>9} | "
        f"species {rec.species:>2} largest {rec.largest_niche_share:4.0%} | "
        f"{rec.seconds:5.1f} s"
    )


class GenerationProgress:
    """A live bar on a terminal, one line per generation otherwise (module docstring).

    Args:
        total: generations of the run.
        stream: where to write (default stderr).
        live: draw the live bar (default: when ``stream`` is a terminal).

    Use it as a context manager, so that the bar is closed when the run ends or fails.
    """

    def __init__(self, total: int, stream: TextIO | None = None, live: bool | None = None):
        self.total = total
        self.stream = sys.stderr if stream is None else stream
        self.live = self.stream.isatty() if live is None else live
        self._progress: Progress | None = None
        self._task: TaskID | None = None

    def __enter__(self) -> GenerationProgress:
        if self.live:
            console = Console(file=self.stream, force_terminal=True)
            self._progress = Progress(
                TextColumn("gen"),
                MofNCompleteColumn(),
                BarColumn(bar_width=16),
                TimeElapsedColumn(),
                TextColumn("eta"),
                TimeRemainingColumn(),
                TextColumn("{task.fields[numbers]}"),
                console=console,
                refresh_per_second=2,
                speed_estimate_period=_PACE_WINDOW_S,
            )
            self._task = self._progress.add_task("train", total=self.total, numbers="")
            self._progress.start()
        return self

    def __exit__(
        self,
        kind: type[BaseException] | None,
        error: BaseException | None,
        trace: TracebackType | None,
    ) -> None:
        if self._progress is not None:
            self._progress.stop()
            self._progress = None

    def __call__(self, rec: GenerationRecord) -> None:
        """Report a finished generation."""
        if self._progress is None or self._task is None:
            print(generation_line(rec, self.total), file=self.stream, flush=True)
            return
        # best/mean F, best G, the ranking: short enough for an 80-column terminal
        numbers = f"F {rec.best_F:.3f}/{rec.mean_F:.3f} G {_gain(rec, '.1f')} {rec.mode}"
        if self._progress.tasks[0].completed < rec.generation:  # a resumed run: start there
            self._progress.reset(self._task, total=self.total, completed=rec.generation)
        self._progress.update(self._task, completed=rec.generation + 1, numbers=numbers)


def refinement_line(iteration: int, total: int, reached: int, credit: float) -> str:
    """One refinement iteration's numbers on one line (``mentor_core.training.refinement``):
    goals reached and path credit on the refinement scenarios."""
    return f"refine {iteration:>4}/{total} | reached {reached:>4} | path credit {credit:9.3f}"


class RefinementLines:
    """Prints :func:`refinement_line` every ``every`` iterations and at the last, to ``stream``
    (default stderr): a ``refine_progress`` for ``train``."""

    def __init__(self, every: int = 10, stream: TextIO | None = None) -> None:
        self.every = every
        self.stream = stream

    def __call__(self, iteration: int, total: int, reached: int, credit: float) -> None:
        if iteration % self.every == 0 or iteration == total:
            line = refinement_line(iteration, total, reached, credit)
            print(line, file=self.stream or sys.stderr, flush=True)


__all__ = ["GenerationProgress", "RefinementLines", "generation_line", "refinement_line"]
