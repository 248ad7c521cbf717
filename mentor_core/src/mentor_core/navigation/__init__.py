"""The navigation wing: global planning for the robots, as a ROS navigation stack splits it.

Shortest paths for a robot's footprint (on box worlds and on occupancy grids), occupancy grids
and ROS maps (the ``map_server`` YAML + PGM pair), and following a path by a lookahead point
(the planner/controller split of Nav2). Used by the runtime (the planner node's global plans),
by the benchmark (solvable pairs, SPL, the oracle) and by ``mentor-eval --global-plan``.

May import ``errors``, ``atomic`` and ``sim``; never evolution, training, runtime or above.
"""
