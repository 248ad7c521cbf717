"""The runtime wing: what the ROS 2 nodes run, with no rclpy in it.

The reference simulator (pymunk episodes, events), the scenario plan of each simulated robot,
the planner (an evolved genome deciding for one robot, and when), the lockstep command
barrier, the recording of episodes into bags, and the simulator node's whole run (episodes,
stepping, events, sim time: ``sim_session``). The node packages only turn messages into calls
of these and back.

May import every wing below it (errors, atomic, evolution, sim, objectives, files); never
training, report or cli.
"""
