"""Reference physics: a world and its robots in pymunk, queried without stepping.

The ROS simulator node uses this module; the batched engine (:mod:`mentor_core.sim.sensors`,
:mod:`mentor_core.sim.collision`) is tested against it. Each :class:`PymunkWorld` owns a fresh
``pymunk.Space`` with ``collision_persistence = 0`` (no contact state carried between queries)
and is never stepped: robots are kinematic bodies *placed* at their poses, and readings and
collisions are pure geometric queries of that placement, so results are deterministic and
independent of any query history.

Geometry:

* Obstacles: static boxes (``pymunk.Poly`` with the 4 corners, radius 0).
* Arena walls: four static boxes outside ``[0, size]^2`` whose inner faces lie exactly on
  ``x = 0``, ``x = size``, ``y = 0``, ``y = size``.
* Robots: a ``length x width`` box on a kinematic body per robot, of the world's profile or of
  a profile of its own (a UGV and a Swarm-Robot may share one world); each robot has its own
  shape filter group, so its rays and collision checks ignore its own body but see every other
  robot.

Range reading of a sensor: the nearest first hit, over its beam's rays, of the segment
``o -> o + R u`` (``o``, ``u`` a ray's map-frame origin and direction from
``sensors.beam_frames``, ``R`` the sensor range) by ``Space.segment_query_first``:
``alpha * R`` m, or ``+inf`` when nothing lies within ``R`` (REP-117); 0 when the origin is
inside a shape.

Collision: the body overlaps an obstacle, a wall or another robot with penetration depth
above ``CONTACT_TOLERANCE`` (touching is free), or a body corner lies outside the arena.
pymunk reports depth 0 for two exactly coincident boxes, so a shape whose centre lies inside
the other one (or the other way round) also counts as overlapping.

Driving (:meth:`PymunkWorld.drive`): one decision moves a robot along its exact unicycle arc,
sampled as in the batched engine (:func:`mentor_core.sim.collision.sample_counts`,
:func:`mentor_core.sim.kinematics.arc_samples`), and stops at the first event along the samples,
exactly as :meth:`mentor_core.sim.engine.BatchEngine.step` does: the first colliding sample stops
the robot at the sample before it; otherwise the first sample within the goal radius stops it
there (reached); otherwise it ends at the end of the arc.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pymunk
from numpy.typing import ArrayLike, NDArray

from mentor_core.sim.collision import sample_counts
from mentor_core.sim.kinematics import arc_samples, wrap_angle
from mentor_core.sim.robots import RobotProfile, body_corners
from mentor_core.sim.sensors import beam_frames
from mentor_core.sim.world import World

# Penetration (m) below which two shapes only touch: pymunk reports exact touching as a
# contact of depth ~0, which must not count as a collision.
CONTACT_TOLERANCE = 1e-9

Pose = tuple[float, float, float]


@dataclass(frozen=True)
class Move:
    """Outcome of one decision of one robot (:meth:`PymunkWorld.drive`).

    Attributes:
        pose: where the robot stopped, (x, y, theta) (m, m, rad).
        collided: the swept body hit a box, a wall or another robot (it stopped before).
        reached: a sample came within the goal radius (the robot stopped there).
        fraction: share of the control period used, ``stop_sample / n_samples`` in [0, 1].
    """

    pose: Pose
    collided: bool
    reached: bool
    fraction: float


def _box(body: pymunk.Body, x0: float, y0: float, x1: float, y1: float) -> pymunk.Poly:
    return pymunk.Poly(body, [(x0, y0), (x1, y0), (x1, y1), (x0, y1)], radius=0.0)


def _pose(pose: ArrayLike) -> Pose:
    p = np.asarray(pose, dtype=np.float64).reshape(-1)
    if p.shape != (3,) or not np.isfinite(p).all():
        raise ValueError(f"a pose is three finite numbers (x, y, theta), got {pose!r}")
    return float(p[0]), float(p[1]), float(wrap_angle(p[2]))


class PymunkWorld:
    """A :class:`World` in a fresh pymunk space, with any number of named robots.

    ``profile`` is the default robot profile; :meth:`add_robot` may give a robot another one.
    ``ranges``, ``collides`` and ``swept_collision`` take the pose to test; ``robot`` names the
    robot whose own body the query ignores and whose profile (sensors, body) the query uses
    (None: a free probe of the default profile, which sees every robot).
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
        self._profiles: dict[str, RobotProfile] = {}
        self._poses: dict[str, Pose] = {}
        # probe bodies test poses for shape queries (one per body shape); never in the space
        self._probes: dict[tuple[float, float], tuple[pymunk.Body, pymunk.Poly]] = {}

    @property
    def robot_names(self) -> tuple[str, ...]:
        """Names of the robots in the world, sorted."""
        return tuple(sorted(self._robots))

    def add_robot(
        self, name: str, pose: ArrayLike, profile: RobotProfile | None = None
    ) -> None:
        """Place a new robot's body at ``pose`` (x, y, theta); ValueError if the name is taken.

        ``profile`` gives the robot's body and sensors (default: the world's profile).
        """
        if name in self._robots:
            raise ValueError(f"robot {name!r} already exists")
        own = self.profile if profile is None else profile
        body = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
        shape = pymunk.Poly(body, list(own.body_polygon), radius=0.0)
        # groups start at 1: group 0 means "no group" and would filter nothing
        group = 1 + max(self._groups.values(), default=0)
        shape.filter = pymunk.ShapeFilter(group=group)
        self._space.add(body, shape)
        self._robots[name] = (body, shape)
        self._groups[name] = group
        self._profiles[name] = own
        self.set_pose(name, pose)

    def remove_robot(self, name: str) -> None:
        """Take a robot out of the world."""
        body, shape = self._robots.pop(self._known(name))
        del self._groups[name], self._profiles[name], self._poses[name]
        self._space.remove(body, shape)

    def profile_of(self, name: str) -> RobotProfile:
        """The profile (body, sensors) of a robot."""
        return self._profiles[self._known(name)]

    def set_pose(self, name: str, pose: ArrayLike) -> None:
        """Move a robot's body to ``pose`` (placement, no dynamics; theta wrapped)."""
        self._known(name)
        self._place(name, _pose(pose))

    def _place(self, name: str, pose: Pose) -> None:
        body, _ = self._robots[name]
        body.position = (pose[0], pose[1])
        body.angle = pose[2]
        # the space is never stepped, so the spatial index must learn the new placement here
        self._space.reindex_shapes_for_body(body)
        self._poses[name] = pose

    def pose(self, name: str) -> Pose:
        """Current pose (x, y, theta) of a robot, exactly as placed."""
        return self._poses[self._known(name)]

    def ranges(self, pose: ArrayLike, robot: str | None = None) -> NDArray[np.float64]:
        """Readings (k,) in m of the robot's (or the default profile's) sensors at ``pose``,
        +inf when nothing lies in range."""
        shape_filter = self._filter(robot)
        profile = self.profile if robot is None else self._profiles[robot]
        frames = beam_frames(np.asarray(_pose(pose))[None, :], profile)[0]
        reach = profile.sensor_range
        out = np.full(profile.n_sensors, np.inf, dtype=np.float64)
        for i, rays in enumerate(frames):
            for ox, oy, a in rays:  # a beam reads its nearest ray's hit
                end = (float(ox + reach * np.cos(a)), float(oy + reach * np.sin(a)))
                hit = self._space.segment_query_first(
                    (float(ox), float(oy)), end, 0.0, shape_filter
                )
                if hit is not None:
                    out[i] = min(out[i], hit.alpha * reach)
        return out

    def cast(
        self, origin: ArrayLike, angles: ArrayLike, reach: float, robot: str | None = None
    ) -> NDArray[np.float64]:
        """Distance (m) from ``origin`` (x, y) along each map-frame direction ``angles`` (rad)
        to the first obstacle, wall or other robot, as :meth:`ranges` measures it
        (``alpha * reach``); +inf when nothing lies within ``reach`` (a simulated lidar)."""
        ox, oy = (float(v) for v in np.asarray(origin, dtype=np.float64).reshape(-1)[:2])
        a = np.asarray(angles, dtype=np.float64).reshape(-1)
        shape_filter = self._filter(robot)
        out = np.full(a.size, np.inf, dtype=np.float64)
        ends = np.stack([ox + reach * np.cos(a), oy + reach * np.sin(a)], axis=1)
        for k, (ex, ey) in enumerate(ends.tolist()):
            hit = self._space.segment_query_first((ox, oy), (ex, ey), 0.0, shape_filter)
            if hit is not None:
                out[k] = hit.alpha * reach
        return out

    def collides(
        self, pose: ArrayLike, robot: str | None = None, profile: RobotProfile | None = None
    ) -> bool:
        """Whether the body at ``pose`` penetrates an obstacle, a wall or another robot.

        The body is ``robot``'s (whose own body is ignored) or, for a free probe, one of
        ``profile`` (default: the world's profile).
        """
        x, y, theta = _pose(pose)
        if robot is not None:
            profile = self._profiles[self._known(robot)]
        elif profile is None:
            profile = self.profile
        corners = body_corners(profile, (x, y, theta))
        tol, size = CONTACT_TOLERANCE, self.world.size
        if corners.min() < -tol or corners.max() > size + tol:
            return True
        probe_body, probe = self._probe(profile)
        probe_body.position = (x, y)
        probe_body.angle = theta
        probe.filter = self._filter(robot)
        for info in self._space.shape_query(probe):
            if any(point.distance < -tol for point in info.contact_point_set.points):
                return True
            # pymunk reports depth 0 for exactly coincident boxes; a centre inside the other
            # shape still tells overlap from touching
            other = info.shape
            if (
                other.point_query((x, y)).distance < -tol
                or probe.point_query(other.bb.center()).distance < -tol
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
        ``j / n_samples``, j = 0..n_samples (:func:`mentor_core.sim.kinematics.arc_samples`);
        sample 0 is the start pose. ``n_samples`` defaults to
        :func:`mentor_core.sim.collision.sample_counts`, so the verdict is comparable with the
        batched :func:`mentor_core.sim.collision.swept_collision`.
        """
        profile = self.profile if robot is None else self._profiles[self._known(robot)]
        n = int(sample_counts(dtheta, ds, profile)) if n_samples is None else n_samples
        samples = arc_samples(np.asarray(_pose(pose))[None, :], dtheta, ds, n)[0]
        for j, sample in enumerate(samples):
            if self.collides(sample, robot):
                return j
        return -1

    def drive(
        self,
        name: str,
        dtheta: float,
        ds: float,
        goal: ArrayLike | None = None,
        goal_radius: float | None = None,
    ) -> Move:
        """Move robot ``name`` by one decision ``(dtheta, ds)`` (rad, m); see the module docstring.

        The arc starts at the robot's current pose and is sampled with
        :func:`mentor_core.sim.collision.sample_counts` of its profile, as in the batched engine.
        ``goal`` (x, y) (m) and ``goal_radius`` (m, default the profile's) make the robot stop
        on arrival; without a goal it only stops at a collision. The other robots stay where
        they are and are obstacles to this one. ValueError for a non-finite decision.
        """
        profile = self._profiles[self._known(name)]
        if not (np.isfinite(dtheta) and np.isfinite(ds)):
            raise ValueError(f"decision of {name!r} is not finite (dtheta={dtheta}, ds={ds})")
        start = self._poses[name]
        n = int(sample_counts(dtheta, ds, profile))
        samples = arc_samples(np.asarray(start)[None, :], dtheta, ds, n)[0]
        radius = profile.goal_radius if goal_radius is None else float(goal_radius)
        g = None if goal is None else np.asarray(goal, dtype=np.float64).reshape(-1)[:2]
        stop, collided, reached = n, False, False
        for j, sample in enumerate(samples):
            if self.collides(sample, name):
                stop, collided = max(j - 1, 0), True
                break
            if g is not None and np.hypot(sample[0] - g[0], sample[1] - g[1]) <= radius:
                stop, reached = j, True
                break
        end = samples[stop]
        pose = (float(end[0]), float(end[1]), float(end[2]))
        self._place(name, pose)
        return Move(pose=pose, collided=collided, reached=reached, fraction=stop / n)

    def _known(self, name: str) -> str:
        if name not in self._robots:
            raise KeyError(f"no robot {name!r} (robots: {', '.join(self.robot_names) or 'none'})")
        return name

    def _probe(self, profile: RobotProfile) -> tuple[pymunk.Body, pymunk.Poly]:
        key = (profile.length, profile.width)
        if key not in self._probes:
            body = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
            self._probes[key] = (body, pymunk.Poly(body, list(profile.body_polygon), radius=0.0))
        return self._probes[key]

    def _filter(self, robot: str | None) -> pymunk.ShapeFilter:
        if robot is None:
            return pymunk.ShapeFilter()
        return pymunk.ShapeFilter(group=self._groups[self._known(robot)])

