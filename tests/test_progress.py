"""Progress of a training run (issue 17): a live rich bar on a terminal, one line per
generation in a log."""

from __future__ import annotations

import io
from pathlib import Path

import pytest
import yaml

from mentor_core.cli import train as train_cli
from mentor_core.training.progress import GenerationProgress, generation_line
from mentor_core.training.run_files import GenerationRecord


def record(generation: int, best_f: float = 1.5) -> GenerationRecord:
    return GenerationRecord(
        generation=generation, stage=0, mode="multi", evaluations=8 * (generation + 1),
        best_F=best_f, mean_F=0.5, best_G=3.25, mean_G=1.0, species=3,
        largest_niche_share=0.25, niche_sizes={0: 2, 1: 3, 2: 3}, best_success_rate=0.5,
        mean_complexity=1.0, best_complexity=1.0, seconds=0.5,
    )  # fmt: skip


def test_a_log_gets_one_line_per_generation() -> None:
    log = io.StringIO()  # not a terminal
    with GenerationProgress(3, log) as progress:
        for g in range(3):
            progress(record(g))
    lines = log.getvalue().splitlines()
    assert lines == [generation_line(record(g), 3) for g in range(3)]
    assert lines[2].startswith("gen   3/3 multi ") and "F best    1.500" in lines[2]
    assert "\x1b[" not in log.getvalue()  # no terminal control codes in a log


def test_a_terminal_gets_a_live_bar() -> None:
    screen = io.StringIO()
    with GenerationProgress(4, screen, live=True) as progress:
        for g in range(2, 4):  # a resumed run: the bar starts where the run stands
            progress(record(g, best_f=2.0 + g))
    text = screen.getvalue()
    assert "\x1b[" in text  # drawn with terminal control codes, redrawn in place
    assert "4/4" in text and "F 5.000/0.500 G 3.2 multi" in text
    assert generation_line(record(3), 4) not in text  # no log lines on a terminal


def test_mentor_train_reports_each_generation_in_its_log(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    config = tmp_path / "tiny.yaml"
    config.write_text(yaml.safe_dump({
        "generations": 2, "stage1_generations": 1, "n_scenarios": 3,
        "evolution": {"population_size": 8},
    }))  # fmt: skip
    argv = ["--robot", "swarm", "--framework", "dual", "--config", str(config),
            "--out", str(tmp_path / "run")]  # fmt: skip
    assert train_cli.main(argv) == 0
    err = capsys.readouterr().err.splitlines()
    assert [line[:9] for line in err if line.startswith("gen")] == ["gen   1/2", "gen   2/2"]
