"""The option tables (``model.option_tables``): every front end the table generates accepts every
key the table gives it and nothing else (the contract schema, the ``rmw-introspect`` flags, the
marker's keyword arguments, the parsers of both families; the pytest options and ini keys are
tests/plugin/test_plugin_option_tables.py), the defaults are the table's, precedence is the
table's, and the reference pages and the schema file are rendered from it."""

from __future__ import annotations

import argparse
import shlex
from pathlib import Path
from types import SimpleNamespace
from typing import Any

import jsonschema
import pytest

from pytest_rmw_introspect import options_reference
from pytest_rmw_introspect.check.pipeline import Layers
from pytest_rmw_introspect.cli.arguments import compare_from_args, target_from_args
from pytest_rmw_introspect.cli.check import accept_command
from pytest_rmw_introspect.cli.parser import build_parser
from pytest_rmw_introspect.compare.options import OPTION_KEYS, ComparisonOptions, parse_layer, parse_one
from pytest_rmw_introspect.errors import OptionError
from pytest_rmw_introspect.model import contract, system_contract
from pytest_rmw_introspect.model.contract import Contract
from pytest_rmw_introspect.model.option_tables import (
    COMPARISON,
    FAMILIES,
    PRECEDENCE,
    TARGET,
    FrontEnd,
    Source,
    stack,
)
from pytest_rmw_introspect.plugin import marker, system_marker
from pytest_rmw_introspect.run.target import TARGET_KEYS, TargetSpec

#: a valid value of every option: (as a contract or marker writes it, as rmw-introspect flags say it)
SAMPLES: dict[str, tuple[Any, list[str]]] = {
    "ignore_type_hash": (True, ["--ignore-type-hash"]),
    "ignore_qos": (["depth"], ["--ignore-qos", "depth"]),
    "rmw": ("rmw_zenoh_cpp", ["--rmw", "rmw_zenoh_cpp"]),
    "allow_extra": (True, ["--allow-extra"]),
    "include_infrastructure": (True, ["--include-ros-infra"]),
    "fail_on": ("risky", ["--fail-on", "risky"]),
    "include_types": (True, ["--include-types"]),
    "ignore_parameters": (["qos_overrides.*"], ["--ignore-parameters", "qos_overrides.*"]),
    "ignore_parameter_values": (["rate"], ["--ignore-parameter-values", "rate"]),
    "system_fail_on": ("any", ["--system-fail-on", "any"]),
    # issue 49: rule levels per project
    "rules": ({"SUB_ADDED": "breaking"}, ["--rule", "SUB_ADDED=breaking"]),
    "package": ("demo_pkg", ["--package", "demo_pkg"]),
    "executable": ("talker", ["--executable", "talker"]),
    "command": (["echo", "hi"], []),
    "script": ("node.py", ["--script", "node.py"]),
    "module": ("my_pkg.node", ["--module", "my_pkg.node"]),
    "entry_point": ("my_pkg.node:main", ["--entry-point", "my_pkg.node:main"]),
    "arguments": (["fast"], ["--arg", "fast"]),
    "namespace": ("/robot1", ["--namespace", "/robot1"]),
    "node_name": ("talker2", ["--node-name", "talker2"]),
    "remappings": ({"chatter": "talk"}, ["--remap", "chatter:=talk"]),
    "parameters": ({"rate": 5}, ["--param", "rate:=5"]),
    "params_file": ("params.yaml", ["--params-file", "params.yaml"]),
    "env": ({"A": "1"}, ["--env", "A=1"]),
    "cwd": ("run", ["--cwd", "run"]),
    "settle": (0.5, ["--settle", "0.5"]),
    "timeout": (3.0, ["--timeout", "3"]),
    "horizon": (2.0, ["--horizon", "2"]),
    "cold_start": (True, ["--cold-start"]),
    "lifecycle": ("inactive", ["--lifecycle", "inactive"]),
    "read_parameters": (False, ["--no-read-parameters"]),
    "stimuli": (["/reset"], ["--stimulus", "/reset"]),
}


def test_every_option_has_a_sample_and_names_are_unique():
    everything = [o.name for f in FAMILIES.values() for o in f.options]
    assert len(everything) == len(set(everything))
    assert sorted(everything) == sorted(SAMPLES)


# ---------------------------------------------------------------------------- parsers of both families


