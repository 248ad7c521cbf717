"""Evaluation throughput of mentor_core's batched engine against neat-python 2.0, one JSON.

    export NUMBA_CACHE_DIR=.venv/numba-cache
    .venv/bin/python benchmarks/perf/throughput_vs_neat.py [--genomes 100] [--scenarios 80]
        [--neat-genomes 4] [--rounds 10] [--repeats 3]

Both sides drive the same paper-scale UGV genomes (minimal genomes put through ``--rounds``
of the paper's mutation, :func:`generation_bench.evolved_looking`) through the same training
scenarios with the SAME simulator step:
:func:`mentor_core.controller.episodes.run_episodes`, i.e. per decision the range sensors
(numba ray casts), the network inputs
(:func:`mentor_core.sim.observation.network_inputs`), the network, the actions
(:func:`~mentor_core.sim.observation.actions_from_outputs`), the swept-arc step of
:class:`mentor_core.sim.engine.BatchEngine` (numba collision kernels) and the experience-point
bookkeeping. Neither side computes objectives or the experience MST.

* mentor_core ("ours"): ``NavigationProblem.simulate(genomes)``, the trainer's path: all
  genomes compiled into one :class:`mentor_core.evolution.batch_network.BatchNetwork` (compile time
  included), then all ``genomes x scenarios`` robots stepped together, one batched network
  call per decision over all active robots of all genomes.
* neat-python: each genome converted to a ``neat.DefaultGenome`` (same nodes, connections,
  weights; our bias-node connections become neat's node biases; NEAT's sigmoid
  ``1/(1+exp(-4.9 x))`` registered as a custom activation because neat-python's own sigmoid
  uses slope 5; the conversion is not timed), compiled with
  ``neat.nn.FeedForwardNetwork.create`` (timed, as our compile is); then each robot runs
  alone, one after the other in a Python loop: ``run_episodes([scenario], ...)`` whose policy
  is ``net.activate(inputs.tolist())``, so one robot per simulator call. Only
  ``--neat-genomes`` genomes (spread over the population) x all scenarios run on this side;
  its rate is robot-steps per second over those robots.

So the ratio measures the network implementation plus batching (robots per simulator call),
nothing else. Before timing, the two sides must agree: network outputs on random inputs and
the actions of the first decisions of a few robots to 1e-9 (the script stops otherwise).
Times are wall-clock seconds, best of ``--repeats`` on each side; the machine's load average
is printed alongside. ``network_share_of_time``: the share spent inside the network's
``activate`` (ours: ``BatchNetwork.activate``, from a separate clocked run; neat-python's
from clocks around each call, ~0.1 us per call); ``network_only_ratio_estimate``:
neat-python's activate seconds per robot-step over ours.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import tempfile
import time
from collections.abc import Callable, Sequence
from datetime import date
from typing import Any

import neat
import numpy as np
from generation_bench import evolved_looking

import mentor_core.evolution.batch_network
from mentor_core.controller.episodes import run_episodes
from mentor_core.evolution.batch_network import BatchNetwork
from mentor_core.evolution.genome import Genome
from mentor_core.evolution.network import NEAT_SIGMOID_SLOPE, FeedForwardNetwork
from mentor_core.sim.episode import EpisodeBatch
from mentor_core.sim.robots import RobotProfile, get_profile
from mentor_core.sim.scenarios import training_scenarios
from mentor_core.sim.world import Scenario
from mentor_core.training.problem import NavigationProblem

TOL = 1e-9
CHECK_STEPS = 5

NEAT_CONFIG = """
[NEAT]
fitness_criterion = max
fitness_threshold = 1e9
pop_size = {pop}
reset_on_extinction = False
no_fitness_termination = True

