"""Command-line tools of the MENTOR suite (mentor-train, mentor-eval, ...)."""
