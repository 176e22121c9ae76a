"""The pytest front ends of the option tables (``model.option_tables``): `pytest --help` lists a
``--rmw-introspect-<name>`` option and an ``rmw_introspect_<name>`` ini key for every option whose
table says so and for nothing else, and a session given all of them puts each value in its
layer (tests/unit/test_option_tables.py checks the other front ends)."""

from __future__ import annotations

import json
import re

from pytest_rmw_introspect.model.option_tables import FAMILIES, FrontEnd

#: the plugin's own session options, in no table (they say how the session runs, not a check)
SESSION_FLAGS = {"--rmw-introspect-shard", "--rmw-introspect-capture-ahead", "--rmw-introspect-no-capture-ahead",
                 "--rmw-introspect-contracts"}
SESSION_INI_KEYS = {"rmw_introspect_contracts", "rmw_introspect_baseline", "rmw_introspect_capture_ahead"}

#: a valid value of each option that pytest takes: (command-line words after the flag, ini value)
VALUES = {
    "ignore_type_hash": ([], "true"),
    "ignore_qos": (["depth"], "depth history"),
    "allow_extra": ([], "true"),
    "include_infrastructure": ([], "true"),
    "fail_on": (["risky"], "breaking"),
    "include_types": ([], "true"),
    "ignore_parameters": (["rate"], "all"),
    "ignore_parameter_values": (["rate,speed"], "rate"),
    "settle": (["0.5"], "0.25"),
    "timeout": (["7"], "8"),
    "horizon": (["3"], "4"),
    "cold_start": ([], "true"),
    "lifecycle": (["inactive"], "unconfigured"),
    "read_parameters": (["false"], "false"),
    # issue 49: rule levels per project
    "rules": (["SUB_ADDED=breaking"], "QOS_DEPTH_*=note SUB_ADDED=risky"),
    # issue 49: the middleware whose QoS rules judge the contracts
    "rmw": (["rmw_zenoh_cpp"], "rmw_cyclonedds_cpp"),
}


def _exposed(front_end: FrontEnd) -> list:
    return [option for family in FAMILIES.values() for option in family.exposed(front_end)]


def test_help_lists_every_option_and_ini_key_of_the_tables_and_nothing_else(project):
    result = project.run("--help")
    assert result.ret == 0
    out = result.stdout.str()
    flags = set(re.findall(r"--rmw-introspect-[a-z-]+", out))
    ini_keys = set(re.findall(r"^  (rmw_introspect_[a-z_]+)", out, flags=re.M))
    assert flags - SESSION_FLAGS == {o.pytest_flag for o in _exposed(FrontEnd.PYTEST)}
    assert ini_keys - SESSION_INI_KEYS == {o.ini_key for o in _exposed(FrontEnd.INI)}
    assert sorted(VALUES) == sorted({o.name for o in _exposed(FrontEnd.PYTEST)} | {o.name for o in _exposed(FrontEnd.INI)})


def test_every_option_and_ini_key_reaches_its_layer(project):
    ini = "\n".join(f"{o.ini_key} = {VALUES[o.name][1]}" for o in _exposed(FrontEnd.INI))
    project.pytester.makeini(f"[pytest]\n{ini}\n")
    project.write("conftest.py", """
        import json
        from pytest_rmw_introspect.plugin.session import state

        def pytest_sessionstart(session):
            s = state(session.config)
            print("LAYERS " + json.dumps({"ini_options": s.ini_options, "cli_options": s.cli_options,
                                          "ini_target": s.ini_target, "cli_target": s.cli_target},
                                         default=lambda v: sorted(v) if isinstance(v, frozenset) else str(v)))
    """)
    project.test("def test_nothing():\n    pass\n")
    words = [word for o in _exposed(FrontEnd.PYTEST) for word in (o.pytest_flag, *VALUES[o.name][0])]
    result = project.run("-s", *words)
    assert result.ret == 0, result.stdout.str()
    line = next(line for line in result.stdout.lines if line.startswith("LAYERS "))
    layers = json.loads(line[len("LAYERS "):])
    for family, ini_layer, cli_layer in (("comparison", "ini_options", "cli_options"),
                                         ("target", "ini_target", "cli_target")):
        names = FAMILIES[family]
        assert sorted(layers[ini_layer]) == sorted(names.names(FrontEnd.INI))
        assert sorted(layers[cli_layer]) == sorted(names.names(FrontEnd.PYTEST))
    assert layers["ini_options"]["fail_on"] == "breaking" and layers["cli_options"]["fail_on"] == "risky"
    assert layers["ini_options"]["ignore_qos"] == ["depth", "history"]
    assert layers["cli_options"]["ignore_parameter_values"] == ["rate", "speed"]
    assert layers["ini_target"]["settle"] == 0.25 and layers["cli_target"]["timeout"] == 7.0
    assert layers["ini_target"]["cold_start"] is True and layers["cli_target"]["read_parameters"] == "false"
    assert [(r.split("key='")[1].split("'")[0], r.split("level='")[1].split("'")[0])
            for r in layers["ini_options"]["rules"]] == [("QOS_DEPTH_*", "note"), ("SUB_ADDED", "risky")]
    assert "level='breaking'" in layers["cli_options"]["rules"][0]


def test_a_bad_ini_value_names_the_key(project):
    project.pytester.makeini("[pytest]\nrmw_introspect_horizon = soon\n")
    project.test("def test_nothing():\n    pass\n")
    result = project.run()
    assert result.ret != 0
    assert "ini option rmw_introspect_horizon = 'soon' is not a number of seconds" in result.stderr.str()