[DefaultGenome]
num_inputs = {n_inputs}
num_outputs = {n_outputs}
num_hidden = 0
feed_forward = True
initial_connection = full_direct
compatibility_disjoint_coefficient = 1.0
compatibility_weight_coefficient = 0.4
conn_add_prob = 0.5
conn_delete_prob = 0.0
node_add_prob = 0.08
node_delete_prob = 0.0
activation_default = sigmoid
activation_options = sigmoid
activation_mutate_rate = 0.0
aggregation_default = sum
aggregation_options = sum
aggregation_mutate_rate = 0.0
bias_init_mean = 0.0
bias_init_stdev = 1.0
bias_max_value = 30.0
bias_min_value = -30.0
bias_mutate_power = 0.5
bias_mutate_rate = 0.25
bias_replace_rate = 0.1
response_init_mean = 1.0
response_init_stdev = 0.0
response_max_value = 1.0
response_min_value = 1.0
response_mutate_power = 0.0
response_mutate_rate = 0.0
response_replace_rate = 0.0
weight_init_mean = 0.0
weight_init_stdev = 1.0
weight_max_value = 30.0
weight_min_value = -30.0
weight_mutate_power = 0.5
weight_mutate_rate = 0.25
weight_replace_rate = 0.1
enabled_default = True
enabled_mutate_rate = 0.0

[DefaultSpeciesSet]
compatibility_threshold = 3.0

[DefaultStagnation]
species_fitness_func = max
max_stagnation = 15
species_elitism = 0

[DefaultReproduction]
elitism = 2
survival_threshold = 0.2
"""


def neat_sigmoid(z: float) -> float:
    """mentor_core's sigmoid 1/(1+exp(-4.9 z)) in plain Python (overflow-free form)."""
    x = NEAT_SIGMOID_SLOPE * z
    if x >= 0.0:
        return 1.0 / (1.0 + math.exp(-x))
    e = math.exp(x)
    return e / (1.0 + e)


def neat_tanh(z: float) -> float:
    return math.tanh(z)


def neat_identity(z: float) -> float:
    return z


def neat_relu(z: float) -> float:
    return z if z > 0.0 else 0.0


# our activation name -> (name registered in neat-python, function with our exact formula)
ACTIVATIONS = {
    "sigmoid": ("mentor_sigmoid", neat_sigmoid),
    "tanh": ("mentor_tanh", neat_tanh),
    "identity": ("mentor_identity", neat_identity),
    "relu": ("mentor_relu", neat_relu),
}


def neat_config(n_inputs: int, n_outputs: int, pop: int) -> Any:
    """A neat-python 2.0 Config with our activations registered."""
    with tempfile.NamedTemporaryFile("w", suffix=".ini", delete=False) as handle:
        handle.write(NEAT_CONFIG.format(pop=pop, n_inputs=n_inputs, n_outputs=n_outputs))
        path = handle.name
    try:
        config = neat.Config(neat.DefaultGenome, neat.DefaultReproduction,
                             neat.DefaultSpeciesSet, neat.DefaultStagnation, path)
    finally:
        os.unlink(path)
    for name, fn in ACTIVATIONS.values():
        config.genome_config.add_activation(name, fn)
    return config


def to_neat_genome(genome: Genome, key: int) -> Any:
    """The same network as a neat.DefaultGenome (bias-node edges -> node biases)."""
    n_in = genome.n_inputs
    outputs = list(genome.output_ids)

    def key_of(node_id: int) -> int:
        if node_id < n_in:
            return -(node_id + 1)  # neat-python: inputs are -1, -2, ...
        if node_id in outputs:
            return outputs.index(node_id)  # outputs are 0, 1, ...
        assert node_id >= len(outputs), "hidden ids must not collide with neat's output keys"
        return node_id

    g = neat.DefaultGenome(key)
    for node in genome.nodes:
        if node.kind in ("input", "bias"):
            continue
        gene = neat.genes.DefaultNodeGene(key_of(node.id))
        gene.bias, gene.response, gene.time_constant = 0.0, 1.0, 1.0
        gene.activation = ACTIVATIONS[node.activation][0]
        gene.aggregation = "sum"
        g.nodes[gene.key] = gene
    for c in genome.connections:
        if c.in_node == genome.bias_id:
            if c.enabled:
                g.nodes[key_of(c.out_node)].bias += c.weight
            continue
        conn = neat.genes.DefaultConnectionGene(
            (key_of(c.in_node), key_of(c.out_node)), innovation=c.innovation
        )
        conn.weight, conn.enabled = c.weight, c.enabled
        g.connections[conn.key] = conn
    return g