def test_the_parsers_take_exactly_their_tables_keys():
    assert OPTION_KEYS == COMPARISON.names()
    assert TARGET_KEYS == TARGET.names()
    for key in COMPARISON.names():
        parse_one(key, SAMPLES[key][0], "test")
    for key in TARGET.names():
        TargetSpec.from_mapping({key: SAMPLES[key][0]}, base_dir="/tmp", source="test")
    with pytest.raises(OptionError, match="unknown option 'settle'"):
        parse_one("settle", 1.0, "test")


def test_defaults_are_the_tables():
    defaults = ComparisonOptions()
    for option in COMPARISON.options:
        assert getattr(defaults, option.name) == option.default, option.name
    spec = TargetSpec()
    assert spec.effective_settle() == TARGET["settle"].default
    assert spec.effective_timeout() == TARGET["timeout"].default
    assert spec.effective_horizon() == TARGET["horizon"].default
    assert spec.effective_lifecycle() == TARGET["lifecycle"].default
    assert spec.effective_read_parameters() is TARGET["read_parameters"].default
    assert not spec.cold_start and TARGET["cold_start"].default is False


# ---------------------------------------------------------------------------- contract schema


def _valid(schema: dict[str, Any], document: dict[str, Any]) -> bool:
    return jsonschema.Draft7Validator(schema).is_valid(document)


def test_the_contract_schema_takes_every_key_of_its_blocks_and_nothing_else():
    definitions = contract.schema()["definitions"]
    assert list(definitions["options"]["properties"]) == list(COMPARISON.names(FrontEnd.CONTRACT))
    assert list(definitions["target"]["properties"]) == list(TARGET.names(FrontEnd.CONTRACT))
    node_contract = contract.schema()
    for family, block in ((COMPARISON, "options"), (TARGET, "target")):
        for name in family.names(FrontEnd.CONTRACT):
            assert _valid(node_contract, {"contract_version": 1, "nodes": {}, block: {name: SAMPLES[name][0]}}), name
        assert not _valid(node_contract, {"contract_version": 1, "nodes": {}, block: {"strict": True}})


def test_the_system_contract_schema_takes_the_keys_of_every_process_and_nothing_else():
    definitions = system_contract.schema()["definitions"]
    assert list(definitions["system_target"]["properties"]) == list(TARGET.names(FrontEnd.SYSTEM))
    assert system_contract.SYSTEM_TARGET_KEYS == TARGET.names(FrontEnd.SYSTEM)
    assert list(definitions["options"]["properties"]) == list(COMPARISON.names(FrontEnd.SYSTEM))
    assert "system_fail_on" not in contract.schema()["definitions"]["options"]["properties"]
    assert "script" not in definitions["system_target"]["properties"]


def test_the_schema_file_is_generated_from_the_tables():
    path = Path(contract.__file__).parent.parent / "schema" / "contract.schema.json"
    assert path.read_text("utf-8") == options_reference.contract_schema_text(path.read_text("utf-8")), (
        "the option tables changed: run `python -m pytest_rmw_introspect.options_reference --write-schema`")


# ---------------------------------------------------------------------------- rmw-introspect flags


def _subparser(name: str) -> argparse.ArgumentParser:
    action = next(a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction))
    return action.choices[name]


def _group_dests(parser: argparse.ArgumentParser, title: str) -> list[str]:
    group = next(g for g in parser._action_groups if g.title == title)
    return [a.dest for a in group._group_actions]


@pytest.mark.parametrize("command, front_end", [("check", FrontEnd.CLI), ("diff", FrontEnd.DIFF)])
def test_the_comparison_flags_are_the_tables(command, front_end):
    title = "comparison options (override the contract's options: block)"
    assert _group_dests(_subparser(command), title) == list(COMPARISON.names(front_end))


@pytest.mark.parametrize("command", ["capture", "check"])
def test_the_target_flags_are_the_tables(command):
    assert _group_dests(_subparser(command), "target options") == list(TARGET.names(FrontEnd.CLI))


@pytest.mark.parametrize("name", COMPARISON.names(FrontEnd.CLI))
def test_every_comparison_flag_gives_its_option(name):
    value, words = SAMPLES[name]
    args = build_parser().parse_args(["check", "c.yaml", *words])
    given = {k: v for k, v in compare_from_args(args).items() if v is not None}
    assert parse_layer(given, "command line") == parse_layer({name: value}, "contract")


