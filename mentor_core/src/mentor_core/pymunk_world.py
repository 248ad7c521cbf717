"""Reference physics: a world and its robots in pymunk, queried without stepping.

The ROS simulator node uses this module; the batched engine (:mod:`mentor_core.sensors`,
:mod:`mentor_core.collision`) is tested against it. Each :class:`PymunkWorld` owns a fresh
``pymunk.Space`` with ``collision_persistence = 0`` (no contact state carried between queries)
and is never stepped: robots are kinematic bodies *placed* at their poses, and readings and
collisions are pure geometric queries of that placement, so results are deterministic and
independent of any query history.

Geometry:

* Obstacles: static boxes (``pymunk.Poly`` with the 4 corners, radius 0).
* Arena walls: four static boxes outside ``[0, size]^2`` whose inner faces lie exactly on
  ``x = 0``, ``x = size``, ``y = 0``, ``y = size``.
* Robots: a ``length x width`` box on a kinematic body per robot; each robot has its own shape
  filter group, so its rays and collision checks ignore its own body but see every other
  robot.

Range reading of a sensor: the first hit of the segment ``o -> o + R u`` (``o``, ``u`` the
sensor's map-frame origin and direction, ``R`` the sensor range) by
``Space.segment_query_first``: ``alpha * R`` m, or ``+inf`` when nothing lies within ``R``
(REP-117); 0 when the origin is inside a shape.

Collision: the body overlaps an obstacle, a wall or another robot with penetration depth
above ``CONTACT_TOLERANCE`` (touching is free), or a body corner lies outside the arena.
pymunk reports depth 0 for two exactly coincident boxes, so a shape whose centre lies inside
the other one (or the other way round) also counts as overlapping.
"""

from __future__ import annotations

import numpy as np
import pymunk
from numpy.typing import ArrayLike, NDArray

from mentor_core.collision import sample_counts
from mentor_core.kinematics import arc_samples, wrap_angle
from mentor_core.robots import RobotProfile, body_corners
from mentor_core.sensors import sensor_frames
from mentor_core.world import World

# Penetration (m) below which two shapes only touch: pymunk reports exact touching as a
# contact of depth ~0, which must not count as a collision.
CONTACT_TOLERANCE = 1e-9

Pose = tuple[float, float, float]


def _box(body: pymunk.Body, x0: float, y0: float, x1: float, y1: float) -> pymunk.Poly:
    return pymunk.Poly(body, [(x0, y0), (x1, y0), (x1, y1), (x0, y1)], radius=0.0)


def _pose(pose: ArrayLike) -> Pose:
    p = np.asarray(pose, dtype=np.float64).reshape(-1)
    if p.shape != (3,) or not np.isfinite(p).all():
        raise ValueError(f"a pose is three finite numbers (x, y, theta), got {pose!r}")
    return float(p[0]), float(p[1]), float(wrap_angle(p[2]))


