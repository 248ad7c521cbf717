"""Goals given to the simulator's robots on goal topics: turned into ``map``, checked against
the arena, and kept for robots that cannot take them yet.

A goal may come in any frame of the simulator's tree (:func:`session_frames`: ``map``,
``odom``, a robot's ``<ns>/base_link``; an empty frame is ``map``). One outside the arena
``[0, size]^2`` is refused (the robot could never reach it, and would only time out).
"""

from __future__ import annotations

from collections.abc import Sequence

from mentor_core.runtime.simulator import ReferenceSimulator
from mentor_core.runtime.wiring import Wiring
from mentor_core.sim.frames import MAP_FRAME, ODOM_FRAME
from mentor_core.sim.robot_description import BASE_LINK, frame_id
from mentor_core.sim.transforms import FrameTree, Transform2D


def session_frames(sim: ReferenceSimulator, wiring: Wiring) -> FrameTree:
    """The simulator's frames now: ``map -> odom`` and ``odom -> <ns>/base_link`` of every
    robot placed in the world."""
    tree = FrameTree()
    tree.link(MAP_FRAME, ODOM_FRAME, wiring.map_to_odom)
    for name in sim.robots:
        pose = wiring.odom_pose(sim.pose(name))
        tree.link(ODOM_FRAME, frame_id(name, BASE_LINK), Transform2D(*pose))
    return tree


def goal_in_map(
    tree: FrameTree, frame: str, xy: Sequence[float], arena_size: float
) -> tuple[tuple[float, float] | None, str]:
    """``xy`` (m) in ``frame`` turned into ``map`` and checked against the arena: ``(goal,
    "")``, or ``(None, why)`` when it is refused."""
    try:
        goal = tree.lookup(MAP_FRAME, frame or MAP_FRAME).apply_point(xy)
    except (LookupError, ValueError) as err:
        return None, f"goal refused: {err}"
    size = float(arena_size)
    if not (0.0 <= goal[0] <= size and 0.0 <= goal[1] <= size):
        return None, (
            f"goal ({goal[0]:.3f}, {goal[1]:.3f}) in {MAP_FRAME} lies outside the arena "
            f"[0, {size:g}] x [0, {size:g}] m; refused"
        )
    return goal, ""
