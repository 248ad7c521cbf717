"""The layout of mentor_core: its import contracts bite, its public API resolves."""

from __future__ import annotations

import ast
import importlib
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import mentor_core

ROOT = Path(__file__).resolve().parents[1]
SRC = ROOT / "mentor_core" / "src"
LINT_IMPORTS = Path(sys.executable).with_name("lint-imports")
#: the ROS 2 packages: both nodes, what they share and the demo that runs them together
NODE_PACKAGES = ("mentor_sim_node", "mentor_planner_node", "mentor_ros_common", "mentor_bringup")
WINGS = (
    "evolution", "sim", "objectives", "files", "navigation", "controller", "training", "runtime",
    "benchmark", "report", "cli", "irsim",
)


def _lint_imports(tree: Path) -> subprocess.CompletedProcess[str]:
    """lint-imports with the repository's contracts over a copy of the three packages."""
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(
        str(tree / d) for d in ("src", *NODE_PACKAGES)
    )
    return subprocess.run(
        [str(LINT_IMPORTS), "--no-cache", str(ROOT / "pyproject.toml")],
        cwd=tree, env=env, capture_output=True, text=True, timeout=120, check=False,
    )


@pytest.fixture(scope="module")
def tree_copy(tmp_path_factory: pytest.TempPathFactory) -> Path:
    tree = tmp_path_factory.mktemp("layout")
    ignore = shutil.ignore_patterns("__pycache__", "*.egg-info")
    shutil.copytree(SRC / "mentor_core", tree / "src" / "mentor_core", ignore=ignore)
    for node in NODE_PACKAGES:
        shutil.copytree(ROOT / node / node, tree / node / node, ignore=ignore)
    return tree


def _inject(module: Path, line: str) -> str:
    original = module.read_text()
    head, sep, rest = original.partition("from __future__ import annotations\n")
    module.write_text(head + sep + line + "\n" + rest)
    return original


@pytest.mark.parametrize(
    ("module", "line", "fault"),
    [
        (
            "src/mentor_core/evolution/genome.py",
            "import mentor_core.sim.robots",
            "mentor_core.evolution is not allowed to import mentor_core.sim",
        ),
        (
            "src/mentor_core/sim/world.py",
            "import mentor_core.training.trainer",
            "mentor_core.sim is not allowed to import mentor_core.training",
        ),
        (
            "src/mentor_core/sim/episode.py",
            "import mentor_core.controller.stage",
            "mentor_core.sim is not allowed to import mentor_core.controller",
        ),
        (
            "src/mentor_core/controller/pipeline.py",
            "import mentor_core.runtime.planner",
            "mentor_core.controller is not allowed to import mentor_core.runtime",
        ),
        (
            "src/mentor_core/sim/kinematics.py",
            "import rclpy",
            "mentor_core is not allowed to import rclpy",
        ),
        (
            "mentor_planner_node/mentor_planner_node/planner.py",
            "import mentor_core.runtime.planner",
            "mentor_planner_node is not allowed to import mentor_core.runtime",
        ),
    ],
)
def test_a_deliberate_violation_breaks_a_contract(
    tree_copy: Path, module: str, line: str, fault: str
) -> None:
    path = tree_copy / module
    original = _inject(path, line)
    try:
        result = _lint_imports(tree_copy)
    finally:
        path.write_text(original)
    assert result.returncode != 0
    assert fault in result.stdout


def test_the_repository_keeps_every_contract(tree_copy: Path) -> None:
    result = _lint_imports(tree_copy)
    assert result.returncode == 0, result.stdout[-2000:]


def test_every_public_name_resolves_to_its_module() -> None:
    exports: dict[str, str] = vars(mentor_core)["_EXPORTS"]
    for name, module in exports.items():
        assert getattr(mentor_core, name) is getattr(importlib.import_module(module), name)
    with pytest.raises(AttributeError, match="no_such_name"):
        _ = mentor_core.no_such_name  # type: ignore[attr-defined]


def test_the_public_api_is_declared_once() -> None:
    """The TYPE_CHECKING imports are the one declaration: the lazy loader serves exactly their
    names, each re-exported as ``X as X`` (what mypy --strict takes as public), none twice."""
    tree = ast.parse((SRC / "mentor_core" / "__init__.py").read_text())
    typed: list[tuple[str, str]] = []
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and ast.unparse(node.test) == "TYPE_CHECKING":
            for imp in node.body:
                assert isinstance(imp, ast.ImportFrom) and imp.module is not None
                assert all(alias.asname == alias.name for alias in imp.names), imp.module
                typed += [(alias.name, imp.module) for alias in imp.names]
    names = [name for name, _ in typed]
    assert len(set(names)) == len(names) > 100
    assert dict(typed) == vars(mentor_core)["_EXPORTS"]
    assert "_EXPORTS: dict" not in (SRC / "mentor_core" / "__init__.py").read_text()


@pytest.mark.parametrize("wing", WINGS)
def test_each_wing_says_what_it_holds(wing: str) -> None:
    doc = importlib.import_module(f"mentor_core.{wing}").__doc__
    assert doc is not None and len(doc.split()) >= 10
