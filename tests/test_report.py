"""mentor_core.report: figures and report.md from synthetic runs and evaluations; bad input."""

from __future__ import annotations

import csv
import io
import itertools
import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml
from matplotlib.figure import Figure
from matplotlib.image import imread

from mentor_core.cli.report import main as report_main
from mentor_core.errors import ConfigError, FileFormatError
from mentor_core.evolution.genome import ConnectionGene, Genome, NodeGene, genome_from_edges
from mentor_core.evolution.genome_codec import genome_to_dict
from mentor_core.files.genome_file import save_genome
from mentor_core.report.figures import (
    complexity_bins,
    niche_share_matrix,
    node_labels,
    node_layers,
    pareto_front,
    topology,
)
from mentor_core.report.markdown import write_report
from mentor_core.report.runs import load_eval, load_run, read_history
from mentor_core.training.run_files import HISTORY_FIELDS, GenerationRecord

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"
N_RAYS = 8
N_IN = N_RAYS + 3  # rays, dX, dY, heading


def make_genome(rng: np.random.Generator, hidden: int = 3) -> Genome:
    """An UGV-shaped genome: 11 inputs, bias, 2 outputs, a chain of hidden nodes."""
    bias, outs = N_IN, (N_IN + 1, N_IN + 2)
    nodes = [NodeGene(i, "input", "identity") for i in range(N_IN)]
    nodes += [NodeGene(bias, "bias", "identity")]
    nodes += [NodeGene(o, "output", "sigmoid") for o in outs]
    hid = list(range(N_IN + 3, N_IN + 3 + hidden))
    nodes += [NodeGene(h, "hidden", "sigmoid") for h in hid]
    edges = [(i, o) for i in range(N_IN + 1) for o in outs]
    if hid:
        edges += [(0, hid[0]), (N_IN - 3, hid[0]), (hid[-1], outs[0]), (hid[-1], outs[1])]
        edges += [*itertools.pairwise(hid), (1, hid[-1])]
    conns = [
        ConnectionGene(k, a, b, float(rng.normal(0.0, 1.5)), enabled=k % 7 != 3)
        for k, (a, b) in enumerate(edges)
    ]
    return Genome(N_IN, 2, tuple(nodes), tuple(conns))


