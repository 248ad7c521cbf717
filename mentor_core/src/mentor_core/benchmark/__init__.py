"""The benchmark wing: how well planners reach goals in worlds they never saw.

Seeded families of procedurally generated worlds for each robot (rooms with doorways,
corridors, slalom walls, U-shaped traps, box forests, mazes, the paper's DoE), start/goal
pairs checked solvable, the validation and test splits, classic baselines and the
shortest-path oracle, and the scores (success, collisions, timeouts, time to goal, SPL).

May import every wing below it (errors, atomic, evolution, sim, objectives, files,
navigation, controller, training, runtime); never report or cli.
"""
