"""The planner's own TF buffer, for an installation without ``tf2_ros`` (its Python needs
tf2's C++ library, which has no wheel): the latest planar transform of each frame from
``/tf`` and ``/tf_static``, and lookups through the tree as ``tf2_ros.Buffer`` makes them at
the latest time (the planner node asks for nothing else).

Each link is a child's pose in its parent (:func:`~mentor_core.sim.transforms.planar_transform`)
and whether the child is upside down; a lookup composes the links up to the two frames'
common ancestor (:class:`~mentor_core.sim.transforms.FrameTree`), and a frame is upside down in
another when an odd number of links on the way between them are.
"""

from __future__ import annotations

from mentor_core.sim.transforms import FrameTree, Transform2D


class TfBuffer:
    """The latest transform of each frame (module docstring)."""

    def __init__(self) -> None:
        self._tree = FrameTree()
        self._inverted: dict[str, bool] = {}  # child -> upside down in its parent

    def set(self, parent: str, child: str, transform: Transform2D, inverted: bool = False) -> None:
        """``child``'s pose in ``parent`` (the latest: it replaces the one before).
        ValueError as :meth:`FrameTree.link` (an empty name, a loop)."""
        self._tree.link(parent, child, transform)
        self._inverted[child] = bool(inverted)

    def lookup(self, target: str, source: str) -> tuple[Transform2D, bool]:
        """The pose of ``source`` in ``target`` and whether ``source`` is upside down in it.
        LookupError when the two frames are not linked."""
        found = self._tree.lookup(target, source)
        up_source, up_target = self._tree.chain(source), self._tree.chain(target)
        common = next(f for f in up_source if f in up_target)  # lookup found one
        below = up_source[: up_source.index(common)] + up_target[: up_target.index(common)]
        return found, sum(self._inverted[f] for f in below) % 2 == 1


__all__ = ["TfBuffer"]
