"""Goals given on goal topics (RViz's and Foxglove's goal tools, any ``PoseStamped``): turned
into ``map`` and checked against the known area, by the simulator and by the planner alike.

A goal may come in any frame the receiver can link to ``map`` (the simulator's tree,
:func:`session_frames`: ``map``, ``odom``, a robot's ``<ns>/base_link``; an empty frame is
``map``). One outside the known area (the arena ``[0, size]^2``, or the bounds of a map) is
refused (the robot could never reach it, and would only time out).

In the simulator (:meth:`mentor_core.runtime.sim_session.SimSession.give_goal`) a driving robot
takes a goal at once, with a new time budget from where it stands, and is judged against it;
a robot waiting for a goal (``wait_for_goals``) starts with it at the next step boundary (its
``started`` event then carries it); one given between episodes waits for the next
(``wait_for_goals`` only); the goal a robot already has changes nothing.
"""

from __future__ import annotations

import math
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


Bounds = tuple[float, float, float, float]  # xmin, ymin, xmax, ymax in map (m)
#: m: goals nearer each other than this are one goal (one goal may come twice, through two
#: subscriptions or two frames)
SAME_GOAL = 1e-9


def same_goal(a: Sequence[float] | None, b: Sequence[float] | None) -> bool:
    """``a`` and ``b`` are one goal (:data:`SAME_GOAL`); None is no goal."""
    if a is None or b is None:
        return a is None and b is None
    return math.hypot(float(a[0]) - float(b[0]), float(a[1]) - float(b[1])) <= SAME_GOAL


def bounds_fault(goal: Sequence[float], bounds: Bounds | None) -> str:
    """Why ``goal`` (x, y in ``map``) lies outside ``bounds`` (one line), or '' when it lies
    inside or no bounds are known."""
    if bounds is None:
        return ""
    x, y = float(goal[0]), float(goal[1])
    x0, y0, x1, y1 = bounds
    if x0 <= x <= x1 and y0 <= y <= y1:
        return ""
    return (
        f"goal ({x:.3f}, {y:.3f}) in {MAP_FRAME} lies outside the known area "
        f"[{x0:g}, {x1:g}] x [{y0:g}, {y1:g}] m; refused"
    )


def bounds_in(bounds: Bounds, transform: Transform2D) -> Bounds:
    """The axis-aligned box ``(xmin, ymin, xmax, ymax)`` about ``bounds``' four corners as
    ``transform`` carries them into another frame (its pose of the bounds' frame there): the
    area, such as the arena, seen from a frame turned against ``map``."""
    x0, y0, x1, y1 = bounds
    corners = [transform.apply_point(c) for c in ((x0, y0), (x1, y0), (x1, y1), (x0, y1))]
    xs, ys = [c[0] for c in corners], [c[1] for c in corners]
    return (min(xs), min(ys), max(xs), max(ys))


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
    why = bounds_fault(goal, (0.0, 0.0, size, size))
    return (None, why) if why else (goal, "")
