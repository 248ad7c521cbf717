"""Configs: EvolutionConfig (paper values, YAML round trip, unknown keys and bad values
rejected) and the trainer's config files (strict types, one line naming file and key, the
JSON schema)."""

from __future__ import annotations

import dataclasses
import json
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

from mentor_core.errors import ConfigError, FileFormatError
from mentor_core.evolution.config import EvolutionConfig
from mentor_core.evolution.mutation import MutationConfig
from mentor_core.evolution.species import SpeciationConfig
from mentor_core.training.config import (
    TrainerConfig,
    load_config_file,
    read_config,
    shipped_config,
)

ROOT = Path(__file__).resolve().parents[1]
CONFIG_DIR = ROOT / "mentor_core/src/mentor_core/configs"
EXPERIMENT_CONFIGS = sorted((ROOT / "benchmarks/configs").glob("[su]*.yaml"))


@pytest.mark.parametrize(
    ("robot", "node_rate", "edge_rate"), [("ugv", 0.05, 0.03), ("swarm", 0.08, 0.5)]
)
def test_paper_table_one(robot: str, node_rate: float, edge_rate: float) -> None:
    c = EvolutionConfig.paper(robot)  # type: ignore[arg-type]
    assert c.population_size == 100
    assert c.generations == 50
    assert c.elitism == 0.02
    assert c.crossover_rate == 0.85
    assert c.mutation.weight_rate == 0.25
    assert c.mutation.node_rate == node_rate
    assert c.mutation.edge_rate == edge_rate
    assert (c.speciation.c1, c.speciation.c2, c.speciation.c3) == (1.0, 1.0, 0.4)


def test_paper_unknown_robot() -> None:
    with pytest.raises(ConfigError, match="robot"):
        EvolutionConfig.paper("drone")  # type: ignore[arg-type]


@pytest.mark.parametrize(("name", "robot"), [("ugv_paper", "ugv"), ("swarm_paper", "swarm")])
def test_shipped_paper_configs_equal_table_one(name: str, robot: str) -> None:
    assert EvolutionConfig.from_yaml(CONFIG_DIR / f"{name}.yaml") == EvolutionConfig.paper(
        robot  # type: ignore[arg-type]
    )
    assert EvolutionConfig.packaged(name) == EvolutionConfig.paper(robot)  # type: ignore[arg-type]


def test_shipped_xor_config() -> None:
    c = EvolutionConfig.packaged("xor")
    assert c.population_size == 150
    assert c.generations == 100
    assert c == EvolutionConfig.from_yaml(CONFIG_DIR / "xor.yaml")
    raw = yaml.safe_load((CONFIG_DIR / "xor.yaml").read_text())
    assert c.mutation.node_rate == raw["mutation"]["node_rate"]
    assert c.speciation.target_species == raw["speciation"]["target_species"]


def test_defaults_are_the_ugv_case() -> None:
    assert EvolutionConfig() == EvolutionConfig.paper("ugv")


@pytest.mark.parametrize("name", ["ugv_paper", "swarm_paper", "xor"])
def test_round_trip_dict_and_yaml(name: str, tmp_path: Path) -> None:
    c = EvolutionConfig.packaged(name)
    assert EvolutionConfig.from_dict(c.to_dict()) == c
    path = tmp_path / "c.yaml"
    path.write_text(c.to_yaml())
    assert EvolutionConfig.from_yaml(path) == c


def test_missing_keys_keep_defaults() -> None:
    c = EvolutionConfig.from_dict({"population_size": 30, "mutation": {"node_rate": 0.2}})
    assert c.population_size == 30
    assert c.mutation == dataclasses.replace(MutationConfig(), node_rate=0.2)
    assert c.speciation == SpeciationConfig()


def test_int_accepted_for_float() -> None:
    c = EvolutionConfig.from_dict({"crossover_rate": 1, "speciation": {"threshold": 2}})
    assert c.crossover_rate == 1.0 and isinstance(c.crossover_rate, float)
    assert c.speciation.threshold == 2.0


@pytest.mark.parametrize(
    ("data", "key"),
    [
        ({"populaton_size": 10}, "populaton_size"),
        ({"mutation": {"node_rat": 0.1}}, "mutation.node_rat"),
        ({"speciation": {"c4": 1.0}}, "speciation.c4"),
    ],
)
def test_unknown_key_names_key_and_file(data: dict[str, object], key: str) -> None:
    with pytest.raises(ConfigError) as info:
        EvolutionConfig.from_dict(data, source="run.yaml")
    assert info.value.key == key
    assert info.value.path == "run.yaml"
    assert "unknown key" in str(info.value)
    assert str(info.value).startswith("run.yaml: ")


