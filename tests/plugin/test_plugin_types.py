"""The contract's `types:` section through the plugin: include_types (marker, ini) makes
--update-golden write it, a contract without it drifts (TYPE_DESCRIPTION_MISSING), and a
changed type is reported field by field under its interface."""

from __future__ import annotations

from test_plugin_golden import EXPECTED_TALKER_CONTRACT, expected_talker_contract

TYPES_SECTION = """
# Generated with include_types: the definitions behind the type hashes above, so that a
# changed hash is reported field by field. Rewritten by --update-golden.
types:
  std_msgs/msg/String:
    fields:
      - string data
    constants: []
"""

MARKER_TEST = """
@pytest.mark.interfaces("contracts/talker.yaml", script=NODES + "/talker.py", include_types=True)
def test_talker(interfaces):
    assert "std_msgs/msg/String" in interfaces.types
"""

PLAIN_TEST = """
@pytest.mark.interfaces("contracts/talker.yaml", script=NODES + "/talker.py")
def test_talker(interfaces):
    pass
"""


def test_update_golden_writes_the_types_section_then_passes_and_changes_no_byte(project):
    project.test(MARKER_TEST)
    project.run("--update-golden").assert_outcomes(passed=1)
    written = project.read("contracts/talker.yaml")
    assert written == expected_talker_contract(project) + TYPES_SECTION
    project.run().assert_outcomes(passed=1, skipped=1)
    result = project.run("--update-golden")
    result.assert_outcomes(passed=1, skipped=1)
    assert "golden contract(s) written" not in result.stdout.str()
    assert project.read("contracts/talker.yaml") == written


def test_ini_include_types_makes_a_contract_without_the_section_drift(project):
    project.test(PLAIN_TEST)
    project.write("contracts/talker.yaml", EXPECTED_TALKER_CONTRACT)
    project.run().assert_outcomes(passed=1, skipped=1)
    project.pytester.makeini("[pytest]\nrmw_introspect_include_types = true\n")
    result = project.run()
    result.assert_outcomes(failed=1, skipped=1)
    result.stdout.fnmatch_lines([
        "*SAFE (1)*",
        "*publisher /chatter*",
        "*[[]TYPE_DESCRIPTION_MISSING[]] the contract's types: section does not describe std_msgs/msg/String*",
    ])
    project.run("--update-golden").assert_outcomes(passed=1, skipped=1)
    assert project.read("contracts/talker.yaml") == expected_talker_contract(project) + TYPES_SECTION
    # the section, once there, is kept up to date without the option
    project.pytester.makeini("[pytest]\n")
    project.run().assert_outcomes(passed=1, skipped=1)


def test_a_changed_type_is_reported_field_by_field_under_its_interface(project):
    project.test(MARKER_TEST)
    project.run("--update-golden").assert_outcomes(passed=1)
    # the golden as if written from an older std_msgs: another hash, a wide string
    golden = project.read("contracts/talker.yaml")
    edited = golden.replace("type_hash: RIHS01_df668c74", "type_hash: RIHS01_00000000").replace(
        "      - string data\n", "      - wstring data\n")
    project.write("contracts/talker.yaml", edited)
    result = project.run()
    result.assert_outcomes(failed=1, skipped=1)
    result.stdout.fnmatch_lines([
        "*Interface drift of script */talker.py against contracts/talker.yaml: 2 changes (2 breaking, 0 risky, 0 safe)",
        "*BREAKING (2)",
        "*  /talker",
        "*    publisher /chatter",
        "*      [[]TYPE_HASH_CHANGED[]] message definition of std_msgs/msg/String changed; the types: section shows how "
        "(1 field-level change listed under this interface)*",
        "*      [[]TYPE_FIELD_RETYPED[]] std_msgs/msg/String: field `data` wstring -> string: the field's wire "
        "representation changes",
    ])
    project.run("--update-golden").assert_outcomes(passed=1, skipped=1)
    assert project.read("contracts/talker.yaml") == golden
