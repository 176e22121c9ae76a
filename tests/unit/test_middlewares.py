"""QoS judged for the middleware a robot runs (issue 49 items 3 and 4): one test per row of
docs/drift-rules.md's "QoS per middleware" table, the service QoS rules, and where a system's
middleware comes from (``rmw:``, its launch environment, ``--rmw``)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from pytest_rmw_introspect.check import diff, system_pipeline
from pytest_rmw_introspect.cli.parser import build_parser
from pytest_rmw_introspect.compare import compatibility
from pytest_rmw_introspect.compare.compatibility import LaunchedProcess, check_compatibility, check_launched
from pytest_rmw_introspect.compare.options import parse_one
from pytest_rmw_introspect.errors import ContractError, OptionError, UsageError
from pytest_rmw_introspect.model import middlewares, qos, system_contract
from pytest_rmw_introspect.model.qos import Compatibility
from pytest_rmw_introspect.model.vocabulary import Severity

DOCS = Path(__file__).resolve().parents[2] / "docs" / "drift-rules.md"
OK, WARNING, ERROR = Compatibility.OK, Compatibility.WARNING, Compatibility.ERROR
BE, REL = {"reliability": "BEST_EFFORT"}, {"reliability": "RELIABLE"}
VOL, TL = {"durability": "VOLATILE"}, {"durability": "TRANSIENT_LOCAL"}
SD_REL, SD_DUR = {"reliability": "SYSTEM_DEFAULT"}, {"durability": "SYSTEM_DEFAULT"}
NO_DEADLINE, DEADLINE = {}, {"deadline_ns": 100_000_000}


def verdict(offered, requested, rmw):
    return qos.profile_compatibility(offered, requested, rmw)[0]


# ------------------------------------------------------------------- the table, row by row

def test_the_docs_table_has_a_row_per_known_middleware_and_the_dds_rules():
    text = DOCS.read_text(encoding="utf-8")
    section = text[text.index("## QoS per middleware"):]
    section = section[:section.index("\n## ", 3)]
    rows = re.findall(r"^\| (?:`([a-z_]+)`|none \(DDS rules\)) \|", section, flags=re.MULTILINE)
    assert sorted(r for r in rows if r) == sorted(middlewares.KNOWN)
    assert "" in rows  # the row of a system that does not say
    assert section.count("https://") >= 6  # every row has its sources


def test_row_dds_rules_when_the_middleware_is_not_said():
    # rmw_dds_common's rules as they are: errors, and warnings where SYSTEM_DEFAULT could go either way
    assert verdict(BE, REL, None) is ERROR and verdict(VOL, TL, None) is ERROR
    assert verdict(NO_DEADLINE, DEADLINE, None) is ERROR
    assert verdict(SD_REL, REL, None) is WARNING and verdict(BE, SD_REL, None) is WARNING
    assert verdict(SD_DUR, TL, None) is WARNING


@pytest.mark.parametrize("rmw", ["rmw_fastrtps_cpp", "rmw_fastrtps_dynamic_cpp"])
def test_row_fast_dds_refuses_like_dds_and_creates_system_default_as_its_writer_and_reader_defaults(rmw):
    assert verdict(BE, REL, rmw) is ERROR and verdict(VOL, TL, rmw) is ERROR and verdict(NO_DEADLINE, DEADLINE, rmw) is ERROR
    # a DataWriter's default is RELIABLE + TRANSIENT_LOCAL, a DataReader's BEST_EFFORT + VOLATILE
    # (measured on the wheels, and witnessed: tests/middleware/test_witnesses.py)
    assert verdict(SD_REL, REL, rmw) is OK
    assert verdict(BE, SD_REL, rmw) is OK
    assert verdict(SD_DUR, TL, rmw) is OK
    assert verdict(VOL, SD_DUR, rmw) is OK
    assert qos.settle_system_defaults("system_default", rmw, offering=True)["durability"] == "TRANSIENT_LOCAL"
    assert qos.settle_system_defaults("system_default", rmw, offering=False)["reliability"] == "BEST_EFFORT"


def test_row_cyclone_dds_creates_system_default_as_reliable_and_volatile_on_both_ends():
    rmw = "rmw_cyclonedds_cpp"
    assert verdict(BE, REL, rmw) is ERROR and verdict(VOL, TL, rmw) is ERROR
    assert verdict(SD_REL, REL, rmw) is OK
    # a subscription left at SYSTEM_DEFAULT requests RELIABLE there: a BEST_EFFORT publisher is refused
    compatibility_, reason = qos.profile_compatibility(BE, SD_REL, rmw)
    assert compatibility_ is ERROR and "rmw_cyclonedds_cpp creates SYSTEM_DEFAULT as subscription reliability RELIABLE" in reason
    # and a publisher left at SYSTEM_DEFAULT offers VOLATILE: a TRANSIENT_LOCAL subscription is refused
    assert verdict(SD_DUR, TL, rmw) is ERROR


def test_row_connext_keeps_the_dds_rules_and_their_warnings():
    rmw = "rmw_connextdds"
    assert verdict(BE, REL, rmw) is ERROR and verdict(VOL, TL, rmw) is ERROR
    assert verdict(SD_REL, REL, rmw) is WARNING and verdict(SD_DUR, TL, rmw) is WARNING


def test_row_zenoh_matches_any_qos():
    rmw = "rmw_zenoh_cpp"
    for offered, requested in ((BE, REL), (VOL, TL), (NO_DEADLINE, DEADLINE), (SD_REL, REL),
                               ({"liveliness": "AUTOMATIC"}, {"liveliness": "MANUAL_BY_TOPIC"})):
        assert qos.profile_compatibility(offered, requested, rmw) == (OK, "")


def test_an_unknown_middleware_is_an_error_naming_the_known_ones():
    with pytest.raises(ValueError, match="unknown middleware 'rmw_gurumdds_cpp': the QoS rules know rmw_fastrtps_cpp"):
        qos.profile_compatibility(BE, REL, "rmw_gurumdds_cpp")
    with pytest.raises(OptionError, match="`rmw` must be one of rmw_fastrtps_cpp, .*rmw_zenoh_cpp, got 'zenoh'"):
        parse_one("rmw", "zenoh", "pytest.ini")
    with pytest.raises(SystemExit):
        build_parser().parse_args(["compat", "a.yaml", "--rmw", "zenoh"])


# ------------------------------------------------------------------- system compatibility

def topic(qos_, name="/chatter"):
    return {"name": name, "type": "std_msgs/msg/String", "qos": qos_}


def pair(provider_kind, provider, requester_kind, requester):
    return {"a.yaml": {"/talker": {provider_kind: [provider]}}, "b.yaml": {"/listener": {requester_kind: [requester]}}}


def test_on_zenoh_a_pair_dds_would_refuse_is_a_note_not_a_problem():
    contracts = pair("publishers", topic("sensor_data"), "subscriptions", topic("default"))
    assert [i.rule for i in check_compatibility(contracts)] == ["QOS_INCOMPATIBLE"]
    item, = check_compatibility(contracts, rmw="rmw_zenoh_cpp")
    assert (item.rule, item.severity) == ("QOS_DDS_WOULD_REFUSE", Severity.NOTE) and item.rule in compatibility.NOTES
    assert "rmw_zenoh_cpp connects these" in item.message and "BEST_EFFORT publisher and RELIABLE subscription" in item.message
    # a pair every middleware connects has no note
    assert check_compatibility(pair("publishers", topic("default"), "subscriptions", topic("sensor_data")),
                               rmw="rmw_zenoh_cpp") == []


def test_on_fast_dds_a_system_default_publisher_is_no_warning():
    contracts = pair("publishers", topic("system_default"), "subscriptions", topic("map"))
    assert {i.rule for i in check_compatibility(contracts)} == {"QOS_MAYBE_INCOMPATIBLE"}
    assert check_compatibility(contracts, rmw="rmw_fastrtps_cpp") == []
    # strict_system_default: what rmw's own check answers (rmw_dds_common's), whatever the vendor
    assert {i.rule for i in check_compatibility(contracts, rmw="rmw_fastrtps_cpp", strict_system_default=True)} == {
        "QOS_MAYBE_INCOMPATIBLE"}


def service(qos_=None, name="/reset"):
    entry = {"name": name, "type": "std_srvs/srv/Trigger"}
    return {**entry, "qos": qos_} if qos_ is not None else entry


@pytest.mark.parametrize(("server", "client", "direction"), [
    ({"reliability": "RELIABLE"}, {"reliability": "BEST_EFFORT"}, "BEST_EFFORT client and RELIABLE server (requests)"),
    ({"reliability": "BEST_EFFORT"}, None, "BEST_EFFORT server and RELIABLE client (responses)"),
    (None, {"durability": "TRANSIENT_LOCAL"}, "VOLATILE server and TRANSIENT_LOCAL client (responses)"),
])
def test_a_service_pair_is_judged_on_requests_and_responses(server, client, direction):
    item, = check_compatibility(pair("service_servers", service(server), "service_clients", service(client)))
    assert (item.rule, item.severity) == ("QOS_INCOMPATIBLE", Severity.BREAKING)
    assert direction in item.message


def test_service_pairs_that_agree_connect_and_zenoh_notes_the_rest():
    assert check_compatibility(pair("service_servers", service(), "service_clients", service())) == []
    same = {"reliability": "BEST_EFFORT"}
    assert check_compatibility(pair("service_servers", service(same), "service_clients", service(same))) == []
    item, = check_compatibility(pair("service_servers", service(same), "service_clients", service()),
                                rmw="rmw_zenoh_cpp")
    assert item.rule == "QOS_DDS_WOULD_REFUSE"


def test_a_service_qos_is_written_only_where_it_decides_whether_a_client_is_served():
    raw = {"history": "KEEP_LAST", "depth": 1000, "reliability": "RELIABLE", "durability": "VOLATILE",
           "liveliness": "SYSTEM_DEFAULT", "deadline_ns": 0, "lifespan_ns": 0, "liveliness_lease_duration_ns": 0}
    assert qos.service_from_capture(raw) is None  # the parameters profile: depth alone differs
    assert qos.service_from_capture({**raw, "reliability": "BEST_EFFORT"}) == {"reliability": "BEST_EFFORT"}


# ------------------------------------------------------------------- which middleware a system runs on

HEADER = "system_version: 1\nlaunch: {path: robot.launch.xml}\n"
NODES = """\
processes:
  - {package: p, executable: cam, name: /cam, nodes: [/cam]}
  - {package: p, executable: det, name: /det, nodes: [/det]}
