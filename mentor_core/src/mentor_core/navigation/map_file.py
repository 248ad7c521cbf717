"""ROS maps on disk: the ``map_server`` YAML + PGM pair that ``nav2_map_server``'s map saver
and ``slam_toolbox`` write, read and written with Nav2's semantics (``nav2_map_server``,
``map_io.cpp``).

YAML keys: ``image`` (the image file, relative to the YAML's folder unless absolute),
``resolution`` (m per pixel), ``origin`` ``[x, y, yaw]`` (the pose of the lower-left pixel in
``map``), ``negate`` (0/1 or a boolean), ``occupied_thresh``, ``free_thresh`` and optionally
``mode`` (``trinary``, the default, ``scale`` or ``raw``); other keys are ignored, as Nav2
does. We also require ``0 <= free_thresh < occupied_thresh <= 1`` (Nav2's saver's check).

Reading a pixel of value ``v`` (maxval ``m``): ``shade = v / m``, ``occ = shade`` when
``negate``, else ``1 - shade``; then

* ``trinary``: 100 if ``occupied_thresh < occ``, 0 if ``occ < free_thresh``, else -1;
* ``scale``: as trinary at the ends, else ``rint(100 (occ - free) / (occupied - free))`` (a
  PGM has no alpha channel, so no pixel is transparent, i.e. unknown);
* ``raw``: ``round(255 shade)`` when it lies in 0..100, else -1.

The image's top row is the grid's last row (``data[height - 1 - y, x]`` is pixel ``(x, y)``).
Images: binary (``P5``, 8 or 16 bit) and plain (``P2``) PGM; anything else is refused with a
one-line error (convert it to PGM first).

Writing (:func:`save_map`), as Nav2's saver: an 8-bit ``P5`` PGM, ``trinary`` (free 254,
occupied 0, unknown 205; a value ``<= rint(100 free_thresh)`` is free, ``>=
rint(100 occupied_thresh)`` occupied, anything else unknown) or ``raw`` (the value itself,
unknown 255), and the YAML beside it with ``negate: 0``. The default ``free_thresh`` is ROS 1's
0.196, not Nav2's saver's 0.25: with 0.25 Nav2 reads its own unknown grey 205 (occ 0.196) back
as free, so unknown space would not survive a round trip.
"""

from __future__ import annotations

import math
import re
from pathlib import Path
from typing import Any

import numpy as np
import yaml
from numpy.typing import NDArray

from mentor_core.atomic import write_bytes_atomic, write_text_atomic
from mentor_core.errors import FileFormatError, is_number
from mentor_core.navigation.grid import FREE, OCCUPIED, UNKNOWN, OccupancyGrid
from mentor_core.validation import read_yaml

MODES = ("trinary", "scale", "raw")
SAVE_MODES = ("trinary", "raw")
#: thresholds written by :func:`save_map` (module docstring: why 0.196)
DEFAULT_OCCUPIED_THRESH = 0.65
DEFAULT_FREE_THRESH = 0.196
_PGM_FREE, _PGM_OCCUPIED, _PGM_UNKNOWN = 254, 0, 205
_TOKEN = re.compile(rb"\s*(?:#[^\n]*\n\s*)*(\S+)")


def load_map(path: str | Path) -> OccupancyGrid:
    """The occupancy grid of a map YAML and its image; FileFormatError naming the YAML or the
    image and the fault (missing, unreadable, malformed, truncated)."""
    source = Path(path)
    doc = read_yaml(source)  # YAML 1.2, as map_server's yaml-cpp: resolution: 5e-2 is a number
    try:
        meta = _metadata(doc)
    except ValueError as err:
        raise FileFormatError(source, str(err)) from None
    image = Path(meta["image"])
    if not image.is_absolute():
        image = source.parent / image
    pixels, maxval = read_pgm(image)
    shade = pixels.astype(np.float64) / maxval
    occ = shade if meta["negate"] else 1.0 - shade
    data = _occupancy(occ, shade, meta["mode"], meta["free_thresh"], meta["occupied_thresh"])
    return OccupancyGrid(meta["resolution"], meta["origin"], data[::-1])


def _metadata(doc: Any) -> dict[str, Any]:
    """The checked keys of a map YAML; ValueError naming the key and the fault."""
    if not isinstance(doc, dict):
        raise ValueError("a map YAML is a mapping with image, resolution, origin, ...")
    for key in ("image", "resolution", "origin", "negate", "occupied_thresh", "free_thresh"):
        if key not in doc:
            raise ValueError(f"missing key {key!r}")
    image = doc["image"]
    if not isinstance(image, str) or not image.strip():
        raise ValueError("image must name the image file")
    resolution = _finite(doc["resolution"], "resolution")
    if resolution <= 0.0:
        raise ValueError(f"resolution must be positive, got {resolution}")
    origin = doc["origin"]
    if not isinstance(origin, list) or len(origin) != 3:
        raise ValueError("origin must be [x, y, yaw]")
    origin = [_finite(v, "origin") for v in origin]
    occupied = _finite(doc["occupied_thresh"], "occupied_thresh")
    free = _finite(doc["free_thresh"], "free_thresh")
    if not 0.0 <= free < occupied <= 1.0:
        raise ValueError(
            f"need 0 <= free_thresh < occupied_thresh <= 1, got {free} and {occupied}"
        )
    negate = doc["negate"]
    if type(negate) not in (int, bool):
        raise ValueError(f"negate must be 0, 1 or a boolean, got {negate!r}")
    mode = doc.get("mode", "trinary")
    if mode not in MODES:
        raise ValueError(f"mode must be one of {', '.join(MODES)}, got {mode!r}")
    return {
        "image": image,
        "resolution": resolution,
        "origin": tuple(origin),
        "occupied_thresh": occupied,
        "free_thresh": free,
        "negate": bool(negate),
        "mode": mode,
    }


