"""ROS 2 package mentor_bringup of the MENTOR suite: the simulator and its planners together."""
