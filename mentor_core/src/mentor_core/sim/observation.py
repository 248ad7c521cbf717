"""The planner's input and output: the ONE place that turns a robot's state into network inputs
and network outputs into actions. The trainer, the planner node and the tests all call these.

Network inputs, ``k + 3`` of them (``k`` = number of range sensors), in one of the two
encodings a profile carries (``RobotProfile.input_encoding``, set from the training config or
the genome's metadata by ``planner_settings.with_planner``):

``"paper"`` (paper, section III-B)::

    [U_1 .. U_k, dX, dY, theta]

* ``U_i``: reading of sensor ``i`` (profile order), m, clipped to ``[0, sensor_range]``; an
  out-of-range reading (+inf, REP-117) becomes ``sensor_range``.
* ``(dX, dY)``: the map-frame gradient of the goal signal ``S = 1 / d`` (``d`` the distance to
  the goal), bounded near the goal and scaled to magnitude <= 1 (see :func:`signal_gradient`).
* ``theta``: global heading, rad, wrapped to ``(-pi, pi]``.

A planner with a proximity scale (``RobotProfile.proximity_scale``, ``lambda`` m; not in the
paper) reads each ``U_i`` as a proximity instead (:func:`range_inputs`)::

    U_i = exp(-r_i / lambda)

1 at contact, ``e^-1`` at ``lambda``, near 0 for what lies far and ``exp(-sensor_range /
lambda)`` for nothing seen. Why: in metres a tree that comes into view 3 m away already
moves its input by a quarter of the input's range, and NEAT's steep sigmoid turns that into
a full turn, so the UGV's planners zig-zag wherever their 4 m sensors read anything
(experiment E061, "Where the UGV's full turns come from"); a proximity leaves what
is far nearly unseen and what is near salient.

A controller's stage may change the readings before either encoding (a view corridor:
:mod:`mentor_core.controller.view_corridor`).

``"egocentric"`` (the shipped training configs)::

    [U_1 .. U_k, cos beta, sin beta, S]

* ``U_i`` as above;
* ``(cos beta, sin beta)``: the direction of the same gradient in the body frame, unit length
  (``beta`` the goal's bearing from the robot's heading; ``(0, 0)`` on the goal itself);
* ``S = R / max(d, R)``: the goal signal ``1 / d`` bounded and scaled by the goal radius ``R``,
  1 inside the goal radius.

Why a second encoding: in the paper's the direction to the goal is scaled by ``(R / d)^2``
(0.01 at 10 m for the UGV) and steering towards it needs ``atan2(dY, dX) - theta`` wrapped
to ``(-pi, pi]``, a discontinuous function a small network hardly represents. The
egocentric inputs carry the same information (a planner that also needs the global heading
cannot use it: the arenas are random), and steering towards the goal is a monotone function of
``sin beta``. docs/algorithm.md gives the measured effect.

A planner with a context (``RobotProfile.feedback_action``, ``RobotProfile.memory_units``; not
in the paper, off by default) reads, after the goal inputs, what it output at its previous
decision (:func:`next_context`)::

    [..., o_1(t-1), o_2(t-1) (with feedback_action), m_1(t-1) .. m_j(t-1)]

the previous action outputs clipped to ``[0, 1]`` (before the clearance limit) and its ``j``
memory outputs, clipped to ``[0, 1]``; at the first decision of an episode or goal
:func:`initial_context`: ``(0.5, 0)`` (no turn, the smallest step) and zeros. Why: a
memoryless network cannot tell a dead end it has just entered from one it keeps returning
to, nor keep to one side of an obstacle; fed-back outputs are an Elman/Jordan context memory
NEAT can evolve to latch such a state, and the graph stays acyclic (one feed-forward pass per
decision, as the batched evaluator needs).

Network outputs ``(o_1, o_2)`` (clipped to ``[0, 1]``) map linearly onto the actions
``dtheta in [-heading_change_max, heading_change_max]`` (rad) and ``ds in [step_min,
step_max]`` (m). A planner with a clearance margin (``RobotProfile.clearance_margin``, not in
the paper) then shortens a step to the free range its sensors read ahead
(:func:`clearance_limit`). A decision becomes a Twist with ``angular.z = dtheta / dt``,
``linear.x = ds / dt`` over the control period ``dt`` (s).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from mentor_core.sim.kinematics import to_body, wrap_angle
from mentor_core.sim.robots import RobotProfile

FloatArray = NDArray[np.float64]
CLEARANCE_CONE = np.pi / 4  # sensors facing within this of the chord read "ahead", rad


def clip_ranges(ranges: ArrayLike, profile: RobotProfile) -> FloatArray:
    """Readings (n, k) in m clipped to ``[0, sensor_range]``; +inf becomes ``sensor_range``.

    Raises ValueError for a wrong number of sensors, a NaN or a negative reading.
    """
    r = np.atleast_2d(np.asarray(ranges, dtype=np.float64))
    if r.ndim != 2 or r.shape[1] != profile.n_sensors:
        raise ValueError(
            f"expected (n, {profile.n_sensors}) range readings for {profile.name!r}, "
            f"got shape {r.shape}"
        )
    if np.isnan(r).any():
        raise ValueError("range reading is NaN")
    if (r < 0.0).any():
        raise ValueError(f"range reading is negative ({r.min()} m)")
    return np.minimum(r, profile.sensor_range)


def range_inputs(ranges: ArrayLike, profile: RobotProfile) -> FloatArray:
    """The sensor inputs ``U`` (n, k) of readings (n, k) in m: :func:`clip_ranges`, or with
    the profile's proximity scale ``lambda`` the proximities ``exp(-r / lambda)`` of the
    clipped readings (module docstring). The same errors as :func:`clip_ranges`."""
    u = clip_ranges(ranges, profile)
    scale = profile.proximity_scale
    return u if scale is None else np.exp(-u / scale)


def ranges_from_inputs(inputs: ArrayLike, profile: RobotProfile) -> FloatArray:
    """The clipped readings (m, k) (m) that network inputs (m, >= k) were made of: the
    inverse of :func:`range_inputs`, for rules that act on the readings a network saw."""
    u = np.asarray(inputs, dtype=np.float64)[:, : profile.n_sensors]
    scale = profile.proximity_scale
    if scale is None:
        return u
    with np.errstate(divide="ignore"):
        return np.minimum(-scale * np.log(u), profile.sensor_range)


def signal_gradient(poses: ArrayLike, goals: ArrayLike, goal_radius: float) -> FloatArray:
    """Bounded, scaled gradient (n, 2) of the goal signal ``S = 1 / d`` in the map frame.

    With ``v = g - p`` (m) and ``d = |v|``, ``grad_p S = v / d^3``. Near the goal ``d`` is
    clamped below at the goal radius ``R`` in the magnitude term, and the result is scaled by
    ``R^2`` so that it is dimensionless and at most 1 in magnitude:

        (dX, dY) = R^2 * (v / d) / max(d, R)^2      ((0, 0) at d = 0)

    Its magnitude is 1 inside the goal radius and ``(R / d)^2`` outside; it points at the goal.
    """
    unit, d = _goal_direction(poses, goals)
    return unit * (goal_radius / np.maximum(d, goal_radius))[:, None] ** 2


def _goal_direction(poses: ArrayLike, goals: ArrayLike) -> tuple[FloatArray, FloatArray]:
    """Map-frame unit vectors (n, 2) from each pose to its goal ((0, 0) on the goal itself)
    and the distances (n,), m."""
    p = np.atleast_2d(np.asarray(poses, dtype=np.float64))
    g = np.atleast_2d(np.asarray(goals, dtype=np.float64))
    v = g[:, :2] - p[:, :2]
    d = np.hypot(v[:, 0], v[:, 1])
    unit = np.divide(v, d[:, None], out=np.zeros_like(v), where=d[:, None] > 0.0)
    return unit, d


def network_inputs(
    ranges: ArrayLike, poses: ArrayLike, goals: ArrayLike, profile: RobotProfile,
    context: ArrayLike | None = None,
) -> FloatArray:
    """Network inputs (n, ``profile.n_inputs``) = ``[range inputs, dX, dY, theta, context]``
    (module docstring; the range inputs of :func:`range_inputs`).

    Args:
        ranges: (n, k) sensor readings, m, in the profile's sensor order; +inf = nothing seen.
        poses: (n, 3) robot poses (x, y, theta) in the map frame (m, m, rad).
        goals: (n, 2) goal positions in the map frame, m.
        profile: the robot.
        context: (n, ``profile.n_context``) what each network output at its previous decision
            (:func:`next_context`, :func:`initial_context`); needed when the profile has a
            context, else ignored.

    Raises ValueError for NaN or negative readings, non-finite poses or goals, or shapes that
    do not match.
    """
    r = clip_ranges(ranges, profile)
    p, g = checked_poses(poses, goals, r.shape[0])
    u = range_inputs(r, profile)
    out = np.empty((u.shape[0], profile.n_inputs), dtype=np.float64)
    out[:, : profile.n_sensors] = u
    k = profile.n_sensors
    if profile.input_encoding == "egocentric":
        out[:, k : k + 3] = egocentric_goal(p, g, profile.goal_radius)
    else:
        out[:, k : k + 2] = signal_gradient(p, g, profile.goal_radius)
        out[:, k + 2] = wrap_angle(p[:, 2])
    if profile.n_context:
        if context is None:
            raise ValueError("a planner with a context (memory) needs its previous outputs")
        c = np.asarray(context, dtype=np.float64)
        if c.shape != (u.shape[0], profile.n_context):
            raise ValueError(f"expected a ({u.shape[0]}, {profile.n_context}) context, got "
                             f"shape {c.shape}")  # fmt: skip
        out[:, k + 3 :] = c
    return out


def checked_poses(
    poses: ArrayLike, goals: ArrayLike, n: int
) -> tuple[FloatArray, FloatArray]:
    """Poses ``(n, 3)`` and goals ``(n, 2)`` as float arrays; ValueError for other shapes or
    a value that is not finite."""
    p = np.atleast_2d(np.asarray(poses, dtype=np.float64))
    g = np.atleast_2d(np.asarray(goals, dtype=np.float64))
    if p.shape != (n, 3) or g.shape != (n, 2):
        raise ValueError(f"expected poses ({n}, 3) and goals ({n}, 2), got {p.shape} and "
                         f"{g.shape}")  # fmt: skip
    if not (np.isfinite(p).all() and np.isfinite(g).all()):
        raise ValueError("pose or goal is not finite")
    return p, g


def initial_context(n: int, profile: RobotProfile) -> FloatArray:
    """The context (n, ``profile.n_context``) of a first decision: the action outputs of "no
    turn, the smallest step" ``(0.5, 0)`` with ``feedback_action``, then zero memory."""
    context = np.zeros((n, profile.n_context), dtype=np.float64)
    if profile.feedback_action:
        context[:, 0] = 0.5
    return context


