"""A scan map that forgets what moved (issue 59, experiment E098): off by default, used by
nothing shipped.

:class:`~mentor_core.navigation.scan_map.ScanMap` holds a cell occupied while its hits are at
least its misses, so an agent that walked through space the robot had seen free leaves a
trail of occupied cells until enough rays pass through them again; a plan goes round the
trail. Nav2's obstacle layer clears by ray tracing too; its voxel and STVL layers also let an
observation expire. :class:`FadingScanMap` lets a hit expire where it came into space already
seen free: a cell whose first hit came after a ray had passed through it (something
*appeared* there) drops its hits once ``memory`` updates pass without a new one. A cell first
read as hit (a wall, a pillar: rays end there before any passes it) never fades.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from mentor_core.navigation.guide import GuideConfig
from mentor_core.navigation.scan_map import ScanGuide, ScanMap

FloatArray = NDArray[np.float64]


class FadingScanMap(ScanMap):
    """A :class:`ScanMap` whose hits in space seen free expire after ``memory`` updates
    without a new hit (module docstring)."""

    def __init__(self, size: float, resolution: float, origin: tuple[float, float] = (0.0, 0.0),
                 memory: int = 8) -> None:  # fmt: skip
        super().__init__(size, resolution, origin)
        if memory < 1:
            raise ValueError(f"memory must be at least one update, got {memory}")
        self.memory = int(memory)
        self.updates = 0
        self.last_hit = np.zeros(self.hits.shape, dtype=np.int64)
        self.appeared = np.zeros(self.hits.shape, dtype=bool)

    def update(
        self, rays: ArrayLike, readings: ArrayLike, max_range: float,
        located: ArrayLike | None = None,
    ) -> FloatArray:  # fmt: skip
        """:meth:`ScanMap.update`, then the expired hits dropped."""
        self.updates += 1
        hits, misses = self.hits.copy(), self.misses.copy()
        new = super().update(rays, readings, max_range, located)
        fresh = self.hits > hits
        self.appeared |= fresh & (hits == 0) & (misses > 0)
        self.last_hit[fresh] = self.updates
        stale = self.appeared & (self.hits > 0) & (self.updates - self.last_hit >= self.memory)
        self.hits[stale] = 0
        self.occupied[stale] = False  # no hits: not occupied (kept in step with the counts)
        self.appeared[stale] = False
        return new


class FadingScanGuide(ScanGuide):
    """A :class:`ScanGuide` on a :class:`FadingScanMap` of ``memory`` updates."""

    def __init__(self, size: float, config: GuideConfig, origin: tuple[float, float] = (0.0, 0.0),
                 memory: int = 8) -> None:  # fmt: skip
        super().__init__(size, config, origin)
        self.map = FadingScanMap(size, config.resolution, origin, memory)
        self.guide.set_map(self._snapshot())


__all__ = ["FadingScanGuide", "FadingScanMap"]