nodes:
  /cam:
    publishers: [{name: /image, type: std_msgs/msg/String, qos: sensor_data}]
  /det:
    subscriptions: [{name: /image, type: std_msgs/msg/String, qos: default}]
"""


def write(tmp_path, header_extra="", name="robot.system.yaml"):
    path = tmp_path / name
    path.write_text(HEADER + header_extra + NODES)
    return path


def test_a_system_contract_says_its_middleware_with_rmw(tmp_path):
    path = write(tmp_path, "rmw: rmw_zenoh_cpp\n")
    assert system_contract.load(path).middleware("rmw_fastrtps_cpp") == "rmw_zenoh_cpp"
    result = system_pipeline.check_contracts([path])
    assert result.items == [] and len(result.notes) == 1 and "rmw_zenoh_cpp connects these" in result.notes[0]
    assert "Notes:" in result.render_text()


def test_else_the_launch_environment_says_it_else_the_option(tmp_path):
    said = write(tmp_path, "target: {env: {RMW_IMPLEMENTATION: rmw_zenoh_cpp}}\n")
    assert system_contract.load(said).middleware("rmw_fastrtps_cpp") == "rmw_zenoh_cpp"
    silent = write(tmp_path, "", name="other.system.yaml")
    contract = system_contract.load(silent)
    assert contract.middleware(None) is None and contract.middleware("rmw_zenoh_cpp") == "rmw_zenoh_cpp"
    assert contract.middleware(None, [("robot.launch.xml:3", {"RMW_IMPLEMENTATION": "rmw_cyclonedds_cpp"})]) == \
        "rmw_cyclonedds_cpp"
    assert [i.rule for i in system_pipeline.check_contracts([silent]).items] == ["QOS_INCOMPATIBLE"]
    assert system_pipeline.check_contracts([silent], rmw="rmw_zenoh_cpp").items == []


def test_a_middleware_the_rules_do_not_know_is_a_clear_error(tmp_path):
    with pytest.raises(ContractError, match=r"robot.system.yaml.*'rmw_gurumdds_cpp' is not one of: rmw_fastrtps_cpp"):
        system_contract.load(write(tmp_path, "rmw: rmw_gurumdds_cpp\n"))
    env = write(tmp_path, "target: {env: {RMW_IMPLEMENTATION: rmw_gurumdds_cpp}}\n", name="env.system.yaml")
    with pytest.raises(ContractError, match=r"RMW_IMPLEMENTATION=rmw_gurumdds_cpp \(target.env\) is a middleware the QoS "
                                            r"rules do not know \(rmw_fastrtps_cpp, .*\): say which rules apply with `rmw:`"):
        system_pipeline.check_contracts([env])
    contract = system_contract.load(write(tmp_path, "", name="two.system.yaml"))
    with pytest.raises(ContractError, match="sets RMW_IMPLEMENTATION to several middlewares"):
        contract.middleware(None, [("a.xml:1", {"RMW_IMPLEMENTATION": "rmw_zenoh_cpp"}),
                                   ("a.xml:2", {"RMW_IMPLEMENTATION": "rmw_fastrtps_cpp"})])


def test_system_contracts_on_different_middlewares_are_not_checked_together(tmp_path):
    zenoh = write(tmp_path, "rmw: rmw_zenoh_cpp\n", name="a.system.yaml")
    dds = write(tmp_path, "rmw: rmw_cyclonedds_cpp\n", name="b.system.yaml")
    with pytest.raises(UsageError, match="run on different middlewares"):
        system_pipeline.check_contracts([zenoh, dds])


def test_check_launched_takes_the_middleware():
    processes = [LaunchedProcess("p/cam", "/cam", {"/cam": {"publishers": [topic("sensor_data", "/image")]}}),
                 LaunchedProcess("p/det", "/det", {"/det": {"subscriptions": [topic("default", "/image")]}})]
    assert [i.rule for i in check_launched(processes)] == ["QOS_INCOMPATIBLE"]
    assert [i.rule for i in check_launched(processes, rmw="rmw_zenoh_cpp")] == ["QOS_DDS_WOULD_REFUSE"]


def test_compat_takes_rmw_on_the_command_line(tmp_path, capsys):
    from pytest_rmw_introspect.cli.compat import cmd_compat

    path = write(tmp_path)
    args = build_parser().parse_args(["compat", str(path), "--rmw", "rmw_zenoh_cpp"])
    assert cmd_compat(args) == 0
    assert "rmw_zenoh_cpp connects these" in capsys.readouterr().out
    args = build_parser().parse_args(["compat", str(path)])
    assert cmd_compat(args) == 1


# ------------------------------------------------------------------- diff

NODE = """\
contract_version: 1
nodes:
  /cam:
    publishers: [{{name: /image, type: std_msgs/msg/String, qos: {qos}}}]
