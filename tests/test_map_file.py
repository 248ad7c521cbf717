"""ROS maps on disk: the map_server YAML + PGM pair with nav2_map_server's semantics, round
trips, bad files, and worlds made from maps (a map YAML, a world file's ``map`` key)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from mentor_core.errors import FileFormatError
from mentor_core.navigation.grid import FREE, OCCUPIED, UNKNOWN, OccupancyGrid, world_grid
from mentor_core.navigation.map_file import load_map, read_pgm, save_map
from mentor_core.navigation.map_world import load_map_world, load_world_file

YAML = (
    "image: {image}\nresolution: 0.5\norigin: [-1.0, 2.0, 0.0]\nnegate: {negate}\n"
    "occupied_thresh: {occ}\nfree_thresh: {free}\n"
)


def _write(folder: Path, pixels: list[list[int]], maxval: int = 255, **keys: object) -> Path:
    """A plain (P2) PGM of ``pixels`` (top row first) and its map YAML; returns the YAML."""
    rows = "\n".join(" ".join(str(v) for v in row) for row in pixels)
    (folder / "m.pgm").write_text(
        f"P2\n# made by a test\n{len(pixels[0])} {len(pixels)}\n{maxval}\n{rows}\n"
    )
    values = {"image": "m.pgm", "negate": 0, "occ": 0.65, "free": 0.196, **keys}
    text = YAML.format(**values) + (f"mode: {keys['mode']}\n" if "mode" in keys else "")
    (folder / "m.yaml").write_text(text)
    return folder / "m.yaml"


def test_trinary_thresholds_and_row_order_follow_nav2(tmp_path: Path) -> None:
    # occ = 1 - v / 255: 0 -> 1.0, 254 -> 0.004, 205 -> 0.196, and exact threshold values
    occ_at_thresh = round(255 * (1 - 0.65))  # 89: occ 0.651 > 0.65 -> occupied
    pixels = [[0, 254, 205], [occ_at_thresh, 90, 128]]
    grid = load_map(_write(tmp_path, pixels))
    assert grid.resolution == 0.5 and grid.origin == (-1.0, 2.0, 0.0)
    # the image's top row is the grid's last row
    assert grid.data.tolist() == [[OCCUPIED, UNKNOWN, UNKNOWN], [OCCUPIED, FREE, UNKNOWN]]
    # Nav2's saver default free_thresh 0.25 reads its own unknown grey 205 back as free
    nav2 = load_map(_write(tmp_path, pixels, free=0.25))
    assert nav2.data[1, 2] == FREE
    # occ exactly at a threshold is neither side: a pixel with occ == free_thresh is unknown
    exact = load_map(_write(tmp_path, [[51]], free=1 - 51 / 255, occ=0.9))
    assert exact.data.tolist() == [[UNKNOWN]]


def test_negate_swaps_black_and_white(tmp_path: Path) -> None:
    grid = load_map(_write(tmp_path, [[0, 255, 128]], negate=1))
    assert grid.data.tolist() == [[FREE, OCCUPIED, UNKNOWN]]
    boolean = load_map(_write(tmp_path, [[0, 255, 128]], negate="true"))
    assert boolean == grid


def test_scale_and_raw_modes(tmp_path: Path) -> None:
    # scale: rint(100 (occ - free) / (occupied - free)) between the thresholds
    pixels = [[0, 255, 153, 102]]  # occ 1, 0, 0.4, 0.6
    grid = load_map(_write(tmp_path, pixels, mode="scale", free=0.2, occ=0.8))
    assert grid.data.tolist() == [[OCCUPIED, FREE, 33, 67]]
    # raw: the pixel value itself (as shade * 255) when in 0..100, else unknown
    raw = load_map(_write(tmp_path, [[0, 37, 100, 101, 255]], mode="raw"))
    assert raw.data.tolist() == [[0, 37, 100, UNKNOWN, UNKNOWN]]


def test_sixteen_bit_binary_pgm(tmp_path: Path) -> None:
    body = np.array([[0, 65535], [40000, 65535]], dtype=">u2").tobytes()
    (tmp_path / "m.pgm").write_bytes(b"P5 2 2\n65535\n" + body)
    (tmp_path / "m.yaml").write_text(
        YAML.format(image="m.pgm", negate=0, occ=0.65, free=0.196)
    )
    # top row (0, 65535) is the last grid row; 40000: occ 0.39, unknown
    assert load_map(tmp_path / "m.yaml").data.tolist() == [[UNKNOWN, FREE], [OCCUPIED, FREE]]
    assert read_pgm(tmp_path / "m.pgm")[1] == 65535


@pytest.mark.parametrize("mode", ["trinary", "raw"])
def test_save_then_load_gives_the_grid_back(tmp_path: Path, mode: str) -> None:
    rng = np.random.default_rng(5)
    values = [UNKNOWN, FREE, OCCUPIED] if mode == "trinary" else list(range(-1, 101))
    data = rng.choice(values, size=(7, 11)).astype(np.int8)
    grid = OccupancyGrid(0.05, (-3.25, 1.5, 0.0), data)
    image = save_map(tmp_path / "out" / "office.yaml", grid, mode=mode)
    assert image == tmp_path / "out" / "office.pgm"
    assert image.read_bytes().startswith(b"P5\n11 7\n255\n")
    assert load_map(tmp_path / "out" / "office.yaml") == grid
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == ["office.pgm", "office.yaml"]


def test_save_writes_nav2_trinary_pixels_and_refuses_scale(tmp_path: Path) -> None:
    grid = OccupancyGrid(0.1, (0.0, 0.0, 0.0), np.array([[-1, 0, 20, 21, 64, 65, 100]]))
    image = save_map(tmp_path / "m.yaml", grid)
    pixels, _ = read_pgm(image)
    assert pixels.tolist() == [[205, 254, 254, 205, 205, 0, 0]]  # free <= 20, occupied >= 65
    with pytest.raises(ValueError, match="trinary, raw"):
        save_map(tmp_path / "s.yaml", grid, mode="scale")


GOOD = "image: m.pgm\nresolution: 0.5\norigin: [0, 0, 0]\nnegate: 0\n"
THRESH = "occupied_thresh: 0.65\nfree_thresh: 0.196\n"


@pytest.mark.parametrize(
    ("yaml_text", "pgm", "where", "fault"),
    [
        (None, b"P2 1 1 255 0", "m.yaml", "no such file"),
        ("image: [unclosed", b"P2 1 1 255 0", "m.yaml", "not valid YAML"),
        ("- a list", b"P2 1 1 255 0", "m.yaml", "a mapping"),
        (GOOD, b"P2 1 1 255 0", "m.yaml", "missing key 'occupied_thresh'"),
        ("image: ''\nresolution: 1\norigin: [0, 0, 0]\nnegate: 0\n" + THRESH, None, "m.yaml",
         "image must name"),
        (GOOD.replace("0.5", "-1") + THRESH, None, "m.yaml", "resolution must be positive"),
        (GOOD.replace("0.5", ".nan") + THRESH, None, "m.yaml", "resolution must hold finite"),
        (GOOD.replace("[0, 0, 0]", "[0, 0]") + THRESH, None, "m.yaml", r"origin must be \[x"),
        (GOOD.replace("[0, 0, 0]", "[0, a, 0]") + THRESH, None, "m.yaml", "origin must hold"),
        (GOOD + "occupied_thresh: 0.2\nfree_thresh: 0.3\n", None, "m.yaml", "free_thresh <"),
        (GOOD.replace("negate: 0", "negate: maybe") + THRESH, None, "m.yaml", "negate must"),
        (GOOD + THRESH + "mode: fancy\n", None, "m.yaml", "mode must be one of"),
        (GOOD + THRESH, None, "m.pgm", "cannot read map image"),
        (GOOD + THRESH, b"\x89PNG\r\n\x1a\n", "m.pgm", "not a PGM image"),
        (GOOD + THRESH, b"P5 4 4 255\n\x00\x00", "m.pgm", "PGM truncated: 2 of 16"),
        (GOOD + THRESH, b"P5 4 x 255\n", "m.pgm", "height is missing or not a number"),
        (GOOD + THRESH, b"P5 0 4 255\n", "m.pgm", "is not an image"),
        (GOOD + THRESH, b"P2 2 1 10 3 11", "m.pgm", "exceeds maxval 10"),
        (GOOD + THRESH, b"P2 2 2 10 3 1 4", "m.pgm", "need 4 numbers"),
    ],
)
def test_bad_map_files_name_the_file_and_the_fault(
    tmp_path: Path, yaml_text: str | None, pgm: bytes | None, where: str, fault: str
) -> None:
    if yaml_text is not None:
        (tmp_path / "m.yaml").write_text(yaml_text)
    if pgm is not None:
        (tmp_path / "m.pgm").write_bytes(pgm)
    with pytest.raises(FileFormatError, match=fault) as info:
        load_map(tmp_path / "m.yaml")
    assert info.value.path == str(tmp_path / where)
    assert "\n" not in str(info.value)


def test_a_map_becomes_a_world_in_the_maps_frame_shifted_to_the_arena(tmp_path: Path) -> None:
    # 3 x 2 pixels at 0.5 m, origin (-1, 2): the occupied top-left pixel is map cell (1, 0)
    yaml_path = _write(tmp_path, [[0, 254, 254], [254, 205, 254]])
    world, grid = load_map_world(yaml_path)
    assert world.name == "m" and world.size == 1.5
    assert grid.origin == (0.0, 0.0, 0.0) and grid.resolution == 0.5
    # occupied cell (row 1, col 0), unknown cell (row 0, col 1): obstacles; beyond the
    # 2-row image up to the 3-cell arena side: an obstacle
    cells = world_grid(world, 0.5).data == OCCUPIED
    assert cells.tolist() == [[False, True, False], [True, False, False], [True, True, True]]


def test_a_world_file_may_name_a_map_relative_to_itself(tmp_path: Path) -> None:
    (tmp_path / "maps").mkdir()
    _write(tmp_path / "maps", [[254] * 6] * 6)
    (tmp_path / "w.yaml").write_text(
        "format: mentor-world\nversion: 1\nmap: maps/m.yaml\nobstacles: [[1, 1, 2, 2]]\n"
        "scenarios: [{start: [0.5, 0.5, 0], goal: [2.5, 2.5]}]\n"
    )
    world, scenarios = load_world_file(tmp_path / "w.yaml")
    assert world.size == 3.0 and world.name == "m"
    assert world.obstacles.tolist() == [[1.0, 1.0, 2.0, 2.0]]
    assert scenarios[0].goal == (2.5, 2.5)
    # a bad map named by a world file: one line naming both files
    (tmp_path / "maps" / "m.pgm").write_bytes(b"P5 6 6 255\n")
    with pytest.raises(FileFormatError, match=r"w\.yaml: .*m\.pgm: PGM truncated"):
        load_world_file(tmp_path / "w.yaml")
