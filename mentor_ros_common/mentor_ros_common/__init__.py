"""What both MENTOR nodes share: their ``main`` and the ROS messages both of them build."""