def neat_policy(net: Any, clock: list[float] | None = None) -> Callable[..., Any]:
    """One robot per call: ``net.activate`` on its input list (optionally timed)."""
    if clock is None:
        def policy(inputs: np.ndarray, robots: np.ndarray) -> list[list[float]]:
            return [net.activate(inputs[0].tolist())]
        return policy

    def timed_policy(inputs: np.ndarray, robots: np.ndarray) -> list[list[float]]:
        t0 = time.perf_counter()
        out = net.activate(inputs[0].tolist())
        clock[0] += time.perf_counter() - t0
        return [out]

    return timed_policy


def run_neat(nets: Sequence[Any], scenarios: Sequence[Scenario], profile: RobotProfile,
             clock: list[float] | None = None) -> list[EpisodeBatch]:
    """Every (net, scenario) as its own one-robot episode, in a Python loop."""
    return [run_episodes([sc], profile, neat_policy(net, clock)) for net in nets
            for sc in scenarios]


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--genomes", type=int, default=100, help="population on our side")
    p.add_argument("--scenarios", type=int, default=80)
    p.add_argument("--neat-genomes", type=int, default=4, help="genomes run through neat-python")
    p.add_argument("--rounds", type=int, default=10, help="mutation rounds per genome")
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--seed", type=int, default=1)
    args = p.parse_args()

    profile = get_profile("ugv")
    scenarios = training_scenarios(profile, 0, args.scenarios)
    n_scen = len(scenarios)
    genomes = evolved_looking(args.genomes, profile.n_inputs, "ugv", args.rounds, args.seed)
    problem = NavigationProblem(profile, scenarios)
    picked = np.linspace(0, args.genomes - 1, min(args.neat_genomes, args.genomes))
    neat_idx = sorted({round(float(i)) for i in picked})
    config = neat_config(profile.n_inputs, 2, args.genomes)
    neat_genomes = [to_neat_genome(genomes[i], i) for i in neat_idx]
    neat_nets = [neat.nn.FeedForwardNetwork.create(g, config) for g in neat_genomes]

    # ---- agreement checks (before any timing) ------------------------------------------
    rng = np.random.default_rng(0)
    x = rng.normal(0.0, 2.0, size=(64, profile.n_inputs))
    net_diff = max(
        float(np.abs(FeedForwardNetwork.from_genome(genomes[i]).activate(x)
                     - np.array([net.activate(row.tolist()) for row in x])).max())
        for i, net in zip(neat_idx, neat_nets, strict=True)
    )
    check_scen = scenarios[: min(4, n_scen)]
    ours_check = NavigationProblem(profile, check_scen).simulate([genomes[i] for i in neat_idx])
    neat_check = run_neat(neat_nets, check_scen, profile)
    k = profile.n_sensors
    action_diff = 0.0
    for r, nb in enumerate(neat_check):
        ours_a = ours_check.experience[r][:CHECK_STEPS, k : k + 2]
        theirs_a = nb.experience[0][:CHECK_STEPS, k : k + 2]
        if ours_a.shape != theirs_a.shape:
            raise SystemExit(f"robot {r}: {len(ours_a)} vs {len(theirs_a)} first decisions")
        if len(ours_a):
            action_diff = max(action_diff, float(np.abs(ours_a - theirs_a).max()))
    if not (net_diff <= TOL and action_diff <= TOL):
        raise SystemExit(f"sides disagree: network {net_diff:.3g}, actions {action_diff:.3g}")

    # ---- ours: the whole population at once ---------------------------------------------
    problem.simulate(genomes[:2])  # load the numba kernels
    ours_s = float("inf")
    for _ in range(args.repeats):
        t0 = time.perf_counter()
        batch = problem.simulate(genomes)
        ours_s = min(ours_s, time.perf_counter() - t0)
    ours_steps = int(batch.steps.sum())

    # breakdown run (not the headline): time inside our network's activate
    net_clock = [0.0]
    plain_activate = mentor_core.evolution.batch_network.BatchNetwork.activate

    def clocked(self: BatchNetwork, inputs: Any, owners: Any, **kwargs: Any) -> Any:
        t0 = time.perf_counter()
        out = plain_activate(self, inputs, owners, **kwargs)
        net_clock[0] += time.perf_counter() - t0
        return out

    mentor_core.evolution.batch_network.BatchNetwork.activate = clocked  # type: ignore[method-assign]
    t0 = time.perf_counter()
    problem.simulate(genomes)
    ours_breakdown_s = time.perf_counter() - t0
    mentor_core.evolution.batch_network.BatchNetwork.activate = plain_activate  # type: ignore[method-assign]

    # ---- neat-python: one robot at a time -----------------------------------------------
    neat_s, neat_net_s = float("inf"), 0.0
    for _ in range(args.repeats):
        neat_clock = [0.0]
        t0 = time.perf_counter()
        nets = [neat.nn.FeedForwardNetwork.create(g, config) for g in neat_genomes]
        neat_batches = run_neat(nets, scenarios, profile, neat_clock)
        took = time.perf_counter() - t0
        if took < neat_s:
            neat_s, neat_net_s = took, neat_clock[0]
    neat_steps = int(sum(int(b.steps.sum()) for b in neat_batches))

    # the same robots in our batched run: same step counts and trajectories?
    rows = [g * n_scen + s for g in neat_idx for s in range(n_scen)]
    same_steps = sum(int(batch.steps[r] == b.steps[0])
                     for r, b in zip(rows, neat_batches, strict=True))
    same_paths = sum(
        int(batch.steps[r] == b.steps[0] and np.allclose(
            batch.trajectories[r, : b.steps[0] + 1], b.trajectories[0], rtol=0, atol=TOL))
        for r, b in zip(rows, neat_batches, strict=True)
    )
    ours_rate = ours_steps / ours_s
    neat_rate = neat_steps / neat_s
    hidden = [len(g.hidden_nodes) for g in genomes]
    enabled = [len(g.enabled_connections) for g in genomes]
    report = {
        "benchmark": "throughput_vs_neat",
        "date": date.today().isoformat(),
        "host": {"cpus": os.cpu_count(), "loadavg_1m": os.getloadavg()[0],
                 "python": platform.python_version(), "neat_python": neat.__version__
                 if hasattr(neat, "__version__") else "2.0"},
        "robot": profile.name,
        "scenarios": n_scen,
        "genomes": args.genomes,
        "mutation_rounds": args.rounds,
        "network_size": {"mean_hidden_nodes": float(np.mean(hidden)),
                         "max_hidden_nodes": int(np.max(hidden)),
                         "mean_enabled_connections": float(np.mean(enabled))},
        "agreement_before_timing": {
            "network_outputs_max_abs_diff": net_diff,
            "first_actions_max_abs_diff": action_diff,
            "robots_checked": len(neat_check), "steps_checked_per_robot": CHECK_STEPS,
            "tolerance": TOL,
        },
        "ours": {
            "includes": "NavigationProblem.simulate: compile all genomes into one mentor_core "
                        "BatchNetwork + run_episodes on all genomes x scenarios robots "
                        "at once (sensors, inputs, one batched network call over all "
                        "genomes' robots, actions, swept-arc step, experience points); no "
                        "objectives, no MST",
            "robots_per_simulator_call": args.genomes * n_scen,
            "robot_steps": ours_steps,
            "seconds_best": ours_s,
            "robot_steps_per_s": ours_rate,
            "network_share_of_time": net_clock[0] / ours_breakdown_s,
        },
        "neat_python": {
            "includes": "per robot: run_episodes([scenario]) with policy "
                        "neat.nn.FeedForwardNetwork.activate(inputs.tolist()) (same "
                        "sensors, inputs, actions, swept-arc step, experience points), robots "
                        "one after another in a Python loop, after FeedForwardNetwork.create "
                        "of each genome (timed; the conversion to neat genomes is not)",
            "genomes_run": len(neat_idx),
            "robots": len(neat_batches),
            "robots_per_simulator_call": 1,
            "robot_steps": neat_steps,
            "robot_steps_per_s": neat_rate,
            "seconds_best": neat_s,
            "network_share_of_time": neat_net_s / neat_s,
            "robots_with_same_step_count_as_ours": same_steps,
            "robots_with_same_trajectory_as_ours": same_paths,
        },
        "throughput_ratio_ours_over_neat": ours_rate / neat_rate,
        "network_only_ratio_estimate": (neat_net_s / neat_steps)
        / (net_clock[0] / ours_steps),
        "goal_ratio": 100.0,
    }
    print(json.dumps(report, indent=2))


if __name__ == "__main__":
    main()
