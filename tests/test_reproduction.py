"""The reproduction page (mentor-report --paper): the claims' verdicts on synthetic studies
whose answer is known, the Mann-Whitney test against its exact value, and the command's
outputs and refusals."""

from __future__ import annotations

import csv
from pathlib import Path

import pytest
from test_report import _assert_png, make_eval, make_run

from mentor_core.cli.report import main as report_main
from mentor_core.errors import FileFormatError
from mentor_core.report.paper_claims import CLAIMS, Claim
from mentor_core.report.reproduction import PAGE_TITLE, compared_configs, write_reproduction
from mentor_core.report.significance import compare, directed_verdict
from mentor_core.report.study import load_study

SEEDS = (1, 2, 3, 4)


def _scale_best_f(run: Path, factor: float) -> None:
    """Multiply a run's best F in every generation by ``factor``."""
    path = run / "history.csv"
    with path.open(newline="", encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    for row in rows:
        row["best_F"] = str(float(row["best_F"]) * factor)
    with path.open("w", newline="", encoding="utf-8") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]), lineterminator="\n")
        writer.writeheader()
        writer.writerows(rows)


def make_study(root: Path, single_factor: float = 1.0, dominant: bool = False) -> Path:
    """A study folder of UGV runs under config ``original``, 4 seeds a framework, the single
    stage's best F scaled by ``single_factor``; and their unseen evaluation."""
    for framework in ("single", "dual"):
        for seed in SEEDS:
            run = make_run(root / "original", f"ugv-{framework}-s{seed}", framework=framework,
                           seed=seed, dominant=dominant)  # fmt: skip
            if framework == "single":
                _scale_best_f(run, single_factor)
    labels = [(f"original-{fw}-s{s}", root / "g.json") for fw in ("single", "dual") for s in SEEDS]
    make_eval(root / "eval_unseen_ugv.json", labels)
    return root


def _claim(where: str, text: str) -> Claim:
    return next(c for c in CLAIMS if c.where == where and text in c.paper)


def test_mann_whitney_matches_its_exact_value_and_the_verdict_follows_the_direction() -> None:
    # five seeds a side, fully separated: the exact two-sided p is 2 / C(10, 5) = 2 / 252
    high, low = [5.0, 6.0, 7.0, 8.0, 9.0], [1.0, 2.0, 3.0, 4.0, 4.5]
    c = compare(high, low)
    assert c.p == pytest.approx(2 / 252)
    assert directed_verdict(c, a_higher=True) == "holds"
    assert directed_verdict(c, a_higher=False) == "fails"
    assert directed_verdict(compare(high, [5.5, 6.5, 7.5, 8.5, 9.5])) == "not shown"
    assert directed_verdict(compare([1.0], low)) == "cannot be tested"
    assert compare([2.0, 2.0], [2.0, 2.0]).p == 1.0


@pytest.mark.parametrize(("factor", "verdict"), [(3.0, "holds"), (0.3, "fails"),
                                                  (1.0, "not shown")])  # fmt: skip
def test_the_single_stage_ends_higher_only_when_its_seeds_do(
    tmp_path: Path, factor: float, verdict: str
) -> None:
    study = load_study(make_study(tmp_path, single_factor=factor))
    claim = _claim("Fig. 8", "eventually outperforms")
    finding = claim.check(study, "original")
    assert finding.verdict == verdict, finding.text
    assert "single" in finding.text and "p = " in finding.text


def test_niche_sizes_are_judged_against_the_papers_range(tmp_path: Path) -> None:
    # the synthetic niches: 4-8 even species, or one holding 18 of 24 genomes
    even = load_study(make_study(tmp_path / "even"))
    dominant = load_study(make_study(tmp_path / "dominant", dominant=True))
    dual = _claim("Fig. 9", "largest niche")
    assert dual.check(even, "original").verdict == "holds"  # a median near 27 %
    assert dual.check(dominant, "original").verdict == "fails"  # above 35 %
    assert "median 75 ± 0 %" in dual.check(dominant, "original").text  # 18 of 24


def test_a_claim_without_its_runs_cannot_be_tested(tmp_path: Path) -> None:
    study = load_study(make_study(tmp_path))
    for claim in CLAIMS:
        if claim.robot == "swarm":
            assert claim.check(study, "original").verdict == "cannot be tested", claim.paper


