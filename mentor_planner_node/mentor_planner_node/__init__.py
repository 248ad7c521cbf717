"""ROS 2 package mentor_planner_node of the MENTOR suite."""
