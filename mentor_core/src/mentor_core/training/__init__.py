"""The training wing: MENTOR's single- and dual-stage trainers (paper section III-D).

The trainers and their configuration, the path-planning problem joining evolution and
simulation, the evaluation backends (in-process, process pool, ray) and the child processes
that die with them, the files of a run
directory, and the test-on-unseen assessment of trained planners.

May import every wing below it (errors, atomic, evolution, sim, objectives, files,
navigation, controller); never runtime, report or cli.
"""
