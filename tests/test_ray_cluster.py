"""Joining a Ray cluster as a Ray user does (issue 17, failure 9).

One cluster for the module: ``ray start --head --block`` on a free port with 1 CPU, token
authentication on (``RAY_AUTH_MODE=token``, a fresh random token of its own) and a temporary
directory of its own (``RAY_TMPDIR``, where ``ray start`` notes its address for ``auto``), so
that another Ray on this machine finds nothing of it, nor it of them. Ray binds
its GCS to the node's address whatever ``--node-ip-address`` says; the token keeps others out.
Teardown stops it by signalling that ``ray start`` (it stops what it started), then kills what
is left in its session, never with ``ray stop`` (which would stop every Ray of the machine).
"""

from __future__ import annotations

import os
import secrets
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import pytest
import yaml
from run_support import TINY, snapshot

from mentor_core.cli import train as train_cli

pytest.importorskip("ray")


@dataclass(frozen=True)
class Cluster:
    address: str  # 127.0.0.1:PORT
    token_path: Path
    tmpdir: Path

    def env(self, **changes: str) -> dict[str, str]:
        """The environment of a process on this cluster's machine that may join it: its Ray
        temporary directory, ``RAY_AUTH_*`` as Ray documents (an empty value unsets)."""
        env = {k: v for k, v in os.environ.items() if not k.startswith(("RAY_AUTH", "RAY_ADDR"))}
        env.update(RAY_TMPDIR=str(self.tmpdir), RAY_AUTH_MODE="token",
                   RAY_AUTH_TOKEN_PATH=str(self.token_path))
        env.update(changes)
        return {k: v for k, v in env.items() if v}


def free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        port: int = sock.getsockname()[1]
        return port


def session_processes(sid: int) -> list[int]:
    """The processes of session ``sid`` (ray start's own, it leads the session)."""
    found = []
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                if os.getsid(int(entry.name)) == sid:
                    found.append(int(entry.name))
            except OSError:
                continue
    return found


@pytest.fixture(scope="module")
def cluster() -> Iterator[Cluster]:
    root = Path(tempfile.mkdtemp(prefix="mray", dir="/tmp"))  # Ray's socket paths stay short
    token = root / "token"
    token.write_text(secrets.token_hex(32))
    port = free_port()
    cluster = Cluster(f"127.0.0.1:{port}", token, root)
    head = subprocess.Popen(
        [str(Path(sys.executable).with_name("ray")), "start", "--head", "--port", str(port),
         "--num-cpus", "1", "--include-dashboard", "false", "--disable-usage-stats", "--block"],
        env=cluster.env(), stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
        start_new_session=True,
    )
    log: list[str] = []
    try:
        assert head.stdout is not None
        for line in head.stdout:
            log.append(line)
            if "block forever" in line:
                break
        else:
            pytest.fail("ray start --head failed:\n" + "".join(log))
        yield cluster
    finally:
        head.send_signal(signal.SIGTERM)
        try:
            head.wait(timeout=30)
        except subprocess.TimeoutExpired:
            head.kill()
        deadline = time.monotonic() + 10
        while session_processes(head.pid) and time.monotonic() < deadline:
            time.sleep(0.2)
        for pid in session_processes(head.pid):
            os.kill(pid, signal.SIGKILL)
        shutil.rmtree(root, ignore_errors=True)


def tiny_yaml(path: Path) -> Path:
    path.write_text(yaml.safe_dump(TINY))
    return path


def train_args(config: Path, out: Path) -> list[str]:
    return ["--robot", "swarm", "--framework", "dual", "--config", str(config), "--seed", "3",
            "--out", str(out), "--quiet"]


def mentor_train(args: list[str], env: dict[str, str]) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "mentor_core.cli.train", *args], env=env,
                          capture_output=True, text=True, timeout=300, check=False)


def test_a_run_on_the_cluster_equals_the_in_process_run(cluster: Cluster, tmp_path: Path) -> None:
    config = tiny_yaml(tmp_path / "tiny.yaml")
    assert train_cli.main(train_args(config, tmp_path / "here")) == 0
    proc = mentor_train([*train_args(config, tmp_path / "ray"), "--ray", cluster.address],
                        cluster.env())
    assert proc.returncode == 0, proc.stderr
    said = [line for line in proc.stderr.splitlines() if "evaluating on" in line]
    assert len(said) == 1 and "the Ray cluster at" in said[0], proc.stderr
    assert "(1 node, 1 CPU), 1 task a generation" in said[0]
    here, there = snapshot(tmp_path / "here"), snapshot(tmp_path / "ray")
    assert sorted(there) == sorted(here) and len(here) >= 6
    for name in here:
        assert there[name] == here[name], name


def test_auto_joins_the_cluster_ray_start_started(cluster: Cluster, tmp_path: Path) -> None:
    config = tiny_yaml(tmp_path / "tiny.yaml")
    # found through the address `ray start` noted in RAY_TMPDIR, as on a head node; and no
    # RAY_AUTH_MODE: Ray turns token authentication on by itself when it finds a token
    proc = mentor_train([*train_args(config, tmp_path / "run"), "--ray", "auto"],
                        cluster.env(RAY_AUTH_MODE=""))
    assert proc.returncode == 0, proc.stderr
    said = [line for line in proc.stderr.splitlines() if "evaluating on" in line]
    assert len(said) == 1, proc.stderr
    assert said[0].startswith("mentor-train: evaluating on the Ray cluster at ")
    assert f":{cluster.address.split(':')[1]} (1 node, 1 CPU)" in said[0]


def test_a_missing_token_is_one_line_with_rays_hint(cluster: Cluster, tmp_path: Path) -> None:
    config = tiny_yaml(tmp_path / "tiny.yaml")
    # no RAY_AUTH_MODE: for an explicit address Ray sends no token (Ray's retries cut short)
    env = cluster.env(RAY_AUTH_MODE="", RAY_AUTH_TOKEN_PATH="",
                      RAY_gcs_server_port_wait_time_s="1")
    proc = mentor_train([*train_args(config, tmp_path / "run"), "--ray", cluster.address], env)
    assert proc.returncode == 2, proc.stderr
    last = proc.stderr.strip().splitlines()[-1]
    assert last.startswith(f"mentor-train: cannot join Ray at {cluster.address}: token "), last
    assert "RAY_AUTH_MODE is currently 'disabled' (not 'token')" in last  # Ray's own words
    assert "RAY_AUTH_TOKEN" in last and "Traceback" not in proc.stderr
    assert not (tmp_path / "run" / "checkpoint.json").exists()