@pytest.mark.parametrize(
    ("data", "key"),
    [
        ({"population_size": 1}, "population_size"),
        ({"population_size": 0}, "population_size"),
        ({"population_size": 10.5}, "population_size"),
        ({"population_size": True}, "population_size"),
        ({"population_size": "100"}, "population_size"),
        ({"generations": 0}, "generations"),
        ({"elitism": -0.1}, "elitism"),
        ({"elitism": 1.0}, "elitism"),
        ({"crossover_rate": 1.5}, "crossover_rate"),
        ({"crossover_rate": float("nan")}, "crossover_rate"),
        ({"tournament_size": 0}, "tournament_size"),
        ({"global_fraction": -0.5}, "global_fraction"),
        ({"global_fraction": 0.99}, "global_fraction"),
        ({"hidden_activation": "swish"}, "hidden_activation"),
        ({"output_activation": 3}, "output_activation"),
        ({"initial_weight_sigma": 0.0}, "initial_weight_sigma"),
        ({"mutation": {"node_rate": 1.5}}, "mutation.node_rate"),
        ({"mutation": {"weight_rate": "high"}}, "mutation.weight_rate"),
        ({"mutation": [1, 2]}, "mutation"),
        ({"speciation": {"threshold": -1.0}}, "speciation.threshold"),
        ({"speciation": {"target_species": 0}}, "speciation.target_species"),
        ({"speciation": {"target_species": 2.5}}, "speciation.target_species"),
    ],
)
def test_bad_values_rejected(data: dict[str, object], key: str) -> None:
    with pytest.raises(ConfigError) as info:
        EvolutionConfig.from_dict(data, source="bad.yaml")
    assert info.value.key == key
    assert info.value.path == "bad.yaml"
    assert "\n" not in str(info.value)


def test_direct_construction_is_validated() -> None:
    with pytest.raises(ConfigError, match="elitism"):
        EvolutionConfig(elitism=2.0)


def test_elites_and_global_must_leave_room() -> None:
    with pytest.raises(ConfigError, match="global_fraction"):
        EvolutionConfig(population_size=10, elitism=0.5, global_fraction=0.5)


def test_config_is_frozen() -> None:
    c = EvolutionConfig()
    with pytest.raises(dataclasses.FrozenInstanceError):
        c.population_size = 3  # type: ignore[misc]


def test_top_level_must_be_mapping() -> None:
    with pytest.raises(ConfigError, match="mapping"):
        EvolutionConfig.from_dict([1, 2], source="x.yaml")  # type: ignore[arg-type]


def test_from_yaml_missing_file(tmp_path: Path) -> None:
    with pytest.raises(FileFormatError) as info:
        EvolutionConfig.from_yaml(tmp_path / "nope.yaml")
    assert "nope.yaml" in str(info.value)
    assert "no such file" in str(info.value)


def test_from_yaml_bad_yaml(tmp_path: Path) -> None:
    path = tmp_path / "bad.yaml"
    path.write_text("population_size: [1, 2\n")
    with pytest.raises(FileFormatError, match="not valid YAML at line 2"):
        EvolutionConfig.from_yaml(path)


def test_from_yaml_unknown_key_names_file(tmp_path: Path) -> None:
    path = tmp_path / "typo.yaml"
    path.write_text("populaton_size: 10\n")
    with pytest.raises(ConfigError) as info:
        EvolutionConfig.from_yaml(path)
    assert info.value.path == str(path)


def test_empty_yaml_is_refused(tmp_path: Path) -> None:
    path = tmp_path / "empty.yaml"
    path.write_text("# all commented out\n")
    with pytest.raises(FileFormatError, match=r"empty\.yaml: empty file"):
        EvolutionConfig.from_yaml(path)
    path.write_text("{}\n")  # an explicit empty mapping: every default
    assert EvolutionConfig.from_yaml(path) == EvolutionConfig()


# ------------------------------------------------ the trainer's config files (issue 17, failure 7)

TRAIN_CONFIGS = sorted(CONFIG_DIR.glob("train_*.yaml"))