def next_context(outputs: ArrayLike, profile: RobotProfile) -> FloatArray:
    """The context (n, ``profile.n_context``) the next decision reads, from this decision's
    outputs (n, ``profile.n_outputs``): ``[o_1, o_2]`` with ``feedback_action``, then the
    memory outputs ``m_1 .. m_j``, all clipped to ``[0, 1]`` (their range under the sigmoid;
    an unbounded activation cannot make the loop grow without bound).
    Raises ValueError for a wrong shape or NaN (:func:`actions_from_outputs`)."""
    o = np.clip(_outputs(outputs, profile), 0.0, 1.0)
    return o[:, 0 if profile.feedback_action else 2 :]


def egocentric_goal(poses: ArrayLike, goals: ArrayLike, goal_radius: float) -> FloatArray:
    """Goal inputs (n, 3) of the egocentric encoding: ``[cos beta, sin beta, S]``.

    With ``v = g - p`` and ``d = |v|``, the unit direction ``v / d`` rotated into the body frame
    (by ``-theta``) is ``(cos beta, sin beta)``, ``(0, 0)`` at ``d = 0``;
    ``S = R / max(d, R)`` (``R`` the goal radius).
    """
    unit, d = _goal_direction(poses, goals)
    theta = np.atleast_2d(np.asarray(poses, dtype=np.float64))[:, 2]
    out = np.empty((unit.shape[0], 3), dtype=np.float64)
    out[:, :2] = to_body(theta, unit)
    out[:, 2] = goal_radius / np.maximum(d, goal_radius)
    return out


