"""The objectives wing: the paper's criteria of a planner.

Performance F (eqs. 3-4, from an episode batch), experience gain G (eqs. 5-8, the minimum
spanning tree length of the experience points) and complexity (the FLOPs of a forward pass
relative to the minimal network).

May import errors, atomic, evolution and sim; never files, training, runtime, report or cli.
"""