@pytest.mark.parametrize(
    ("text", "key", "fault"),
    [
        ("generations: 12.5\n", "generations", "expected a whole number, got 12.5"),
        ("generations: '12'\n", "generations", "expected a whole number, got '12'"),
        ("generations: true\n", "generations", "expected a whole number, got True"),
        ("n_scenarios: 10.7\n", "n_scenarios", "expected a whole number, got 10.7"),
        ("stage2_seed_fraction: .nan\n", "stage2_seed_fraction", "expected a finite number"),
        ("step_max: yes\n", "step_max", "expected a number, got 'yes'"),  # YAML 1.2: text
        ("framework: triple\n", "framework", "must be 'single' or 'dual', got 'triple'"),
        ("evolution:\n  mutation:\n    weight_rate: 1.5\n", "evolution.mutation.weight_rate",
         "must be <= 1.0, got 1.5"),
        ("evolution:\n  speciation:\n    threshold_min: 4.0\n", "evolution.speciation.threshold",
         "3.0 is below threshold_min 4.0"),
        ("evolution:\n  populaton_size: 10\n", "evolution.populaton_size",
         "unknown key (known: population_size, generations,"),
        ("evolution:\n  population_size: 20\n  elitism: 0.5\n  global_fraction: 0.5\n",
         "evolution.global_fraction", "elites (10) and global offspring (10) leave no room"),
        ("doe:\n  crowded_count: [8]\n", "doe.crowded_count", "expected 2 values, got [8]"),
        ("doe:\n  wall_count: [1.5, 2]\n", "doe.wall_count[0]", "expected a whole number"),
        ("heading_change_max_deg: 1e3\n", "heading_change_max_deg", "must be <= 180.0"),
        ("seed: -2\n", "seed", "must be >= 0, got -2"),
        ("seed: 3.0\n", "seed", "expected a whole number, got 3.0"),
        ("- 1\n- 2\n", None, "expected a mapping, got [1, 2]"),
    ],
)  # fmt: skip
def test_trainer_config_faults_are_one_line_naming_file_and_key(
    tmp_path: Path, text: str, key: str | None, fault: str
) -> None:
    path = tmp_path / "config.yaml"
    path.write_text(text)
    with pytest.raises(ConfigError) as info:
        load_config_file(path)
    assert info.value.key == key and info.value.path == str(path)
    where = f"{path}: {key}: " if key else f"{path}: "
    assert str(info.value).startswith(where + fault), str(info.value)
    assert "\n" not in str(info.value)


def test_trainer_config_types_are_strict_in_code_too() -> None:
    with pytest.raises(ConfigError) as info:
        TrainerConfig(generations=12.5)  # type: ignore[arg-type]
    assert info.value.key == "generations" and "whole number" in str(info.value)
    config = TrainerConfig(stage2_seed_fraction=1, step_max=1)
    assert isinstance(config.stage2_seed_fraction, float) and config.step_max == 1.0


def test_an_empty_trainer_config_file_is_refused(tmp_path: Path) -> None:
    path = tmp_path / "config.yaml"
    path.write_text("\n# robot: ugv\n")
    with pytest.raises(FileFormatError, match=r"config\.yaml: empty file"):
        load_config_file(path)
    path.write_text("{}\n")  # an explicit empty mapping: the defaults
    assert load_config_file(path) == (TrainerConfig.from_dict({}), None)


def test_yaml_numbers_are_yaml_1_2(tmp_path: Path) -> None:
    """1e-1 is a number (YAML 1.1, and PyYAML's default, read it as text)."""
    path = tmp_path / "config.yaml"
    path.write_text("stage2_seed_fraction: 25e-2\nevolution:\n  mutation:\n    weight_max: 1E1\n")
    config, _ = load_config_file(path)
    assert config.stage2_seed_fraction == 0.25 and config.evolution.mutation.weight_max == 10.0


@pytest.mark.parametrize("path", TRAIN_CONFIGS, ids=lambda p: p.name)
def test_shipped_trainer_configs_load_and_round_trip(path: Path, tmp_path: Path) -> None:
    config = TrainerConfig.from_yaml(path)
    again = tmp_path / "config.yaml"
    again.write_text(yaml.safe_dump({"seed": 5, **config.to_dict()}))
    assert load_config_file(again) == (config, 5)


def test_print_schema_describes_every_key_and_checks_configs(
    capsys: pytest.CaptureFixture[str],
) -> None:
    """``mentor-train --print-schema``: a JSON schema that accepts the shipped configs and a
    run's config.yaml, and refuses what the validation refuses."""
    jsonschema = pytest.importorskip("jsonschema")
    from mentor_core.cli.train import main as train_main

    assert train_main(["--print-schema"]) == 0
    schema = json.loads(capsys.readouterr().out)
    jsonschema.Draft202012Validator.check_schema(schema)
    fields = {f.name for f in dataclasses.fields(TrainerConfig)}
    assert set(schema["properties"]) == fields | {"seed", "extends"}
    assert schema["properties"]["generations"]["description"].startswith("Total generations")
    validator = jsonschema.Draft202012Validator(schema)
    for path in TRAIN_CONFIGS + EXPERIMENT_CONFIGS:
        validator.validate(yaml.safe_load(path.read_text()))
    validator.validate({"seed": 3, **TrainerConfig().to_dict()})
    for bad in ({"generations": 12.5}, {"generations": "12"}, {"generations": True},
                {"bogus": 1}, {"evolution": {"mutation": {"weight_rate": 1.5}}}):  # fmt: skip
        assert not validator.is_valid(bad), bad