def make_history(
    framework: str, generations: int, pop: int, rng: np.random.Generator, dominant: bool = False
) -> list[GenerationRecord]:
    records = []
    stage1 = generations // 2 if framework == "dual" else generations
    best = 0.2
    for g in range(generations):
        best = min(2.0, best + abs(rng.normal(0.06, 0.04)))
        n_species = int(np.clip(4 + g // 3, 4, 8))
        weights = rng.dirichlet(np.full(n_species, 30.0))
        if dominant:
            weights = np.r_[0.6, np.full(n_species - 1, 0.4 / (n_species - 1))]
        sizes = np.floor(weights * pop).astype(int)
        sizes[0] += pop - sizes.sum()
        niche = {int(s + g // 4): int(n) for s, n in enumerate(sizes) if n > 0}
        records.append(
            GenerationRecord(
                generation=g,
                stage=0 if g < stage1 else 1,
                mode="multi" if framework == "dual" and g < stage1 else "single",
                evaluations=(g + 1) * pop,
                best_F=best,
                mean_F=best * 0.55,
                best_G=10.0 + g,
                mean_G=5.0 + 0.5 * g,
                species=len(niche),
                largest_niche_share=max(niche.values()) / pop,
                niche_sizes=niche,
                best_success_rate=min(1.0, best / 2.0),
                mean_complexity=1.0 + 0.02 * g,
                best_complexity=1.1 + 0.03 * g,
                seconds=0.5,
            )
        )
    return records


def write_history(path: Path, records: list[GenerationRecord]) -> None:
    buf = io.StringIO()
    writer = csv.DictWriter(buf, fieldnames=list(HISTORY_FIELDS), lineterminator="\n")
    writer.writeheader()
    for r in records:
        writer.writerow(r.row())
    path.write_text(buf.getvalue(), encoding="utf-8")


def make_run(
    root: Path,
    name: str,
    robot: str = "ugv",
    framework: str = "dual",
    seed: int = 0,
    generations: int = 12,
    pop: int = 24,
    finished: bool = True,
    dominant: bool = False,
) -> Path:
    """A run directory laid out as mentor_core.training.trainer.train leaves it."""
    rng = np.random.default_rng(seed + (100 if framework == "dual" else 0))
    run = root / name
    run.mkdir(parents=True)
    config = {"seed": seed, "robot": robot, "framework": framework, "generations": generations}
    config["stage1_generations"] = generations // 2
    (run / "config.yaml").write_text(yaml.safe_dump(config), encoding="utf-8")
    write_history(run / "history.csv", make_history(framework, generations, pop, rng, dominant))
    if not finished:
        return run
    genomes = [make_genome(rng, hidden=int(rng.integers(0, 4))) for _ in range(pop)]
    f = rng.uniform(0.2, 1.8, pop)
    g = rng.uniform(2.0, 30.0, pop)
    members: list[dict[str, Any]] = [
        {
            "genome": genome_to_dict(gen),
            "objectives": {"performance": float(f[i]), "experience_gain": float(g[i])},
            "success_rate": float(f[i] / 2),
            "collision_rate": 0.1,
            "species": i % 3,
            "complexity": 1.0 + 0.1 * len(gen.hidden_nodes) + float(rng.uniform(0, 0.05)),
        }
        for i, gen in enumerate(genomes)
    ]
    population = {"format": "mentor-population", "version": 1, "members": members}
    (run / "population.json").write_text(json.dumps(population), encoding="utf-8")
    points = np.c_[f, g]
    front = [
        i
        for i in range(pop)
        if not any(np.all(points[j] >= points[i]) and np.any(points[j] > points[i])
                   for j in range(pop))
    ]  # fmt: skip
    pareto = {
        "format": "mentor-pareto",
        "version": 1,
        "stage": 0,
        "objectives": ["performance", "experience_gain"],
        "points": points.tolist(),
        "front": front,
        "genomes": [genome_to_dict(genomes[i]) for i in front],
    }
    (run / "pareto.json").write_text(json.dumps(pareto), encoding="utf-8")
    meta = {"robot": robot, "framework": framework, "seed": seed}
    save_genome(make_genome(rng, hidden=3), run / "best_genome.json", meta)
    return run


def make_eval(path: Path, genome_paths: list[tuple[str, Path]], seed: int = 0) -> Path:
    """A mentor-eval document: 12 m arena, 3 boxes, 5 start/goal pairs."""
    rng = np.random.default_rng(seed)
    obstacles = [[3.0, 3.0, 5.0, 4.0], [7.0, 6.0, 8.0, 9.0], [2.0, 8.0, 4.0, 10.5]]
    starts = [[1.0, 1.0, 0.0], [11.0, 1.0, 2.0], [1.0, 6.0, 0.0], [6.0, 11.0, -1.5],
              [10.0, 10.0, 3.0]]  # fmt: skip
    goals = [[10.0, 11.0], [1.0, 11.0], [11.0, 5.0], [6.0, 1.0], [2.0, 2.0]]
    runs = []
    for k, (label, gpath) in enumerate(genome_paths):
        results = []
        for s, (st, gl) in enumerate(zip(starts, goals, strict=True)):
            outcome = ("reached", "collided", "timed_out")[(s + k) % 3 if s != 0 else 0]
            end = (
                np.array(gl)
                if outcome == "reached"
                else np.array(st[:2]) * 0.4 + 0.6 * np.array(gl)
            )
            n = 30
            t = np.linspace(0, 1, n)[:, None]
            xy = (1 - t) * np.array(st[:2]) + t * end
            xy += np.sin(np.pi * t) * rng.normal(0, 0.8, 2)
            if outcome == "timed_out":
                xy = np.r_[xy, xy[-1] + np.cumsum(rng.normal(0, 0.15, (20, 2)), axis=0)]
            theta = np.r_[np.arctan2(np.diff(xy[:, 1]), np.diff(xy[:, 0])), 0.0]
            results.append({
                "scenario": s, "reached": outcome == "reached",
                "collided": outcome == "collided", "timed_out": outcome == "timed_out",
                "time": 10.0 + s if outcome == "reached" else 50.0,
                "final_distance": float(np.hypot(*(xy[-1] - np.array(gl)))),
                "trajectory": np.c_[xy, theta].tolist(),
            })  # fmt: skip
        reached = [r for r in results if r["reached"]]
        runs.append({
            "genome": label, "path": str(gpath), "results": results,
            "summary": {
                "success_rate": len(reached) / len(results),
                "collision_rate": sum(r["collided"] for r in results) / len(results),
                "survivability": 1 - sum(r["collided"] for r in results) / len(results),
                "mean_time_reached": float(np.mean([r["time"] for r in reached]))
                if reached else None,
            },
        })  # fmt: skip
    doc = {
        "format": "mentor-eval", "version": 1, "robot": "ugv",
        "source": "bags/unseen/ugv.mcap-dir",
        "world": {"size": 12.0, "obstacles": obstacles},
        "scenarios": [{"start": s, "goal": g} for s, g in zip(starts, goals, strict=True)],
        "goal_radius": 1.0, "time_limit": 50.0, "runs": runs,
    }  # fmt: skip
    path.write_text(json.dumps(doc), encoding="utf-8")
    return path


@pytest.fixture
def runs(tmp_path: Path) -> list[Path]:
    root = tmp_path / "runs"
    return [
        make_run(root, "ugv-single-s0", framework="single", seed=0),
        make_run(root, "ugv-single-s1", framework="single", seed=1),
        make_run(root, "ugv-dual-s0", framework="dual", seed=0),
        make_run(root, "ugv-dual-s1", framework="dual", seed=1, dominant=True),
    ]


def _assert_png(path: Path) -> None:
    assert path.read_bytes()[:8] == PNG_MAGIC, path
    image = imread(path)
    assert image.ndim == 3 and image.shape[0] > 100 and image.shape[1] > 100


def test_write_report_writes_every_figure_and_the_numbers(
    tmp_path: Path, runs: list[Path]
) -> None:
    unfinished = make_run(tmp_path / "runs", "ugv-dual-s2", seed=2, finished=False)
    ev = make_eval(tmp_path / "eval.json", [(r.name, r / "best_genome.json") for r in runs])
    log = io.StringIO()
    out = tmp_path / "report"
    report = write_report([*runs, unfinished], [ev], out, log=log)

    assert report == out / "report.md"
    md = report.read_text(encoding="utf-8")
    pngs = sorted(out.glob("*.png"))
    # per run: pareto, niches, complexity, topology; one convergence; one trajectory per genome
    assert len(pngs) == 4 * len(runs) + 1 + len(runs)
    for png in pngs:
        _assert_png(png)
        assert f"]({png.name})" in md
    for kind in ("pareto", "niches", "complexity", "topology"):
        assert len(list(out.glob(f"*_{kind}.png"))) == len(runs)
    assert (out / "convergence_ugv.png").is_file()
    assert len(list(out.glob("*_trajectories.png"))) == len(runs)

    for r in runs:
        assert f"`{r.name}`" in md
        last = read_history(r / "history.csv")[-1]
        assert f"{last.best_F:.3f}" in md
        assert f"{last.best_G:.3f}" in md
    # the dominant run's largest niche (60% and more) is flagged against the paper's 1/3
    top = max(r.largest_niche_share for r in read_history(runs[3] / "history.csv"))
    assert top > 0.5 and f"{100 * top:.0f}% ⚠ > 1/3" in md
    tops = [max(h.largest_niche_share for h in read_history(r / "history.csv")) for r in runs]
    assert md.count("⚠ > 1/3 |") == sum(t > 1 / 3 for t in tops)
    assert "±" in md  # two seeds per framework: mean ± std
    doc = json.loads(ev.read_text(encoding="utf-8"))
    for run in doc["runs"]:
        assert f"{100 * run['summary']['success_rate']:.0f}%" in md
    assert "| dual | 2 |" in md and "| single | 2 |" in md  # eval runs grouped by framework
    # the unfinished run is skipped with one warning line and listed
    assert log.getvalue().count("\n") == 1
    assert "ugv-dual-s2" in log.getvalue() and "unfinished" in log.getvalue()
    assert "## Skipped" in md and "ugv-dual-s2" in md
    assert not list(out.glob(".*.tmp"))


def test_cli_writes_report_and_exits_2_on_bad_input(
    tmp_path: Path, runs: list[Path], capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "cli"
    assert report_main([str(runs[0]), "--out", str(out)]) == 0
    assert (out / "report.md").is_file()
    (runs[1] / "history.csv").unlink()
    capsys.readouterr()
    assert report_main([str(runs[1]), "--out", str(tmp_path / "bad")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1
    assert "history.csv" in err and "no such file" in err
    assert not (tmp_path / "bad" / "report.md").exists()


def test_missing_history_names_the_file(runs: list[Path]) -> None:
    (runs[0] / "history.csv").unlink()
    with pytest.raises(FileFormatError) as info:
        load_run(runs[0])
    assert info.value.path == str(runs[0] / "history.csv")


@pytest.mark.parametrize("name", ["population.json", "pareto.json", "best_genome.json"])
def test_corrupt_json_names_the_file(runs: list[Path], name: str) -> None:
    (runs[0] / name).write_text('{"format": "mentor-', encoding="utf-8")
    with pytest.raises(FileFormatError) as info:
        load_run(runs[0])
    assert info.value.path == str(runs[0] / name)
    assert "\n" not in str(info.value)


def test_bad_history_row_names_file_and_line(runs: list[Path]) -> None:
    path = runs[0] / "history.csv"
    lines = path.read_text(encoding="utf-8").splitlines()
    lines[3] = lines[3].replace(lines[3].split(",")[4], "oops", 1)
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    with pytest.raises(FileFormatError, match="line 4"):
        read_history(path)


def test_wrong_format_and_missing_dir(tmp_path: Path, runs: list[Path]) -> None:
    pop = runs[0] / "population.json"
    pop.write_text(json.dumps({"format": "mentor-pareto", "version": 1}), encoding="utf-8")
    with pytest.raises(FileFormatError, match="not a mentor-population file"):
        load_run(runs[0])
    with pytest.raises(FileFormatError, match="no such run directory"):
        write_report([tmp_path / "nowhere"], [], tmp_path / "out")


def test_bad_eval_names_the_file(tmp_path: Path) -> None:
    bad = tmp_path / "eval.json"
    bad.write_text("[1, 2", encoding="utf-8")
    with pytest.raises(FileFormatError) as info:
        load_eval(bad)
    assert info.value.path == str(bad)
    good = make_eval(tmp_path / "good.json", [("a", tmp_path / "a.json")])
    doc = json.loads(good.read_text(encoding="utf-8"))
    del doc["runs"][0]["results"][1]["collided"]
    bad.write_text(json.dumps(doc), encoding="utf-8")
    with pytest.raises(FileFormatError, match="collided"):
        load_eval(bad)
    assert math.isclose(load_eval(good).world_size, 12.0)


def test_node_layers_follow_the_longest_path() -> None:
    g = make_genome(np.random.default_rng(0), hidden=3)
    layers = node_layers(g)
    hid = [n.id for n in g.hidden_nodes]
    assert [layers[h] for h in hid] == [1, 2, 3]
    assert all(layers[i] == 0 for i in range(N_IN + 1))
    assert layers[N_IN + 1] == layers[N_IN + 2] == 4
    flat = make_genome(np.random.default_rng(0), hidden=0)
    assert set(node_layers(flat).values()) == {0, 1}


def test_niche_shares_and_complexity_bins() -> None:
    hist = make_history("dual", 10, 20, np.random.default_rng(1))
    ids, shares = niche_share_matrix(hist)
    assert ids == sorted(ids) and shares.shape == (10, len(ids))
    np.testing.assert_allclose(shares.sum(axis=1), 1.0)
    np.testing.assert_allclose(shares.max(axis=1), [r.largest_niche_share for r in hist])
    bins = complexity_bins([1.0, 1.0, 1.5, 2.0], [0.1, 0.2, 0.3, 0.4], n_bins=4)
    assert [len(v) for _, _, v in bins] == [2, 1, 1]  # the empty bin is left out
    assert bins[-1][1] == 2.0
    assert complexity_bins([1.0, 1.0], [0.5, 0.6])[0][2].tolist() == [0.5, 0.6]


def test_figures_are_figures() -> None:
    fig = pareto_front([[1.0, 2.0], [2.0, 1.0], [0.5, 0.5]], [0, 1])
    assert isinstance(fig, Figure)
    assert isinstance(topology(make_genome(np.random.default_rng(2))), Figure)


def test_the_nodes_of_a_planner_with_a_memory_are_named() -> None:
    genome = genome_from_edges(10, 4, [(9, 11, 1.0), (0, 14, 1.0)])  # 3 sensors, 2 + 2 units
    labels = node_labels(genome, "egocentric", feedback_action=True)
    assert [labels[i] for i in range(11)] == [
        "r0", "r1", "r2", "cos β", "sin β", "S", "Δθ⁻", "Δs⁻", "m1⁻", "m2⁻", "bias"]
    assert [labels[o] for o in genome.output_ids] == ["Δθ", "Δs", "m1", "m2"]
    assert isinstance(topology(genome, encoding="egocentric", feedback_action=True), Figure)


def test_a_genome_trained_with_other_sensors_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """docs/algorithm.md: mentor-report refuses a best genome whose sensor record differs
    from the robot file's, as mentor-eval and the planner node do (issue 17)."""
    from mentor_core.files.genome_file import load_genome_and_metadata
    from mentor_core.sim.robots import get_profile, sensor_record

    run = make_run(tmp_path / "runs", "ugv-single-s0", framework="single", generations=4, pop=6)
    genome, meta = load_genome_and_metadata(run / "best_genome.json")
    record = sensor_record(get_profile("ugv"))
    save_genome(genome, run / "best_genome.json", {**meta, "sensors": record})
    assert load_run(run).best_genome == genome  # the robot file's own sensors: accepted
    record["sensor_range"] = 2.0
    save_genome(genome, run / "best_genome.json", {**meta, "sensors": record})
    with pytest.raises(ConfigError, match=r"best_genome\.json: sensors: .*other sensors"):
        load_run(run)
    out = tmp_path / "report"
    assert report_main([str(run), "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "best_genome.json" in err
    assert not (out / "report.md").exists()


def test_the_report_folder_is_checked_before_any_run_is_read(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    """--out: never a run directory (nor inside one); a folder of files only with --force,
    an earlier report's included, which is replaced, its figures no longer drawn removed
    (issues 17, 58)."""
    import mentor_core.report.markdown as markdown

    monkeypatch.setattr(markdown, "_png", lambda fig: PNG_MAGIC)  # figures: not the point
    root = tmp_path / "runs"
    a = make_run(root, "ugv-single-s0", framework="single", generations=4, pop=6)
    b = make_run(root, "ugv-dual-s1", framework="dual", seed=1, generations=4, pop=6)
    before = sorted(p.name for p in a.iterdir())
    for out, force in ((a, ["--force"]), (a / "report", ["--force"]), (b / "x.png", [])):
        assert report_main([str(a), str(b), "--out", str(out), *force]) == 2
        err = capsys.readouterr().err.strip()
        assert len(err.splitlines()) == 1 and f"--out {out}" in err
    assert sorted(p.name for p in a.iterdir()) == before
    notes = tmp_path / "notes"
    notes.mkdir()
    (notes / "todo.txt").write_text("mine\n")
    assert report_main([str(a), "--out", str(notes)]) == 2
    assert "already exists and is not empty; pass --force" in capsys.readouterr().err
    assert report_main([str(a), "--out", str(notes), "--force"]) == 0
    assert (notes / "report.md").is_file() and (notes / "todo.txt").read_text() == "mine\n"
    # an earlier report is rewritten in place, with --force
    out = tmp_path / "report"
    assert report_main([str(a), str(b), "--out", str(out)]) == 0
    assert any(p.name.startswith("ugv-dual-s1") for p in out.glob("*.png"))
    (out / "mine.png").write_bytes(b"kept")  # not a figure of the report: left alone
    assert report_main([str(a), "--out", str(out)]) == 2
    assert "pass --force" in capsys.readouterr().err
    assert report_main([str(a), "--out", str(out), "--force"]) == 0
    assert not any(p.name.startswith("ugv-dual-s1") for p in out.glob("*.png"))
    assert any(p.name.startswith("ugv-single-s0") for p in out.glob("*.png"))
    assert (out / "mine.png").read_bytes() == b"kept"