def _finite(value: Any, key: str) -> float:
    if not is_number(value) or not math.isfinite(value):
        raise ValueError(f"{key} must hold finite numbers, got {value!r}")
    return float(value)


def _occupancy(
    occ: NDArray[np.float64], shade: NDArray[np.float64], mode: str, free: float, occupied: float
) -> NDArray[np.int8]:
    """Cell values of the pixels' occupancies (module docstring), image row order."""
    if mode == "raw":
        value = np.floor(shade * 255.0 + 0.5)  # std::round of a non-negative number
        return np.where(value <= OCCUPIED, value, UNKNOWN).astype(np.int8)
    middle = (
        np.rint((occ - free) / (occupied - free) * 100.0)
        if mode == "scale"
        else np.full(occ.shape, UNKNOWN, dtype=np.float64)
    )
    value = np.where(occupied < occ, OCCUPIED, np.where(occ < free, FREE, middle))
    return value.astype(np.int8)


def read_pgm(path: str | Path) -> tuple[NDArray[np.int64], int]:
    """Pixels ``(height, width)`` (top row first) and maxval of a PGM image (``P5`` 8/16 bit
    or ``P2``); FileFormatError naming the file and the fault."""
    source = Path(path)
    try:
        raw = source.read_bytes()
    except OSError as err:
        raise FileFormatError(source, f"cannot read map image ({err.strerror})") from None
    magic = raw[:2]
    if magic not in (b"P5", b"P2"):
        raise FileFormatError(
            source, "not a PGM image (P5 or P2); convert the map image to PGM first"
        )
    pos = 2
    header: list[int] = []
    for name in ("width", "height", "maxval"):
        match = _TOKEN.match(raw, pos)
        if match is None or not match.group(1).isdigit():
            raise FileFormatError(source, f"PGM header: {name} is missing or not a number")
        header.append(int(match.group(1)))
        pos = match.end()
    width, height, maxval = header
    if width == 0 or height == 0 or not 0 < maxval < 65536:
        raise FileFormatError(
            source, f"PGM header: {width}x{height} pixels, maxval {maxval} is not an image"
        )
    count = width * height
    if magic == b"P5":
        wide = maxval > 255
        need = count * (2 if wide else 1)
        body = raw[pos + 1 : pos + 1 + need]  # one whitespace byte ends the header
        if len(body) < need:
            raise FileFormatError(source, f"PGM truncated: {len(body)} of {need} pixel bytes")
        pixels = np.frombuffer(body, dtype=">u2" if wide else np.uint8).astype(np.int64)
    else:
        tokens = raw[pos:].split()
        if len(tokens) < count or not all(t.isdigit() for t in tokens[:count]):
            raise FileFormatError(source, f"PGM truncated or malformed: need {count} numbers")
        pixels = np.array([int(t) for t in tokens[:count]], dtype=np.int64)
    if pixels.max() > maxval:
        raise FileFormatError(source, f"PGM pixel value {pixels.max()} exceeds maxval {maxval}")
    return pixels.reshape(height, width), maxval


def save_map(
    path: str | Path,
    grid: OccupancyGrid,
    mode: str = "trinary",
    occupied_thresh: float = DEFAULT_OCCUPIED_THRESH,
    free_thresh: float = DEFAULT_FREE_THRESH,
) -> Path:
    """Write ``grid`` as the map YAML ``path`` and the PGM beside it (same stem), each
    atomically, image first; returns the image's path. ValueError for a mode other than
    ``trinary`` or ``raw`` (``scale`` needs transparency, which PGM lacks) or bad thresholds.
    """
    if mode not in SAVE_MODES:
        modes = ", ".join(SAVE_MODES)
        raise ValueError(f"mode must be one of {modes} to write a PGM, got {mode!r}")
    if not 0.0 <= free_thresh < occupied_thresh <= 1.0:
        raise ValueError(
            f"need 0 <= free_thresh < occupied_thresh <= 1, got {free_thresh}, {occupied_thresh}"
        )
    target = Path(path)
    image = target.with_suffix(".pgm")
    v = grid.data[::-1].astype(np.int64)  # top row first
    known = (v >= 0) & (v <= OCCUPIED)
    if mode == "trinary":
        free_int, occupied_int = round(free_thresh * 100.0), round(occupied_thresh * 100.0)
        pixels = np.full(v.shape, _PGM_UNKNOWN, dtype=np.uint8)
        pixels[known & (v <= free_int)] = _PGM_FREE
        pixels[known & (v >= occupied_int)] = _PGM_OCCUPIED
    else:
        pixels = np.where(known, v, 255).astype(np.uint8)
    header = f"P5\n{grid.width} {grid.height}\n255\n".encode("ascii")
    write_bytes_atomic(image, header + pixels.tobytes())
    doc = {
        "image": image.name,
        "mode": mode,
        "resolution": grid.resolution,
        "origin": list(grid.origin),
        "negate": 0,
        "occupied_thresh": float(occupied_thresh),
        "free_thresh": float(free_thresh),
    }
    write_text_atomic(target, yaml.safe_dump(doc, sort_keys=False, default_flow_style=None))
    return image
