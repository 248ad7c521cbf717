"""Evaluation backends: in process, process pool and Ray agree bit for bit; Ray's errors.

The Ray tests start one local Ray (2 CPUs, a few seconds) shared by the module's Ray tests;
they are skipped only when ``ray`` cannot be imported (it is in requirements.lock and the
``ray`` extra of mentor-core). What the Ray addresses mean to ``ray.init`` is checked on a
stand-in for Ray here, and on a real ``ray start --head`` cluster in test_ray_cluster.py.
"""

from __future__ import annotations

import csv
import importlib
import os
import socket
import subprocess
import sys
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml
from run_support import TINY

from mentor_core.cli import train as train_cli
from mentor_core.errors import ConfigError, MentorError
from mentor_core.evolution.config import EvolutionConfig
from mentor_core.evolution.genome import Genome
from mentor_core.evolution.mutation import mutated_genomes
from mentor_core.training.config import TrainerConfig
from mentor_core.training.evaluators import (
    BackendError,
    InProcessEvaluator,
    PoolEvaluator,
    RayEvaluator,
    _check_reachable,
    make_evaluator,
)
from mentor_core.training.problem import Evaluation, NavigationProblem
from mentor_core.training.trainer import make_problem, train

try:
    importlib.import_module("ray")
    HAVE_RAY = True
except ImportError:
    HAVE_RAY = False
NO_RAY = "ray cannot be imported (install the extra: pip install 'mentor-core[ray]')"
needs_ray = pytest.mark.skipif(not HAVE_RAY, reason=NO_RAY)


def tiny_config() -> TrainerConfig:
    return TrainerConfig.from_dict(dict(TINY))


def varied_genomes(n: int, n_inputs: int, rounds: int = 6, seed: int = 5) -> list[Genome]:
    """Minimal genomes put through the paper's mutation, so they carry hidden nodes."""
    mutation = EvolutionConfig.paper("swarm").mutation
    return mutated_genomes(n, n_inputs, mutation, rounds, np.random.default_rng(seed))


@pytest.fixture(scope="module")
def problem() -> NavigationProblem:
    return make_problem(tiny_config())


@pytest.fixture(scope="module")
def genomes(problem: NavigationProblem) -> list[Genome]:
    return varied_genomes(5, problem.n_inputs)


@pytest.fixture(scope="module")
def serial(problem: NavigationProblem, genomes: list[Genome]) -> Evaluation:
    return InProcessEvaluator(problem).evaluate(genomes)


@pytest.fixture(scope="module")
def ray_evaluator(problem: NavigationProblem) -> Iterator[RayEvaluator]:
    if not HAVE_RAY:
        pytest.skip(NO_RAY)
    import ray

    assert not ray.is_initialized()
    evaluator = RayEvaluator(problem, "local", workers=2)
    yield evaluator
    evaluator.close()
    assert not ray.is_initialized(), "close() must shut down the Ray it started"


@pytest.fixture
def ray_evaluator_or_none(request: pytest.FixtureRequest) -> RayEvaluator | None:
    return request.getfixturevalue("ray_evaluator") if HAVE_RAY else None


def assert_same(a: Evaluation, b: Evaluation) -> None:
    assert np.array_equal(a.objectives, b.objectives)
    assert np.array_equal(a.success_rate, b.success_rate)
    assert np.array_equal(a.collision_rate, b.collision_rate)


def history(run: Path) -> list[dict[str, str]]:
    with (run / "history.csv").open() as handle:
        return [{k: v for k, v in r.items() if k != "seconds"} for r in csv.DictReader(handle)]


def test_genomes_are_not_trivial(genomes: list[Genome], serial: Evaluation) -> None:
    assert any(g.hidden_nodes for g in genomes)
    assert serial.objectives.shape == (len(genomes), 2)
    assert np.isfinite(serial.objectives).all()
    assert (serial.objectives[:, 1] > 0).all()  # experience gain was computed


def test_pool_is_bit_identical_to_in_process(
    problem: NavigationProblem, genomes: list[Genome], serial: Evaluation
) -> None:
    with PoolEvaluator(problem, workers=2) as pool:
        assert_same(pool.evaluate(genomes), serial)
        assert_same(pool.evaluate(genomes[:1]), InProcessEvaluator(problem).evaluate(genomes[:1]))
        assert pool.evaluate([]).objectives.shape == (0, 2)


@needs_ray
def test_ray_is_bit_identical_to_in_process(
    ray_evaluator: RayEvaluator, genomes: list[Genome], serial: Evaluation
) -> None:
    assert ray_evaluator.workers == 2
    assert ray_evaluator.describe().startswith("a private local Ray at ")
    assert ray_evaluator.describe().endswith("(1 node, 2 CPUs), 2 tasks a generation")
    assert_same(ray_evaluator.evaluate(genomes), serial)
    assert ray_evaluator.evaluate([]).objectives.shape == (0, 2)