"""


def test_diff_judges_qos_drift_for_the_middleware(tmp_path):

    old, new = tmp_path / "old.interfaces.yaml", tmp_path / "new.interfaces.yaml"
    old.write_text(NODE.format(qos="default"))
    new.write_text(NODE.format(qos="sensor_data"))
    weakened = [i for i in diff.diff_contracts(old, new).items if i.rule == "QOS_RELIABILITY_WEAKENED"]
    assert [i.severity for i in weakened] == [Severity.BREAKING]
    zenoh = [i for i in diff.diff_contracts(old, new, {"rmw": "rmw_zenoh_cpp"}).items
             if i.rule == "QOS_RELIABILITY_WEAKENED"]
    assert [i.severity for i in zenoh] == [Severity.RISKY]


def test_diff_of_system_contracts_takes_the_middleware_they_say(tmp_path):
    reliable = NODES.replace("qos: sensor_data", "qos: default")
    old = tmp_path / "old.system.yaml"
    old.write_text(HEADER + reliable)
    new = write(tmp_path, "", name="new.system.yaml")  # the camera now publishes BEST_EFFORT

    def weakened(result):
        return [i.severity for i in result.items if i.rule == "QOS_RELIABILITY_WEAKENED"]

    assert weakened(diff.diff_contracts(old, new)) == [Severity.BREAKING]
    new.write_text(HEADER + "rmw: rmw_zenoh_cpp\n" + NODES)
    result = diff.diff_contracts(old, new)
    assert result.options.rmw == "rmw_zenoh_cpp" and weakened(result) == [Severity.RISKY]
    # what a contract says beats --rmw
    assert diff.diff_contracts(old, new, [({"rmw": "rmw_cyclonedds_cpp"}, "command line")]).options.rmw == \
        "rmw_zenoh_cpp"


def test_the_gate_judges_a_system_contract_for_the_middleware_it_says(tmp_path, monkeypatch):
    """``diff --against`` compares by ``diff``'s path: a system contract that moved to Zenoh weakens
    its camera's reliability without a BREAKING finding (the gate once judged it by the DDS rules)."""
    import subprocess

    from pytest_rmw_introspect.check import gate

    monkeypatch.chdir(tmp_path)
    subprocess.run(["git", "init", "-q", "-b", "main"], check=True)
    for config in (["user.email", "t@example.com"], ["user.name", "t"]):
        subprocess.run(["git", "config", *config], check=True)
    contract = write(tmp_path, "", name="robot.system.yaml")
    contract.write_text(HEADER + NODES.replace("qos: sensor_data", "qos: default"))
    subprocess.run(["git", "add", "robot.system.yaml"], check=True)
    subprocess.run(["git", "commit", "-q", "-m", "robot"], check=True)
    contract.write_text(HEADER + NODES)  # the camera publishes BEST_EFFORT now
    assert [i.severity for i in gate.run("HEAD", ["robot.system.yaml"]).contracts[0].items
            if i.rule == "QOS_RELIABILITY_WEAKENED"] == [Severity.BREAKING]
    contract.write_text(HEADER + "rmw: rmw_zenoh_cpp\n" + NODES)
    [compared] = gate.run("HEAD", ["robot.system.yaml"]).contracts
    assert [i.severity for i in compared.items if i.rule == "QOS_RELIABILITY_WEAKENED"] == [Severity.RISKY]
    assert not compared.failed


def test_the_consumers_of_a_changed_interface_are_judged_for_the_middleware():
    from pytest_rmw_introspect.compare import consumers, drift

    old = {"/cam": {"publishers": [topic("default", "/image")]}}
    new = {"/cam": {"publishers": [topic("sensor_data", "/image")]}}
    systems = {"robot.system.yaml": {"/det": {"subscriptions": [topic("default", "/image")]}}}
    items = drift.compare(old, new)
    assert "CONSUMER_INCOMPATIBLE" in {i.rule for i in consumers.judge(items, new, old, systems)}
    assert "CONSUMER_INCOMPATIBLE" not in {i.rule for i in consumers.judge(items, new, old, systems, rmw="rmw_zenoh_cpp")}
