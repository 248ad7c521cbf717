"""The controller wing: how a trained network decides on a robot, layer by layer.

One decision chain (:mod:`~mentor_core.controller.pipeline`) runs the stages of a deployment
about the network (:mod:`~mentor_core.controller.stage`: what a layer may change), for the
batched episodes of training and the benchmark (:mod:`~mentor_core.controller.episodes`) and
for the planner node alike. A deployment is data (:mod:`~mentor_core.controller.deployment`,
the shipped ones in ``data/deployments.yaml``); the layers are its modules: a view corridor,
a gain on the turn, a turn commitment, a rotation shim, a collision guard and the decision
split.

May import sim, navigation, evolution and the foundation; never training, runtime,
benchmark, report, cli or ROS.
"""