@pytest.mark.parametrize("name", TARGET.names(FrontEnd.CLI))
def test_every_target_flag_gives_its_option(name):
    value, words = SAMPLES[name]
    for command in (["capture"], ["check", "c.yaml"]):
        args = build_parser().parse_args([*command, *words])
        flags = TargetSpec.from_mapping(target_from_args(args, None), base_dir="/tmp", source="command line")
        assert flags == TargetSpec.from_mapping({name: value}, base_dir="/tmp", source="contract")


def test_the_command_is_what_follows_the_double_dash():
    args = build_parser().parse_args(["capture"])
    assert target_from_args(args, ["echo", "hi"]) == {"command": ["echo", "hi"]}


@pytest.mark.parametrize("flag", ["--strict", "--rmw-introspect-fail-on", "--system-fail-on"])
def test_flags_that_are_not_in_the_table_are_refused(flag, capsys):
    with pytest.raises(SystemExit) as info:
        build_parser().parse_args(["diff", "a.yaml", "b.yaml", flag, "any"])
    assert info.value.code == 2
    assert "unrecognized arguments" in capsys.readouterr().err


def test_the_update_hint_says_every_flag_again():
    words = [word for name in TARGET.names(FrontEnd.CLI) if name not in ("package", "executable", "script",
                                                                         "module", "entry_point")
             for word in SAMPLES[name][1]]
    words += [word for name in COMPARISON.names(FrontEnd.CLI) for word in SAMPLES[name][1]]
    words += ["--script", "node.py"]
    args = build_parser().parse_args(["check", "c.yaml", *words])
    hint = accept_command(args, "c.yaml", None)
    again = build_parser().parse_args(shlex.split(hint)[1:])
    assert again.update and "--stimulus /reset" in hint and "--cold-start" in hint
    for name in (*TARGET.names(FrontEnd.CLI), *COMPARISON.names(FrontEnd.CLI)):
        assert getattr(again, name) == getattr(args, name), name


# ---------------------------------------------------------------------------- markers


class _Item(SimpleNamespace):
    def get_closest_marker(self, name: str) -> Any:
        return self.mark if name == self.mark.name else None


def _item(mark: pytest.MarkDecorator, tmp_path: Path) -> Any:
    return _Item(mark=mark.mark, nodeid="test_x.py::test_x", path=tmp_path / "test_x.py")


def test_the_interfaces_marker_takes_every_option_of_both_tables(tmp_path):
    kwargs = {name: SAMPLES[name][0] for name in (*TARGET.names(FrontEnd.MARKER), *COMPARISON.names(FrontEnd.MARKER))}
    _path, target, options = marker.parse(_item(pytest.mark.interfaces("c.yaml", **kwargs), tmp_path))
    assert list(target) == list(TARGET.names(FrontEnd.MARKER))
    assert list(options) == list(COMPARISON.names(FrontEnd.MARKER))
    with pytest.raises(OptionError, match="unknown keyword argument"):
        marker.parse(_item(pytest.mark.interfaces("c.yaml", strict=True), tmp_path))


def test_the_system_marker_takes_the_options_of_every_process(tmp_path):
    kwargs = {name: SAMPLES[name][0] for name in (*TARGET.names(FrontEnd.SYSTEM), *COMPARISON.names(FrontEnd.SYSTEM))}
    mark = pytest.mark.system_contract("r.system.yaml", **kwargs)
    _path, _arguments, target, options = system_marker.parse(_item(mark, tmp_path))
    assert list(target) == list(TARGET.names(FrontEnd.SYSTEM))
    assert list(options) == list(COMPARISON.names(FrontEnd.SYSTEM))
    with pytest.raises(OptionError, match="unknown keyword argument"):
        system_marker.parse(_item(pytest.mark.system_contract("r.system.yaml", script="x.py"), tmp_path))


# ---------------------------------------------------------------------------- precedence


def test_stack_orders_layers_by_the_tables_precedence():
    assert PRECEDENCE == (Source.DEFAULT, Source.INI, Source.PYTEST, Source.CONTRACT, Source.OWN)
    given = {Source.OWN: ["marker"], Source.INI: ["ini", "ini 2"], Source.CONTRACT: ["contract"],
             Source.PYTEST: ["pytest"]}
    assert stack(given) == ["ini", "ini 2", "pytest", "contract", "marker"]


