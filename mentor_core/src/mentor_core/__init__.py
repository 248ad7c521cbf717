"""MENTOR: multi-criteria evolution of neural-network topologies for robot path planning.

A pure-Python library (no ROS import). One module per concept; see docs/architecture.md.
"""

__version__ = "0.1.0"
