"""The planner node's global plan (``global_plan:=true``, or a deployment with a scan map): Nav2's
planner / controller split, with the evolved network as the controller.

The node follows a ``nav_msgs/Path`` it is given on ``plan`` (until its goal changes) or plans
one itself on the ``nav_msgs/OccupancyGrid`` it receives on ``map_topic`` (``/map``, latched),
and steers its network towards the point ``lookahead`` m along that path
(:class:`mentor_core.GuidedPlanner`); it publishes the path it follows on ``global_plan``
(latched, for RViz). Until a map or a path has come it does not decide (as Nav2's controller
has nothing to follow): an observation waits for it, and the node's watchdog sends zero
Twists with a warning if it does not come. The map and the path are in ``map``, so the node
decides there: the odometry's pose and the goal are taken into ``map`` through ``map -> odom``
(TF, or the ``map_to_odom`` parameter), and a localiser's correction of ``map -> odom`` moves
the robot on the map, not the map under the robot.

With a deployment whose ``scan_map`` is set (``deployment:=shipped``) it plans instead on a
map of what its own scans read, unknown space free, with the deployment's plan settings
(:class:`mentor_core.ScanGuidedPlanner`, as ``mentor-bench --deployment`` runs the planners): a
square of ``scan_map_size`` m from ``scan_map_origin`` in the frame it decides in (the
odometry frame), or with a size of 0 a map that grows from the first pose when it decides on
its timer (``scan_map_max_cells`` at most, then it rolls), and in lockstep the square about
the simulator's arena (``/mentor/obstacles``) in that frame, which it waits for. Deciding on
its timer, its plans are made on a thread beside the decisions (:class:`mentor_core.ThreadPlans`,
again at least every ``plan_period`` s); in lockstep inside the decision, as the benchmark
makes them (``docs/ros.md``, "Planning beside the controller"). The map starts empty at each
simulator episode's ``started`` event, as each benchmark episode does, and is kept from goal
to goal (``scan_map_keep``, the default; experiment E048, "The scan map from goal to
goal"), or with ``scan_map_keep:=false`` starts empty at each new goal too. It is published on
``scan_map`` (latched, in the odometry frame, for RViz) with each new plan and at most every
:data:`MAP_EVERY_S` s of the node's clock in between.

Everything computed is ``mentor_core``; this module declares the parameters, makes the topics
and converts the messages (:mod:`.conversions`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
from builtin_interfaces.msg import Time
from nav_msgs.msg import OccupancyGrid as OccupancyGridMsg
from nav_msgs.msg import Path
from numpy.typing import ArrayLike
from rcl_interfaces.msg import FloatingPointRange, ParameterDescriptor
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy

from mentor_core import (
    MAX_CELLS,
    Bounds,
    GenomePlanner,
    GuideConfig,
    GuidedPlanner,
    MentorError,
    MountedScan,
    PlannerFrames,
    PlanResult,
    ScanGuidedPlanner,
    ThreadPlans,
    bounds_in,
    guide_config,
    warm_up_scan_map,
)
from mentor_planner_node import conversions
from mentor_ros_common.messages import occupancy_grid_msg

WARN_EVERY_S = 5.0
#: s (node clock) between two publications of a scan map whose plan has not changed
MAP_EVERY_S = 1.0
_NS_PER_S = 1_000_000_000
#: the map: latched, as map_server and the simulator publish it
QOS_MAP = QoSProfile(
    history=HistoryPolicy.KEEP_LAST,
    depth=1,
    reliability=ReliabilityPolicy.RELIABLE,
    durability=DurabilityPolicy.TRANSIENT_LOCAL,
)
#: a given path: volatile, so plain and latched publishers both match
QOS_PATH_IN = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE)
#: the path followed: latched, so RViz shows it when it subscribes late
QOS_PATH_OUT = QOS_MAP


def _descriptor(text: str, low: float | None = None) -> ParameterDescriptor:
    extra: dict[str, Any] = {}
    if low is not None:
        extra["floating_point_range"] = [FloatingPointRange(from_value=low, to_value=1e9)]
    return ParameterDescriptor(description=text, read_only=True, **extra)


class PlanSetupError(MentorError):
    """A global-plan parameter of the planner node is invalid (one line)."""


class GlobalPlan:
    """Topics and decisions of a planner node with a global plan (module docstring)."""

    def __init__(
        self,
        node: Node,
        planner: GenomePlanner,
        frames: PlannerFrames,
        values: dict[str, Any],
        on_ready: Callable[[], None],
        scan_guide: GuideConfig | None = None,
        continuous: bool = False,
    ) -> None:
        self._node = node
        self._frames = frames
        self._on_ready = on_ready
        self._log = node.get_logger()
        self._genome = planner
        self.scan_map = scan_guide is not None
        self._arena: Bounds | None = None  # the simulator's, for a scan map of size 0
        #: the planner deciding (None: a scan map waiting for the arena)
        self.planner: GuidedPlanner | ScanGuidedPlanner | None = None
        self._published = 0
        self._path_pub = node.create_publisher(Path, "global_plan", QOS_PATH_OUT)
        if self.scan_map:
            self._keep_map = bool(values["scan_map_keep"])
            self._map_pub = node.create_publisher(OccupancyGridMsg, "scan_map", QOS_MAP)
            self._map_sent: int | None = None  # node clock (ns) of the last publication
            assert scan_guide is not None
            self._config = scan_guide
            size = float(values["scan_map_size"])
            origin = [float(v) for v in values["scan_map_origin"]]
            if len(origin) != 2 or not all(math.isfinite(v) for v in origin):
                raise PlanSetupError(f"scan_map_origin: {origin} is not [x, y] in m")
            # deciding continuously, plans are made beside the decisions (lockstep: at once,
            # as the benchmark makes them, so that the node equals it)
            warm_up_scan_map(self._config)  # the kernels now, not at the first decision
            # deciding on the timer, the map goes out from the plan thread after each plan,
            # so that building and sending a large one never holds up a decision
            self._continuous = continuous
            self._beside = dict(
                worker=ThreadPlans(on_done=self._plan_done) if continuous else None,
                replan_every=float(values["plan_period"]) if continuous else 0.0,
                max_cells=int(values["scan_map_max_cells"]),
            )
            if size > 0.0 or continuous:  # a fixed square, or a map that grows
                corner = (origin[0], origin[1])
                try:
                    self.planner = ScanGuidedPlanner(planner, self._config, size or None,
                                                     corner, **self._beside)  # type: ignore[arg-type]
                except ValueError as err:  # cells that would exhaust memory
                    raise PlanSetupError(f"scan_map_size: {err}") from None
                if not size:
                    cells = int(values["scan_map_max_cells"])
                    node.get_logger().info(
                        f"scan map: grows from the first pose, at most {cells} cells "
                        f"({cells * 5 / 1e6:.0f} MB, a "
                        f"{math.isqrt(cells) * self._config.resolution:.0f} m square), then "
                        "rolls with the robot"
                    )
            return
        config = guide_config(
            planner.profile,
            lookahead=float(values["lookahead"]) or None,
            replan_distance=float(values["replan_distance"]),
            margin=float(values["inflation_margin"]),
            allow_unknown=bool(values["allow_unknown"]),
        )
        self.planner = GuidedPlanner(planner, config)
        self._map_sub = node.create_subscription(
            OccupancyGridMsg, str(values["map_topic"]), self._on_map, QOS_MAP
        )
        self._path_sub = node.create_subscription(Path, "plan", self._on_path, QOS_PATH_IN)

    @property
    def ready(self) -> bool:
        """There is something to follow: a map or a path has come, or a scan map is set up
        (on the simulator's arena: once it and ``map -> odom`` are known)."""
        if self.scan_map and self.planner is None and self._arena is not None:
            self._map_arena()
        if isinstance(self.planner, ScanGuidedPlanner):
            return True
        guide = None if self.planner is None else self.planner.guide
        return guide is not None and (guide.planner is not None or guide.path is not None)

    def waiting_for(self) -> str:
        """What the node waits for before it decides (one line)."""
        return ("no arena for the scan map yet (the deployment's scan_map: beside this "
                "project's simulator; on another robot set scan_map_size and scan_map_origin)"
                if self.scan_map else "no map or path to follow yet (global_plan)")

    def on_arena(self, arena: Bounds | None) -> None:
        """The simulator's arena (in ``map``): the scan map's square where ``scan_map_size``
        is 0."""
        if not self.scan_map or self.planner is not None or arena is None:
            return
        self._arena = arena
        if self._map_arena():
            self._on_ready()

    def _map_arena(self) -> bool:
        """Set up the scan map on the square about the arena in the odometry frame; False
        while ``map -> odom`` is not known (tried again at the next observation)."""
        assert self._arena is not None
        try:
            to_odom = self._frames.transform(self._frames.odom_frame, self._frames.map_frame)
        except LookupError:
            return False
        xmin, ymin, xmax, ymax = bounds_in(self._arena, to_odom)
        size = max(xmax - xmin, ymax - ymin)
        try:
            self.planner = ScanGuidedPlanner(self._genome, self._config, size, (xmin, ymin),
                                             **self._beside)  # type: ignore[arg-type]
        except ValueError as err:  # an arena too large for the scan map's cells
            self._log.error(f"no scan map of the arena: {err}", throttle_duration_sec=WARN_EVERY_S)
            return False
        self._log.info(f"scan map of the arena: {size:g} m from ({xmin:g}, {ymin:g}) in "
                       f"{self._frames.odom_frame!r}")  # fmt: skip
        return True

    def reset(self, new_episode: bool = True) -> None:
        """Start the planner blank (a new goal, or a new episode of the simulator); a scan
        map starts empty, unless ``scan_map_keep`` and it is only a new goal."""
        if isinstance(self.planner, ScanGuidedPlanner):
            self.planner.reset(keep_map=self._keep_map and not new_episode)
        elif self.planner is not None:
            self.planner.reset()
        else:
            self._genome.reset()

    def goal_fault(self, goal: ArrayLike) -> str:
        """Why ``goal`` (x, y, odometry frame) cannot be reached on the map or the scan map
        (one line), or '' (also while nothing is planned on yet). LookupError: ``map ->
        odom`` is not known, for a map."""
        if self.planner is None:
            return ""
        if isinstance(self.planner, GuidedPlanner):
            to_map = self._frames.transform(self._frames.map_frame, self._frames.odom_frame)
            goal = to_map.apply_point(np.asarray(goal, dtype=np.float64).reshape(2).tolist())
        return self.planner.goal_fault(goal)

    def decide(
        self, ranges: ArrayLike, pose: ArrayLike, goal: ArrayLike,
        scan: MountedScan | None = None,
    ) -> tuple[float, float]:  # fmt: skip
        """The guided decision for ``pose`` and ``goal`` in the odometry frame (module
        docstring: along a plan on a map it decides in ``map``, on a scan map in the odometry
        frame, the map taking all rays of the lidar ``scan`` the readings came off where the
        deployment's ``scan_map.whole_scan`` says so); a new path is published once on
        ``global_plan``, in the frame it decides in. LookupError: ``map -> odom`` is not
        known."""
        assert self.planner is not None  # the node decides only when ready
        frame = self._frames.odom_frame
        if isinstance(self.planner, GuidedPlanner):
            frame = self._frames.map_frame
            to_map = self._frames.transform(frame, self._frames.odom_frame)
            p = np.asarray(pose, dtype=np.float64).reshape(3).tolist()
            g = np.asarray(goal, dtype=np.float64).reshape(2).tolist()
            pose, goal = to_map.apply_pose(p), to_map.apply_point(g)
        if isinstance(self.planner, ScanGuidedPlanner):
            decision = self.planner.decide(ranges, pose, goal, scan)
        else:
            decision = self.planner.decide(ranges, pose, goal)
        guide = self.planner.guide
        now = self._node.get_clock().now()
        new_plan = guide.revision != self._published and guide.path is not None
        if new_plan:
            self._published = guide.revision
            self._path_pub.publish(conversions.path_msg(guide.path, now.to_msg(), frame))
        if isinstance(self.planner, ScanGuidedPlanner) and not self._continuous:
            self._publish_scan_map(self.planner, now.nanoseconds, now.to_msg(), frame, new_plan)
        return decision

    def _plan_done(self, result: PlanResult) -> None:
        """On the plan thread, after each plan: the scan map on ``scan_map`` (at most every
        :data:`MAP_EVERY_S` s, as :meth:`_publish_scan_map`)."""
        planner = self.planner
        if isinstance(planner, ScanGuidedPlanner) and result.owner is planner.scan:
            now = self._node.get_clock().now()
            self._publish_scan_map(planner, now.nanoseconds, now.to_msg(),
                                   self._frames.odom_frame, False)  # fmt: skip

    def _publish_scan_map(
        self, planner: ScanGuidedPlanner, now_ns: int, stamp: Time, frame: str, new_plan: bool
    ) -> None:
        """``planner``'s scan map on ``scan_map`` with a new plan, else at most every
        :data:`MAP_EVERY_S` s (a clock that went back, as sim time does when the simulator
        restarts, counts as due)."""
        last = self._map_sent
        due = last is None or not 0 <= now_ns - last < MAP_EVERY_S * _NS_PER_S
        if not (new_plan or due):
            return
        self._map_sent = now_ns
        grid = planner.scan.map.grid()  # None while another thread grows it
        if grid is not None:
            self._map_pub.publish(occupancy_grid_msg(grid, stamp, frame))

    def _on_map(self, msg: OccupancyGridMsg) -> None:
        try:
            grid = conversions.grid_from_occupancy_grid(msg)
        except ValueError as err:
            self._log.warning(f"map rejected: {err}")
            return
        assert isinstance(self.planner, GuidedPlanner)
        self.planner.set_map(grid)
        self._log.info(f"planning on a {grid.width}x{grid.height} map of {grid.resolution:g} m")
        self._on_ready()

    def _on_path(self, msg: Path) -> None:
        try:
            path = conversions.path_from_msg(msg)
        except ValueError as err:
            self._log.warning(f"path rejected: {err}", throttle_duration_sec=WARN_EVERY_S)
            return
        assert isinstance(self.planner, GuidedPlanner)
        self.planner.set_path(path)
        self._on_ready()


def attach(
    node: Node, planner: GenomePlanner | None, frames: PlannerFrames,
    on_ready: Callable[[], None], scan_guide: GuideConfig | None = None,
    continuous: bool = False,
) -> GlobalPlan | None:  # fmt: skip
    """Declare the global-plan parameters (defaults from the robot, ``docs/ros.md``); a
    :class:`GlobalPlan` when ``global_plan`` is true or the deployment has a scan map
    (``scan_guide``, its plan's settings) and a genome is loaded, else None. ``on_ready`` is
    called when a map or a path comes (a waiting observation may go); ``continuous``: the
    node decides on its timer, so a scan map's plans are made on a thread beside it."""
    profile = planner.profile if planner is not None else None
    defaults = guide_config(profile) if profile is not None else None
    declared = node.declare_parameters(
        "",
        [
            ("global_plan", False, _descriptor("follow a Path on 'plan' or plan on the map")),
            ("map_topic", "/map", _descriptor("OccupancyGrid to plan on (latched)")),
            (
                "lookahead",
                0.0,
                _descriptor("m along the path the network steers to (0: 2 goal radii); a "
                            "scan map's is the deployment's", low=0.0),
            ),
            (
                "replan_distance",
                defaults.replan_distance if defaults else 1.0,
                _descriptor("m off the path before planning again", low=1e-3),
            ),
            (
                "inflation_margin",
                defaults.margin if defaults else 0.0,
                _descriptor("m added to the footprint's radius when planning", low=0.0),
            ),
            ("allow_unknown", True, _descriptor("plan through unknown map cells")),
            (
                "scan_map_size",
                0.0,
                _descriptor("m, side of the scan map's square (0: deciding on the timer, a map "
                            "that grows from the first pose; in lockstep the simulator's arena)",
                            low=0.0),
            ),
            (
                "scan_map_max_cells",
                MAX_CELLS,
                ParameterDescriptor(description="the most cells a growing scan map holds (5 "
                                    "bytes a cell), then it rolls with the robot",
                                    read_only=True),
            ),
            (
                "plan_period",
                1.0,
                _descriptor("s: deciding on the timer, plan again on the scan map when the "
                            "plan is this old (0: only when the path is blocked, the goal "
                            "changes or the robot strays)", low=0.0),
            ),
            (
                "scan_map_origin",
                [0.0, 0.0],
                _descriptor("[x, y] m, the scan map's lower-left corner in the odometry frame"),
            ),
            (
                "scan_map_keep",
                True,
                _descriptor("keep the scan map across goals (cleared at a simulator episode's "
                            "start); false: each goal starts with an empty map"),
            ),
        ],
    )
    values = {p.name: p.value for p in declared}
    if values["global_plan"] and scan_guide is not None:
        raise PlanSetupError("global_plan and a deployment with a scan map: choose one plan "
                             "to follow (-p \"deployment_set:=['scan_map=null']\" drops the "
                             "scan map)")
    if not (values["global_plan"] or scan_guide is not None) or planner is None:
        return None
    if int(values["scan_map_max_cells"]) < 1:
        raise PlanSetupError(f"scan_map_max_cells: {values['scan_map_max_cells']} is not a "
                             "positive number of cells")  # fmt: skip
    return GlobalPlan(node, planner, frames, values, on_ready, scan_guide, continuous)
