"""MENTOR's planners in IR-SIM worlds (issue 59): the optional extra ``mentor-core[irsim]``.

IR-SIM (``ir-sim`` on PyPI) is a 2-D robot simulator of its own: differential drives, circles
and polygons, a ``lidar2d`` with noise, agents that walk by RVO, social force or a script,
worlds written in YAML. This wing runs any genome in such a world exactly as the planner node
deploys it: IR-SIM's scan read through :func:`mentor_core.sim.scan_adapter.readings_from_scan`,
the decision of the node's own chain (:class:`mentor_core.runtime.guided_planner.ScanGuidedPlanner`
around :class:`mentor_core.runtime.planner.GenomePlanner`), turned into a velocity command
held for the deployed control period, and IR-SIM's own stepping and collision checks.

Modules, one concept each:

- :mod:`.dependency`: importing IR-SIM lazily (one line naming the extra when it is missing);
- :mod:`.adapter`: the conversions (scan dict -> ``LaserScanData``, decision -> command);
- :mod:`.world_file`: a world file of this project (IR-SIM's YAML and a ``custom.mentor``
  block: the robot, its start/goal pairs and each pair's agents), read and checked;
- :mod:`.worlds`: the seeded generator of the committed worlds (``benchmarks/irsim_worlds``);
- :mod:`.drivers`: what decides in an episode: a genome as deployed, a baseline, a pursuit;
- :mod:`.episode`: one start/goal pair driven to its end in IR-SIM;
- :mod:`.tally`: the scores of episodes, collisions with agents apart;
- :mod:`.figures`: trajectories drawn from episodes;
- :mod:`.cli`: the ``mentor-irsim`` command.

Nothing else in ``mentor_core`` imports this wing, and nothing here imports ``irsim`` until an
episode runs, so ``mentor_core`` works without the extra.
"""