def actions_from_outputs(
    outputs: ArrayLike, profile: RobotProfile, ranges: ArrayLike | None = None
) -> tuple[FloatArray, FloatArray]:
    """Actions ``(dtheta (n,), ds (n,))`` from network outputs (n, ``profile.n_outputs``):
    the first two, ``(o_1, o_2)`` (the memory outputs are not actions).

    ``o`` clipped to [0, 1]; ``dtheta = hmax (2 o_1 - 1)`` rad, ``ds = step_min + (step_max -
    step_min) o_2`` m, then ``ds <= clearance_limit(ranges, dtheta)`` when the profile has a
    clearance margin (``ranges`` (n, k), the readings the inputs were made of, are then
    required). Raises ValueError for NaN outputs or a wrong shape.
    """
    o = np.clip(_outputs(outputs, profile)[:, :2], 0.0, 1.0)
    dtheta = profile.heading_change_max * (2.0 * o[:, 0] - 1.0)
    ds = profile.step_min + (profile.step_max - profile.step_min) * o[:, 1]
    if profile.clearance_margin is not None:
        if ranges is None:
            raise ValueError("a planner with a clearance margin needs the range readings")
        ds = np.minimum(ds, clearance_limit(ranges, dtheta, profile))
    return dtheta, ds


def _outputs(outputs: ArrayLike, profile: RobotProfile) -> FloatArray:
    """Network outputs as an (n, ``profile.n_outputs``) array; ValueError for another shape
    or a NaN."""
    o = np.atleast_2d(np.asarray(outputs, dtype=np.float64))
    if o.ndim != 2 or o.shape[1] != profile.n_outputs:
        raise ValueError(
            f"expected (n, {profile.n_outputs}) network outputs, got shape {o.shape}"
        )
    if np.isnan(o).any():
        raise ValueError("network output is NaN")
    return o