@pytest.mark.parametrize("strongest", [Source.DEFAULT, Source.INI, Source.PYTEST, Source.CONTRACT, Source.OWN])
def test_the_strongest_source_that_sets_an_option_wins(strongest, tmp_path):
    """Every source sets fail_on and settle, up to ``strongest``: its value is the one used."""
    fail_on = {Source.INI: "breaking", Source.PYTEST: "risky", Source.CONTRACT: "breaking", Source.OWN: "risky"}
    settle = {Source.INI: 1.0, Source.PYTEST: 2.0, Source.CONTRACT: 3.0, Source.OWN: 4.0}
    used = PRECEDENCE[1:PRECEDENCE.index(strongest) + 1]

    def layers(values: dict[Source, Any], key: str) -> dict[Source, list[Any]]:
        return {s: [{key: values[s]}] for s in used if s in (Source.INI, Source.PYTEST)}

    weak_options = {s: [(layer[0], s.value)] for s, layer in layers(fail_on, "fail_on").items()}
    weak_target = {s: [(layer[0], tmp_path, s.value)] for s, layer in layers(settle, "settle").items()}
    own = Source.OWN in used
    resolved = Layers(weak_target=weak_target, weak_options=weak_options,
                      strong_target=[({"settle": settle[Source.OWN]}, tmp_path, "marker")] if own else [],
                      strong_options=[({"fail_on": fail_on[Source.OWN]}, "marker")] if own else [])
    with_contract = Source.CONTRACT in used
    written = Contract(path=tmp_path / "c.yaml", nodes={},
                       options={"fail_on": fail_on[Source.CONTRACT]} if with_contract else {},
                       target={"settle": settle[Source.CONTRACT]} if with_contract else None)
    expected_fail_on = fail_on.get(strongest, COMPARISON["fail_on"].default)
    expected_settle = settle.get(strongest, TARGET["settle"].default)
    assert resolved.options(written, shown="c.yaml").fail_on == expected_fail_on
    assert resolved.target(written, path=tmp_path / "c.yaml").effective_settle() == expected_settle


def test_weak_layers_are_below_the_contract():
    with pytest.raises(AssertionError):
        Layers(weak_options={Source.OWN: [({"fail_on": "risky"}, "marker")]})


# ---------------------------------------------------------------------------- reference pages


@pytest.mark.parametrize("name", sorted(FAMILIES))
def test_the_reference_page_names_every_option_and_its_spellings(name):
    page = options_reference.render_markdown(name)
    table = FAMILIES[name]
    assert page.startswith(f"# {table.title}\n")
    for option in table.options:
        row = next(line for line in page.splitlines() if line.startswith(f"| `{option.name}` |"))
        assert (f"`{option.pytest_flag}`" in row) == (FrontEnd.PYTEST in option.front_ends)
        assert (f"`{option.ini_key}`" in row) == (FrontEnd.INI in option.front_ends)
        assert (f"`{option.flag}" in row) == (FrontEnd.CLI in option.front_ends)
        assert row.count(" | ") == 7, row  # no `|` of a value splits a cell
    assert "## Precedence" in page


def test_an_unknown_family_names_the_known_ones():
    with pytest.raises(KeyError, match="known: comparison, target"):
        options_reference.render_markdown("session")


def test_the_module_prints_a_page(capsys):
    assert options_reference.main(["target"]) == 0
    assert capsys.readouterr().out == options_reference.render_markdown("target")


# ---------------------------------------------------------------------------- the gate's options
def test_the_gate_has_one_name_per_option_in_the_cli_pytest_and_the_action(pytester):
    """issue 51 item 4: `against` and `against_system` are rows of the GATE table, spelled from it
    by `rmw-introspect diff`, by pytest and by the action's inputs."""
    import yaml

    from pytest_rmw_introspect.model.option_tables import GATE

    diff = next(a for a in build_parser()._subparsers._group_actions[0].choices.items() if a[0] == "diff")[1]
    cli_flags = {flag: action.dest for action in diff._actions for flag in action.option_strings}
    inputs = yaml.safe_load((Path(__file__).parents[2] / "action.yml").read_text())["inputs"]
    pytest_help = pytester.runpytest("--help").stdout.str()
    for option in GATE.options:
        assert option.flag == option.pytest_flag == "--" + option.action_input, option.name
        assert cli_flags[option.flag] == option.name
        assert f"{option.pytest_flag}=" in pytest_help
        assert option.action_input in inputs, f"action.yml has no input {option.action_input}"
    action = (Path(__file__).parents[2] / "action.yml").read_text()
    assert "--against-system \"$system\"" in action and "--against \"$RMWI_AGAINST\"" in action
    # the CLI's old spelling of --against-system is still read, under the one name
    assert cli_flags["--system"] == "against_system"
