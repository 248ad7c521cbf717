"""The simulation wing: the two robots and their 2-D worlds (paper section III).

Robot profiles (body, range sensors, action limits, time budgets), worlds and the paper's DoE
scenarios, unicycle kinematics, ray-cast sensors, body collisions, the planner's network inputs
and actions (observation), the batched engine and the outcome of episodes, the pymunk
reference physics, the REP-103/REP-105 frame conventions and planar transforms, a simulated
lidar, a robot's sensors read off any laser scan, and a robot's frames and URDF.

Knows nothing of evolution, nor of the controller's layers (a contract checks it): imports
only the foundation and its own modules.
"""
