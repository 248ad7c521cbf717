"""The documents a reader relies on (issue 54): short pages, an experiment log that holds every
experiment with its verdict and command, no path outside the repository, and the quick
commands of the results page running from a clean checkout.
"""

from __future__ import annotations

import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
EXPERIMENTS = ROOT / "benchmarks" / "experiments"
RESULTS = ROOT / "benchmarks" / "RESULTS.md"
#: an absolute path on a developer's machine: a scratch folder, a home, a temporary file
OUTSIDE = re.compile(r"(?<![\w.~-])/(?:work|tmp|root|home)/[\w.-]")
#: what an experiment file holds, in this order
EXPERIMENT_PARTS = ("## Question", "## Settings", "## Result", "## Verdict", "## Command")
QUICK = "<!-- quick:"


def tracked_text_files() -> list[Path]:
    """The repository's tracked text files outside tests/ (all files where git is absent)."""
    try:
        names = subprocess.run(["git", "ls-files"], cwd=ROOT, capture_output=True, text=True,
                               check=True).stdout.split()  # fmt: skip
    except (OSError, subprocess.CalledProcessError):
        names = [str(p.relative_to(ROOT)) for p in ROOT.rglob("*") if p.is_file()]
    binary = (".mcap", ".png", ".pgm", ".db3", ".lock", ".json")
    paths = [ROOT / n for n in names if not n.startswith("tests/") and not n.endswith(binary)]
    return [p for p in paths if p.is_file()]  # a link to a folder (ros2_ws/src) is none


def test_no_document_names_a_path_outside_the_repository() -> None:
    found = []
    for path in tracked_text_files():
        try:
            text = path.read_text(encoding="utf-8")
        except (UnicodeDecodeError, FileNotFoundError):
            continue
        for number, line in enumerate(text.splitlines(), 1):
            if OUTSIDE.search(line):
                found.append(f"{path.relative_to(ROOT)}:{number}: {line.strip()[:80]}")
    assert not found, "\n".join(found)


def test_the_pages_a_newcomer_reads_are_short() -> None:
    assert len((ROOT / "README.md").read_text().splitlines()) <= 150
    assert len(RESULTS.read_text().splitlines()) <= 300


def experiment_files() -> list[Path]:
    return sorted(EXPERIMENTS.glob("E[0-9][0-9][0-9]-*.md"))


def test_every_experiment_has_its_verdict_command_and_scripts() -> None:
    files = experiment_files()
    assert len(files) >= 84
    ids = [p.name[:4] for p in files]
    assert len(set(ids)) == len(ids), "an id is used twice"
    index = (EXPERIMENTS / "README.md").read_text()
    for path in files:
        text = path.read_text()
        assert text.startswith(f"# {path.name[:4]}: "), path.name
        for field in ("- **Date:**", "- **Verdict:**", "- **Scripts:**"):
            assert field in text, f"{path.name}: no {field}"
        places = [text.find(part) for part in EXPERIMENT_PARTS]
        assert -1 not in places and places == sorted(places), f"{path.name}: parts"
        assert f"]({path.name})" in index, f"{path.name} is not in the index"
        for script in re.findall(r"`((?:benchmarks|scripts)/[\w/.-]+\.(?:py|sh))`", text):
            assert (ROOT / script).is_file(), f"{path.name} cites {script}, not in the repository"


def test_code_cites_experiments_that_exist() -> None:
    ids = {p.name[:4] for p in experiment_files()}
    cited = set()
    for path in tracked_text_files():
        if path.suffix in (".py", ".yaml", ".md", ".sh"):
            lines = path.read_text(encoding="utf-8").splitlines()
            for line in lines:  # E402, E501: ruff's codes, not experiments
                if "noqa" not in line and "ruff" not in line:
                    cited |= set(re.findall(r"\bE\d{3}\b", line))
    assert cited and cited <= ids, sorted(cited - ids)


def quick_commands() -> list[str]:
    """The commands of RESULTS.md's blocks marked ``<!-- quick: ... -->``."""
    text = RESULTS.read_text()
    commands = []
    for block in re.findall(re.escape(QUICK) + r"[^>]*-->\s*```bash\n(.*?)```", text, re.S):
        commands += [line for line in block.splitlines() if line and not line.startswith("#")]
    return commands


def test_results_marks_quick_commands() -> None:
    assert len(quick_commands()) >= 2


@pytest.mark.parametrize("command", quick_commands())
def test_a_quick_command_of_the_results_runs_from_the_checkout(command: str) -> None:
    """Run as a reader would, from the repository root with the environment's commands."""
    env = dict(os.environ, PATH=f"{Path(sys.executable).parent}{os.pathsep}{os.environ['PATH']}")
    done = subprocess.run(shlex.split(command), cwd=ROOT, env=env, capture_output=True,
                          text=True, timeout=300)  # fmt: skip
    assert done.returncode == 0, done.stderr[-2000:]