# ------------------------------------------------------------ extends: a config and its departures


def test_extends_a_shipped_config_changes_only_the_keys_given(tmp_path: Path) -> None:
    path = tmp_path / "n40.yaml"
    path.write_text(
        "extends: swarm/paper\nn_scenarios: 40\n"
        "evolution:\n  mutation:\n    recurrent_rate: 0.05\n"
    )
    config = TrainerConfig.from_yaml(path)
    paper = shipped_config("swarm", "paper")
    mutation = dataclasses.replace(paper.evolution.mutation, recurrent_rate=0.05)
    evolution = dataclasses.replace(paper.evolution, mutation=mutation)
    assert config == dataclasses.replace(paper, n_scenarios=40, evolution=evolution)
    # the base's other evolution keys stay: a mapping is merged key by key
    assert config.evolution.mutation.max_hidden == 40
    assert config.evolution.speciation.threshold == paper.evolution.speciation.threshold


def test_extends_files_in_a_chain_relative_to_each_file(tmp_path: Path) -> None:
    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    (tmp_path / "a/base.yaml").write_text(
        "robot: ugv\nseed: 7\ngenerations: 20\nstage1_generations: 5\n"
        "doe:\n  wall_count: [1, 2]\nfamilies: [rooms, maze]\n"
    )
    (tmp_path / "b/mid.yaml").write_text(
        "extends: ../a/base.yaml\nfamilies: [slalom]\nstep_max: 0.4\n"
    )
    (tmp_path / "b/top.yaml").write_text("extends: mid.yaml\nstep_max: null\nseed: 3\n")
    config, seed = load_config_file(tmp_path / "b/top.yaml")
    assert seed == 3  # its own seed; a base's is not inherited
    assert (config.robot, config.generations, config.stage1_generations) == ("ugv", 20, 5)
    assert config.families == ("slalom",)  # a list replaces the base's
    assert config.step_max is None  # null replaces too
    assert config.doe.wall_count == (1, 2)
    assert load_config_file(tmp_path / "b/mid.yaml")[1] is None
    assert "extends" not in read_config(tmp_path / "b/top.yaml")


@pytest.mark.parametrize(
    ("text", "fault"),
    [
        ("extends: ugv/fast\n", "extends: no shipped config 'ugv/fast'"),
        ("extends: paper\n", "extends: no shipped config 'paper'"),
        ("extends: 3\n", "extends: must be a name or a YAML file's path, got 3"),
        ("extends: self.yaml\n", "extends: extends itself ("),
        ("extends: loop.yaml\n", "extends: extends itself ("),
        ("extends: list.yaml\n", "extends: list.yaml is not a mapping"),
        ("extends: swarm/paper\ngenerations: 0\n", "generations: must be >= 1, got 0"),
    ],
)
def test_bad_extends_is_one_line_naming_the_file(tmp_path: Path, text: str, fault: str) -> None:
    path = tmp_path / "self.yaml"
    path.write_text(text)
    (tmp_path / "loop.yaml").write_text("extends: self.yaml\n")
    (tmp_path / "list.yaml").write_text("- 1\n")
    with pytest.raises(ConfigError) as err:
        load_config_file(path)
    message = str(err.value)
    where = tmp_path / "loop.yaml" if "loop" in text else path  # the file whose extends closes it
    assert "\n" not in message and fault in message and message.startswith(f"{where}: ")


def test_a_missing_base_names_the_base(tmp_path: Path) -> None:
    path = tmp_path / "child.yaml"
    path.write_text("extends: gone.yaml\n")
    with pytest.raises(FileFormatError, match=r"gone\.yaml: no such file"):
        TrainerConfig.from_yaml(path)


@pytest.mark.parametrize("path", EXPERIMENT_CONFIGS, ids=lambda p: p.name)
def test_experiment_configs_load(path: Path) -> None:
    config = TrainerConfig.from_yaml(path)
    assert config.robot in path.name  # ugv_*.yaml trains the UGV, swarm_*.yaml the Swarm-Robot


def test_experiment_configs_train_what_was_pinned() -> None:
    """A shipped config's change moves the experiments that extend it: the pins
    (benchmarks/tools/pin_configs.py) say which, so that the experiments' configs stay what was
    measured."""
    done = subprocess.run(
        [sys.executable, str(ROOT / "benchmarks/tools/pin_configs.py"), "--check"],
        capture_output=True, text=True, check=False,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