def lengths_and_pids(items: Sequence[int]) -> tuple[list[int], int]:
    return [i * i for i in items], os.getpid()


def test_map_chunks_runs_contiguous_chunks_in_order_on_the_workers(
    problem: NavigationProblem, ray_evaluator_or_none: RayEvaluator | None
) -> None:
    items = list(range(7))
    whole = InProcessEvaluator(problem).map_chunks(lengths_and_pids, items)
    assert whole == [([i * i for i in items], os.getpid())]
    with PoolEvaluator(problem, workers=2) as pool:
        parts = pool.map_chunks(lengths_and_pids, items)
        assert [v for values, _ in parts for v in values] == whole[0][0]
        assert len(parts) == 2 and os.getpid() not in {pid for _, pid in parts}
        assert pool.map_chunks(lengths_and_pids, items[:1]) == [([0], os.getpid())]
    if ray_evaluator_or_none is not None:  # Ray's workers cannot import this test module
        assert ray_evaluator_or_none.map_chunks(tuple, items) == [(0, 1, 2, 3), (4, 5, 6)]


@needs_ray
def test_train_on_ray_equals_in_process(ray_evaluator: RayEvaluator, tmp_path: Path) -> None:
    config = tiny_config()
    train(config, tmp_path / "serial", seed=3)
    train(config, tmp_path / "ray", seed=3, evaluator=ray_evaluator)
    assert history(tmp_path / "ray") == history(tmp_path / "serial")
    assert (tmp_path / "ray" / "best_genome.json").read_text() == (
        tmp_path / "serial" / "best_genome.json"
    ).read_text()


@needs_ray
def test_a_running_ray_is_used_and_left_running(
    ray_evaluator: RayEvaluator, problem: NavigationProblem, genomes: list[Genome],
    serial: Evaluation,
) -> None:
    import ray

    guest = make_evaluator(problem, ray_address="auto")  # Ray already runs: joins it
    assert isinstance(guest, RayEvaluator)
    assert guest.workers == 2  # the CPUs of the running Ray
    assert guest.describe().startswith("the Ray runtime of this process at ")
    assert_same(guest.evaluate(genomes), serial)
    guest.close()
    assert ray.is_initialized(), "close() must not shut down a Ray it did not start"


def test_make_evaluator_picks_the_backend(problem: NavigationProblem) -> None:
    assert type(make_evaluator(problem)) is InProcessEvaluator
    assert type(make_evaluator(problem, 1)) is InProcessEvaluator
    with make_evaluator(problem, 2) as pool:
        assert isinstance(pool, PoolEvaluator)
    for bad in (0, -3):
        with pytest.raises(ConfigError, match="workers"):
            make_evaluator(problem, bad)


