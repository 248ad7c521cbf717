"""The files wing: versioned files of genomes, checkpoints and rosbag2 bags.

May import errors, atomic, evolution, sim and objectives; never training, runtime, report,
cli or rclpy.
"""