def clearance_limit(ranges: ArrayLike, dtheta: ArrayLike, profile: RobotProfile) -> FloatArray:
    """Longest step (n,) m that the readings (n, k) allow for heading changes ``dtheta`` (n,).

    Not in the paper. A decision moves the robot along an arc whose chord points at
    ``phi = dtheta / 2`` in the body frame. Each sensor facing within 45 deg of the chord
    (inclusive) saw something ``U_i cos(a_i - phi)`` along it (``U_i`` the clipped reading,
    ``a_i`` the facing; a sensor with a beam counts as facing its beam's axis, though its
    nearest hit may lie anywhere in the beam): for a flat wall across the path, exactly the
    wall's distance (for a single ray; at most that for a beam). The step
    keeps the margin ``m`` (``profile.clearance_margin``) to the nearest, but may always take
    ``step_min``:

        ds_max = clip(min_{i : |wrap(a_i - phi)| <= 45 deg} U_i cos(a_i - phi) - m,
                      step_min, step_max)

    With no sensor in the cone the limit is ``step_max``. Raises ValueError as
    :func:`clip_ranges`.
    """
    u = clip_ranges(ranges, profile)
    half = 0.5 * np.asarray(dtheta, dtype=np.float64).reshape(-1, 1)
    off = wrap_angle(profile.sensor_angles[None, :] - half)
    ahead = np.abs(off) <= CLEARANCE_CONE + 1e-9  # inclusive: 45 deg turns see both neighbours
    along = np.where(ahead, u * np.cos(off), np.inf).min(axis=1)
    limit: FloatArray = np.clip(
        along - (profile.clearance_margin or 0.0), profile.step_min, profile.step_max
    )
    return limit


def twist_from_action(
    dtheta: ArrayLike, ds: ArrayLike, dt: float
) -> tuple[FloatArray, FloatArray]:
    """Twist of one decision: ``(angular_z, linear_x) = (dtheta / dt, ds / dt)`` (rad/s, m/s)."""
    period = _period(dt)
    return np.asarray(dtheta, dtype=np.float64) / period, np.asarray(ds, dtype=np.float64) / period


def action_from_twist(
    angular_z: ArrayLike, linear_x: ArrayLike, dt: float
) -> tuple[FloatArray, FloatArray]:
    """Decision of a twist held for ``dt`` s: ``(dtheta, ds) = (angular_z dt, linear_x dt)``."""
    period = _period(dt)
    return (
        np.asarray(angular_z, dtype=np.float64) * period,
        np.asarray(linear_x, dtype=np.float64) * period,
    )


def experience_point(
    ranges_t: ArrayLike, action: ArrayLike, ranges_t1: ArrayLike, profile: RobotProfile
) -> FloatArray:
    """Experience points V = [U(t), A(t), U(t+1)] (paper eq. 7), (n, 2k + 2).

    ``U`` are readings clipped as network inputs (:func:`clip_ranges`, m); ``A = (dtheta,
    ds)`` (rad, m) is the action taken between t and t + 1, given as (n, 2).
    """
    u0 = clip_ranges(ranges_t, profile)
    u1 = clip_ranges(ranges_t1, profile)
    a = np.atleast_2d(np.asarray(action, dtype=np.float64))
    if a.shape != (u0.shape[0], 2) or u1.shape != u0.shape:
        raise ValueError(
            f"expected actions ({u0.shape[0]}, 2) and next readings {u0.shape}, "
            f"got {a.shape} and {u1.shape}"
        )
    if not np.isfinite(a).all():
        raise ValueError("action is not finite")
    return np.concatenate([u0, a, u1], axis=1)


def _period(dt: float) -> float:
    if not np.isfinite(dt) or dt <= 0.0:
        raise ValueError(f"control period must be positive and finite, got {dt}")
    return float(dt)