def test_missing_ray_is_one_clear_error(
    problem: NavigationProblem, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setitem(sys.modules, "ray", None)  # import ray -> ImportError
    with pytest.raises(BackendError, match=r"pip install 'mentor-core\[ray\]'") as info:
        make_evaluator(problem, ray_address="auto")
    assert isinstance(info.value, MentorError) and "\n" not in str(info.value)


@pytest.mark.parametrize(
    ("address", "message"),
    [
        ("127.0.0.1:1", "unreachable"),
        ("no-such-host.invalid:6379", "unreachable"),
        ("garbage", "HOST:PORT"),
        ("10.0.0.5:", "HOST:PORT"),
    ],
)
def test_bad_cluster_addresses_fail_fast(address: str, message: str) -> None:
    with pytest.raises(BackendError, match=message) as info:
        _check_reachable(address, timeout=2.0)
    assert "\n" not in str(info.value)


def write_tiny_yaml(path: Path) -> Path:
    """A one-generation single-stage config for the command line."""
    single = {k: v for k, v in TINY.items() if k != "stage1_generations"}
    data = {**single, "framework": "single", "generations": 1}
    path.write_text(yaml.safe_dump(TrainerConfig.from_dict(data).to_dict()))
    return path


def test_cli_wires_workers_and_ray_to_make_evaluator(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    calls: list[tuple[int | None, str | None]] = []

    def fake(problem: NavigationProblem, workers: int | None = None,
             ray_address: str | None = None) -> InProcessEvaluator:
        calls.append((workers, ray_address))
        return InProcessEvaluator(problem)

    monkeypatch.setattr(train_cli, "make_evaluator", fake)
    cfg = write_tiny_yaml(tmp_path / "tiny.yaml")
    base = ["--robot", "swarm", "--framework", "single", "--config", str(cfg), "--quiet"]
    assert train_cli.main([*base, "--out", str(tmp_path / "a")]) == 0
    assert train_cli.main([*base, "--out", str(tmp_path / "b"), "--workers", "2"]) == 0
    assert train_cli.main([*base, "--out", str(tmp_path / "c"), "--ray", "auto"]) == 0
    assert train_cli.main(
        [*base, "--out", str(tmp_path / "d"), "--ray", "10.0.0.5:6379", "--workers", "4"]
    ) == 0
    assert calls == [(None, None), (2, None), (None, "auto"), (4, "10.0.0.5:6379")]


@needs_ray
def test_cli_reports_an_unreachable_cluster_in_one_line(tmp_path: Path) -> None:
    cfg = write_tiny_yaml(tmp_path / "tiny.yaml")
    proc = subprocess.run(
        [sys.executable, "-m", "mentor_core.cli.train", "--robot", "swarm", "--framework",
         "single", "--config", str(cfg), "--out", str(tmp_path / "run"), "--ray", "127.0.0.1:1"],
        capture_output=True, text=True, timeout=60, check=False,
    )
    assert proc.returncode == 2, proc.stderr
    last = proc.stderr.strip().splitlines()[-1]
    assert last.startswith("mentor-train: Ray cluster at 127.0.0.1:1 is unreachable"), proc.stderr
    assert "Traceback" not in proc.stderr


class FakeRay:
    """A stand-in for the ray module: records ray.init's arguments, or raises ``error``."""

    def __init__(self, error: Exception | None = None) -> None:
        self.error = error
        self.inits: list[dict[str, Any]] = []
        self.up = False

    def is_initialized(self) -> bool:
        return self.up

    def init(self, **kwargs: Any) -> None:
        self.inits.append(kwargs)
        if self.error is not None:
            raise self.error
        self.up = True

    def shutdown(self) -> None:
        self.up = False

    def cluster_resources(self) -> dict[str, float]:
        return {"CPU": 4.0}

    def nodes(self) -> list[dict[str, Any]]:
        return [{"Alive": True}, {"Alive": True}, {"Alive": False}]

    def get_runtime_context(self) -> Any:
        return type("Context", (), {"gcs_address": "10.0.0.5:6379"})()

    def put(self, value: object) -> object:
        return value

    def remote(self, function: object) -> object:
        return function


@pytest.fixture
def fake_ray(monkeypatch: pytest.MonkeyPatch) -> FakeRay:
    fake = FakeRay()
    monkeypatch.setitem(sys.modules, "ray", fake)
    return fake


def test_ray_addresses_mean_what_they_mean_to_ray(
    problem: NavigationProblem, fake_ray: FakeRay
) -> None:
    with make_evaluator(problem, 3, "local") as local:
        # a private runtime, never one found through RAY_ADDRESS or /tmp/ray
        assert fake_ray.inits[-1]["address"] == "local"
        assert fake_ray.inits[-1]["num_cpus"] == 3
        assert local.describe() == (
            "a private local Ray at 10.0.0.5:6379 (2 nodes, 4 CPUs), 3 tasks a generation"
        )
    assert not fake_ray.up, "close() shuts down the Ray it started"
    with make_evaluator(problem, ray_address="auto") as joined:
        assert fake_ray.inits[-1]["address"] == "auto"  # Ray's own meaning, Ray's own search
        assert "num_cpus" not in fake_ray.inits[-1]
        assert joined.describe() == (
            "the Ray cluster at 10.0.0.5:6379 (2 nodes, 4 CPUs), 4 tasks a generation"
        )
    with socket.create_server(("127.0.0.1", 0)) as head:
        address = f"127.0.0.1:{head.getsockname()[1]}"
        with make_evaluator(problem, ray_address=address):
            assert fake_ray.inits[-1]["address"] == address


def test_auto_without_a_cluster_is_one_clear_error(
    problem: NavigationProblem, fake_ray: FakeRay
) -> None:
    # Ray's words when it finds nothing
    fake_ray.error = ConnectionError(
        "Could not find any running Ray instance. Please specify the one to connect to by "
        "setting `--address` flag or `RAY_ADDRESS` environment variable."
    )
    with pytest.raises(BackendError) as info:
        make_evaluator(problem, ray_address="auto")
    message = str(info.value)
    assert message.startswith("Ray address 'auto' found no running Ray cluster")
    assert "RAY_ADDRESS" in message and "ray start --head" in message and "'local'" in message
    assert "\n" not in message


def test_a_failed_join_keeps_rays_reason(problem: NavigationProblem, fake_ray: FakeRay) -> None:
    # Ray's shape: a one-line ConnectionError raised from the reason, in a traceback's text
    err = ConnectionError("Failed to connect to Ray cluster at 10.0.0.5:6379")
    err.__cause__ = RuntimeError("Failed to connect to GCS.\nTraceback ...\nVersionMismatch: 2.9")
    fake_ray.error = err
    with socket.create_server(("127.0.0.1", 0)) as head:
        address = f"127.0.0.1:{head.getsockname()[1]}"
        with pytest.raises(BackendError) as info:
            make_evaluator(problem, ray_address=address)
    assert str(info.value) == (
        f"cannot join Ray at {address}: Failed to connect to Ray cluster at 10.0.0.5:6379 "
        "(VersionMismatch: 2.9)"
    )
