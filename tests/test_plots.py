"""World drawings and the mentor-draw command."""

from __future__ import annotations

import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from profiles_support import UGV_STRAIGHT

from mentor_core.cli.draw import main, straight_to_goal
from mentor_core.report.plots import draw_world, new_figure, save_png
from mentor_core.sim.pymunk_world import PymunkWorld
from mentor_core.sim.world import Scenario, World, save_world

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"
UGV = UGV_STRAIGHT  # a pair on each edge facing straight out: rays easy to check by hand


def test_draw_world_draws_every_element() -> None:
    world = World(10.0, np.array([[5.0, 4.0, 6.0, 6.0], [1.0, 1.0, 2.0, 2.0]]))
    sc = Scenario(world, (3.0, 5.0, 0.0), (8.0, 8.0))
    rays = PymunkWorld(world, UGV).ranges(sc.start)
    fig = new_figure()
    ax = fig.add_subplot()
    draw_world(ax, world, [sc], UGV, pose=sc.start, rays=rays, trajectory=[(3, 5), (4, 6)])
    # arena + 2 obstacles + goal circle + robot body
    assert len(ax.patches) == 5
    ray_lines = [ln for ln in ax.lines if len(ln.get_xdata()) == 2 and ln.get_linestyle() in
                 ("-", "--") and ln.get_color() in ("tab:orange", "0.6")]
    assert len(ray_lines) == UGV.n_sensors
    # front ray ends on the obstacle face x = 5; an out-of-range ray ends at 4 m
    front = ray_lines[0]
    assert front.get_xdata()[1] == pytest.approx(5.0)
    left = ray_lines[2]
    assert left.get_ydata()[1] - left.get_ydata()[0] == pytest.approx(UGV.sensor_range)
    assert left.get_linestyle() == "--"
    assert ax.get_xlim()[1] > 10.0 and ax.get_ylim()[0] < 0.0


def test_draw_world_needs_profile_and_pose_for_rays() -> None:
    ax = new_figure().add_subplot()
    with pytest.raises(ValueError, match="profile"):
        draw_world(ax, World(5.0), pose=(1.0, 1.0, 0.0))
    with pytest.raises(ValueError, match="pose"):
        draw_world(ax, World(5.0), profile=UGV, rays=np.full(8, np.inf))


def test_save_png_is_atomic(tmp_path: Path) -> None:
    fig = new_figure(2, 2)
    draw_world(fig.add_subplot(), World(5.0))
    out = tmp_path / "sub" / "w.png"
    save_png(fig, out)
    assert out.read_bytes().startswith(PNG_MAGIC)
    assert [p.name for p in out.parent.iterdir()] == ["w.png"]


def test_straight_to_goal_reaches_an_open_goal_and_stops_at_a_wall() -> None:
    world = World(12.0)
    path = straight_to_goal(PymunkWorld(world, UGV), Scenario(world, (2, 2, 0), (10, 9)))
    assert np.hypot(*(path[-1] - (10, 9))) <= UGV.goal_radius
    blocked = World(12.0, np.array([[5.0, 0.0, 6.0, 12.0]]))
    path = straight_to_goal(PymunkWorld(blocked, UGV), Scenario(blocked, (2, 6, 0), (10, 6)))
    assert path[-1, 0] < 5.0 - UGV.length / 2 + 0.1


def test_importing_plots_and_cli_leaves_pyplot_and_backend_alone() -> None:
    code = (
        "import sys, matplotlib\n"
        "before = matplotlib.rcParams._get_backend_or_none()\n"
        "import mentor_core.report.plots, mentor_core.cli.draw\n"
        "print('matplotlib.pyplot' in sys.modules, matplotlib.rcParams._get_backend_or_none()"
        " == before)\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.split() == ["False", "True"]


def test_cli_draws_a_world_file(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    world = World(12.0, np.array([[5.0, 4.0, 6.0, 6.0]]))
    world_file = tmp_path / "w.yaml"
    save_world(world_file, world, [Scenario(world, (3.0, 5.0, math.pi / 4), (10.0, 10.0))])
    out = tmp_path / "w.png"
    assert main(["--robot", "ugv", "--world", str(world_file), "--demo", "--out", str(out)]) == 0
    data = out.read_bytes()
    assert data.startswith(PNG_MAGIC) and len(data) > 10_000
    assert capsys.readouterr().err == ""


def test_cli_draws_a_sampled_world(tmp_path: Path) -> None:
    out = tmp_path / "s.png"
    assert main(["--robot", "swarm", "--seed", "2", "--scenario", "3", "--out", str(out)]) == 0
    assert out.read_bytes().startswith(PNG_MAGIC)
    plain, walled = tmp_path / "plain.png", tmp_path / "walls.png"
    assert main(["--robot", "ugv", "--out", str(plain)]) == 0
    assert main(["--robot", "ugv", "--walls", "1", "2", "--out", str(walled)]) == 0
    assert walled.read_bytes() != plain.read_bytes()  # the shipped configs' training world


@pytest.mark.parametrize(
    ("args", "fault"),
    [
        (["--robot", "ugv", "--world", "{tmp}/missing.yaml"], "{tmp}/missing.yaml: no such file"),
        (["--robot", "tank"], "unknown robot 'tank'"),
        (["--robot", "swarm", "--scenario", "99"], "scenario 99 does not exist"),
        (["--robot", "ugv", "--walls", "2", "1"], "wall_count"),
        # issue 17: more walls than fit are refused, not silently fewer
        (["--robot", "ugv", "--walls", "50", "50"], "--walls 50 50: wall_count: only"),
    ],
)
def test_cli_bad_input_one_line_exit_2(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], args: list[str], fault: str
) -> None:
    out = tmp_path / "x.png"
    argv = [a.replace("{tmp}", str(tmp_path)) for a in args] + ["--out", str(out)]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert fault.replace("{tmp}", str(tmp_path)) in err
    assert err.count("\n") == 1
    assert not out.exists()
