"""ROS 2 package mentor_sim_node of the MENTOR suite."""