class PymunkWorld:
    """A :class:`World` in a fresh pymunk space, with any number of named robots of one profile.

    ``ranges``, ``collides`` and ``swept_collision`` take the pose to test; ``robot`` names the
    robot whose own body the query ignores (None: a free probe, which sees every robot).
    """

    def __init__(self, world: World, profile: RobotProfile) -> None:
        self.world = world
        self.profile = profile
        self._space = pymunk.Space()
        self._space.collision_persistence = 0
        static = self._space.static_body
        shapes = [_box(static, *map(float, box)) for box in world.obstacles]
        s, t = world.size, max(1.0, world.size)  # t: wall thickness, any positive value works
        shapes += [
            _box(static, -t, -t, 0.0, s + t),
            _box(static, s, -t, s + t, s + t),
            _box(static, 0.0, -t, s, 0.0),
            _box(static, 0.0, s, s, s + t),
        ]
        self._space.add(*shapes)
        self._robots: dict[str, tuple[pymunk.Body, pymunk.Poly]] = {}
        self._groups: dict[str, int] = {}
        # the probe body tests poses for shape queries; it is never added to the space
        self._probe_body = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
        self._probe = pymunk.Poly(self._probe_body, list(profile.body_polygon), radius=0.0)

    @property
    def robot_names(self) -> tuple[str, ...]:
        """Names of the robots in the world, sorted."""
        return tuple(sorted(self._robots))

    def add_robot(self, name: str, pose: ArrayLike) -> None:
        """Place a new robot's body at ``pose`` (x, y, theta); ValueError if the name is taken."""
        if name in self._robots:
            raise ValueError(f"robot {name!r} already exists")
        body = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
        shape = pymunk.Poly(body, list(self.profile.body_polygon), radius=0.0)
        # groups start at 1: group 0 means "no group" and would filter nothing
        group = 1 + max(self._groups.values(), default=0)
        shape.filter = pymunk.ShapeFilter(group=group)
        self._space.add(body, shape)
        self._robots[name] = (body, shape)
        self._groups[name] = group
        self.set_pose(name, pose)

    def remove_robot(self, name: str) -> None:
        """Take a robot out of the world."""
        body, shape = self._robots.pop(self._known(name))
        del self._groups[name]
        self._space.remove(body, shape)

    def set_pose(self, name: str, pose: ArrayLike) -> None:
        """Move a robot's body to ``pose`` (placement, no dynamics)."""
        body, _ = self._robots[self._known(name)]
        x, y, theta = _pose(pose)
        body.position = (x, y)
        body.angle = theta
        # the space is never stepped, so the spatial index must learn the new placement here
        self._space.reindex_shapes_for_body(body)

    def pose(self, name: str) -> Pose:
        """Current pose (x, y, theta) of a robot."""
        body, _ = self._robots[self._known(name)]
        return float(body.position.x), float(body.position.y), float(body.angle)

    def ranges(self, pose: ArrayLike, robot: str | None = None) -> NDArray[np.float64]:
        """Readings (k,) in m of the profile's sensors at ``pose``, +inf when nothing in range."""
        shape_filter = self._filter(robot)
        frames = sensor_frames(np.asarray(_pose(pose))[None, :], self.profile)[0]
        reach = self.profile.sensor_range
        out = np.full(self.profile.n_sensors, np.inf, dtype=np.float64)
        for i, (ox, oy, a) in enumerate(frames):
            end = (float(ox + reach * np.cos(a)), float(oy + reach * np.sin(a)))
            hit = self._space.segment_query_first((float(ox), float(oy)), end, 0.0, shape_filter)
            if hit is not None:
                out[i] = hit.alpha * reach
        return out

    def collides(self, pose: ArrayLike, robot: str | None = None) -> bool:
        """Whether the body at ``pose`` penetrates an obstacle, a wall or another robot."""
        x, y, theta = _pose(pose)
        corners = body_corners(self.profile, (x, y, theta))
        tol, size = CONTACT_TOLERANCE, self.world.size
        if corners.min() < -tol or corners.max() > size + tol:
            return True
        self._probe_body.position = (x, y)
        self._probe_body.angle = theta
        self._probe.filter = self._filter(robot)
        for info in self._space.shape_query(self._probe):
            if any(point.distance < -tol for point in info.contact_point_set.points):
                return True
            # pymunk reports depth 0 for exactly coincident boxes; a centre inside the other
            # shape still tells overlap from touching
            other = info.shape
            if (
                other.point_query((x, y)).distance < -tol
                or self._probe.point_query(other.bb.center()).distance < -tol
            ):
                return True
        return False

    def swept_collision(
        self,
        pose: ArrayLike,
        dtheta: float,
        ds: float,
        n_samples: int | None = None,
        robot: str | None = None,
    ) -> int:
        """First colliding sample along the decision's exact unicycle arc, or -1.

        The arc (end heading ``theta + dtheta``, path length ``ds``) is sampled at fractions
        ``j / n_samples``, j = 0..n_samples (:func:`mentor_core.kinematics.arc_samples`);
        sample 0 is the start pose. ``n_samples`` defaults to
        :func:`mentor_core.collision.sample_counts`, so the verdict is comparable with the
        batched :func:`mentor_core.collision.swept_collision`.
        """
        n = int(sample_counts(dtheta, ds, self.profile)) if n_samples is None else n_samples
        samples = arc_samples(np.asarray(_pose(pose))[None, :], dtheta, ds, n)[0]
        for j, sample in enumerate(samples):
            if self.collides(sample, robot):
                return j
        return -1

    def _known(self, name: str) -> str:
        if name not in self._robots:
            raise KeyError(f"no robot {name!r} (robots: {', '.join(self.robot_names) or 'none'})")
        return name

    def _filter(self, robot: str | None) -> pymunk.ShapeFilter:
        if robot is None:
            return pymunk.ShapeFilter()
        return pymunk.ShapeFilter(group=self._groups[self._known(robot)])