def test_the_unseen_claims_read_the_study_evaluation(tmp_path: Path) -> None:
    study = load_study(make_study(tmp_path))
    finding = _claim("Sec. IV-D", "both fail").check(study, "original")
    # make_eval: the genomes reach 2 or 3 of their 5 pairs, above the paper's "at most 2 of 10"
    reached = {
        fw: [sum(r.reached for r in x.results) for x in study.unseen_runs("original", "ugv", fw)]
        for fw in ("single", "dual")
    }
    assert all(len(v) == len(SEEDS) and set(v) <= {2, 3} for v in reached.values())
    assert finding.text.startswith(f"single {sum(reached['single']) / len(SEEDS):.1f} ± ")
    assert finding.verdict == "fails"


def test_the_page_holds_every_claim_and_links_figures_that_exist(tmp_path: Path) -> None:
    page = write_reproduction(make_study(tmp_path / "study", single_factor=3.0),
                              tmp_path / "docs" / "reproduction.md")  # fmt: skip
    text = page.read_text(encoding="utf-8")
    assert text.startswith(PAGE_TITLE + "\n")
    claims = text.split("## Every claim")[1].split("\n## ")[0]
    table = [line for line in claims.splitlines() if line.startswith("| ")]
    assert len(table) == 1 + len(CLAIMS)
    links = [x.split("](")[1].rstrip(")") for x in text.splitlines() if x.startswith("![")]
    assert [Path(x).name[:5] for x in links] == [f"fig{n:02d}" for n in range(7, 13)]
    for link in links:
        _assert_png(page.parent / link)


def test_a_config_trained_in_one_framework_has_no_column(tmp_path: Path) -> None:
    study = make_study(tmp_path / "study")
    make_run(study / "simplicity", "ugv-dual-s1", framework="dual", seed=1)
    make_run(study / "simplicity", "ugv-dual-s2", framework="dual", seed=2)
    loaded = load_study(study)
    assert loaded.configs == ["original", "simplicity"]
    assert compared_configs(loaded) == ["original"]
    text = write_reproduction(study, tmp_path / "page.md").read_text(encoding="utf-8")
    claims = text.split("## Every claim")[1].split("\n## ")[0]
    assert "`original`" in claims and "`simplicity`" not in claims
    assert "| `simplicity` | UGV | dual | 1, 2 |" in text  # listed with the study's runs


def test_cli_writes_the_page_and_refuses_what_it_cannot_do(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    study = make_study(tmp_path / "study")
    page = tmp_path / "docs" / "reproduction.md"
    assert report_main(["--paper", str(study), "--out", str(page)]) == 0
    before = page.read_bytes()
    # an existing page is kept without --force; replaced with it
    assert report_main(["--paper", str(study), "--out", str(page)]) == 2
    assert "already exists" in capsys.readouterr().err
    assert page.read_bytes() == before
    assert report_main(["--paper", str(study), "--out", str(page), "--force"]) == 0
    capsys.readouterr()
    # inside the study folder, beside its runs (as scripts/study.sh writes it): yes; inside a
    # run directory, an input: no
    inside = study / "report" / "reproduction.md"
    assert report_main(["--paper", str(study), "--out", str(inside)]) == 0 and inside.is_file()
    run = study / "original" / "ugv-dual-s1" / "page.md"
    assert report_main(["--paper", str(study), "--out", str(run)]) == 2 and not run.exists()
    capsys.readouterr()
    empty = tmp_path / "empty"
    empty.mkdir()
    assert report_main(["--paper", str(empty), "--out", str(tmp_path / "x.md")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and str(empty) in err[0] and "no finished run" in err[0]
    with pytest.raises(SystemExit):
        report_main(["--paper", str(study), "--out", str(tmp_path / "folder")])
    with pytest.raises(SystemExit):
        report_main(["--paper", str(study), str(study / "original" / "ugv-dual-s1"),
                     "--out", str(tmp_path / "y.md")])  # fmt: skip


def test_a_missing_study_folder_is_named(tmp_path: Path) -> None:
    with pytest.raises(FileFormatError, match="no such study folder"):
        load_study(tmp_path / "nowhere")
