"""The runtime wing: what the ROS 2 nodes run, with no rclpy in it.

The reference simulator (pymunk episodes, events), the scenario plan of each simulated robot,
the planner (an evolved genome deciding for one robot, and when) and its frames, goals given on
goal topics, the lidar and ``odom`` frame as the wire carries them (``wiring``), the lockstep
command barrier and the continuous mode's held commands, the recording of episodes into bags,
the simulator node's whole run (episodes, stepping, goals, events, sim time: ``sim_session``),
and ROS ``-p`` values checked before rcl sees them. The node packages only turn messages into
calls of these and back.

May import every wing below it (errors, atomic, evolution, sim, objectives, files,
navigation, controller); never training, report or cli.
"""
