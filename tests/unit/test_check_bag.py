"""`rmw-introspect check --bag PATH CONTRACT...` (issue 52 item 3): contracts checked against rosbag2
recordings. The recordings are real files in rosbag2's layout, written here as rosbag2 writes them:
`metadata.yaml` (version 9, Jazzy's, and version 8), MCAP storage written with the `mcap` library's
writer (channel metadata `offered_qos_profiles` and `topic_type_hash`, a `rosbag2` metadata record, as
rosbag2_storage_mcap writes them) and sqlite3 storage written with rosbag2's schema; the check reads
them. No ROS process runs."""

from __future__ import annotations

import json
import re
import sqlite3
from pathlib import Path

import pytest
import yaml
from mcap.writer import Writer

from pytest_rmw_introspect import cli
from pytest_rmw_introspect.model import recording as recording_model

STRING = "std_msgs/msg/String"
STRING_HASH = "RIHS01_df668c740482bbd48fb39d76a70dfd4bd59db1288021743503259e948f6b1a18"
OTHER_HASH = "RIHS01_" + "0" * 64
INFINITE = {"sec": 9223372036, "nsec": 854775807}

TALKER = f"""\
contract_version: 1
nodes:
  /talker:
    publishers:
      - name: /chatter
        type: {STRING}
        type_hash: {STRING_HASH}
        qos: {{history: KEEP_LAST, depth: 10, reliability: RELIABLE, durability: VOLATILE}}
    subscriptions: []
    service_servers: []
    service_clients: []
    action_servers: []
    action_clients: []
"""
LISTENER = f"""\
contract_version: 1
nodes:
  /listener:
    publishers: []
    subscriptions:
      - name: /chatter
        type: {STRING}
        type_hash: {STRING_HASH}
        qos: {{history: KEEP_LAST, depth: 10, reliability: RELIABLE, durability: VOLATILE}}
    service_servers: []
    service_clients: []
    action_servers: []
    action_clients: []
"""


def profile(version: int = 9, *, reliability: str = "reliable", durability: str = "volatile") -> dict:
    """One offered QoS profile as rosbag2 writes a discovered publisher's (history and depth unknown)."""
    if version >= 9:
        return {"history": "unknown", "depth": 0, "reliability": reliability, "durability": durability,
                "deadline": INFINITE, "lifespan": INFINITE, "liveliness": "automatic",
                "liveliness_lease_duration": INFINITE, "avoid_ros_namespace_conventions": False}
    ints = {"reliable": 1, "best_effort": 2, "transient_local": 1, "volatile": 2}
    return {"history": 3, "depth": 0, "reliability": ints[reliability], "durability": ints[durability],
            "deadline": INFINITE, "lifespan": INFINITE, "liveliness": 1, "liveliness_lease_duration": INFINITE,
            "avoid_ros_namespace_conventions": False}


def topic(name: str = "/chatter", type_name: str = STRING, *, count: int = 5, type_hash: str = STRING_HASH,
          profiles: list[dict] | None = None) -> dict:
    return {"name": name, "type": type_name, "hash": type_hash, "count": count,
            "profiles": [{}] if profiles is None else profiles}


def metadata(topics: list[dict], *, storage: str, files: list[str], version: int = 9) -> dict:
    """``metadata.yaml`` as rosbag2 (Jazzy: version 9) writes it."""
    entries = []
    for t in topics:
        profiles = [profile(version, **p) for p in t["profiles"]]
        meta = {"name": t["name"], "type": t["type"], "serialization_format": "cdr",
                "offered_qos_profiles": profiles if version >= 9 else yaml.safe_dump(profiles, sort_keys=False)}
        if version >= 7:
            meta["type_description_hash"] = t["hash"]
        entries.append({"topic_metadata": meta, "message_count": t["count"]})
    total = sum(t["count"] for t in topics)
    return {"rosbag2_bagfile_information": {
        "version": version, "storage_identifier": storage, "duration": {"nanoseconds": 1000},
        "starting_time": {"nanoseconds_since_epoch": 1_700_000_000_000_000_000}, "message_count": total,
        "topics_with_message_count": entries, "compression_format": "", "compression_mode": "",
        "relative_file_paths": files,
        "files": [{"path": f, "starting_time": {"nanoseconds_since_epoch": 1_700_000_000_000_000_000},
                   "duration": {"nanoseconds": 1000}, "message_count": total} for f in files],
        "custom_data": None, "ros_distro": "jazzy"}}


def write_mcap(path: Path, topics: list[dict], *, version: int = 9) -> None:
    """An MCAP file as rosbag2_storage_mcap writes it: a schema per type, a channel per topic with
    its offered QoS profiles (always in version 9's spelling) and type hash in the channel metadata,
    the bag's metadata record."""
    with open(path, "wb") as stream:
        writer = Writer(stream)
        writer.start(profile="ros2", library="rosbag2_storage_mcap (test)")
        schemas: dict[str, int] = {}
        for t in topics:
            if t["type"] not in schemas:
                schemas[t["type"]] = writer.register_schema(t["type"], "ros2msg", b"string data\n")
            channel = writer.register_channel(t["name"], "cdr", schemas[t["type"]], {
                "offered_qos_profiles": yaml.safe_dump([profile(**p) for p in t["profiles"]], sort_keys=False),
                "topic_type_hash": t["hash"]})
            for i in range(t["count"]):
                writer.add_message(channel, log_time=1000 + i, publish_time=1000 + i, data=b"\x00\x01\x00\x00" + b"x" * 8)
        writer.add_metadata("rosbag2", {"serialized_metadata": yaml.safe_dump(
            metadata(topics, storage="mcap", files=[path.name], version=version))})
        writer.finish()


def write_db3(path: Path, topics: list[dict], *, version: int = 9) -> None:
    """An sqlite3 file in rosbag2's schema (Jazzy): topics with their QoS as a YAML string, messages."""
    db = sqlite3.connect(path)
    db.executescript("""
        CREATE TABLE schema(schema_version INTEGER PRIMARY KEY, ros_distro TEXT NOT NULL);
        CREATE TABLE metadata(id INTEGER PRIMARY KEY, metadata_version INTEGER NOT NULL, metadata TEXT NOT NULL);
        CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL,
            serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL, type_description_hash TEXT NOT NULL);
        CREATE TABLE message_definitions(id INTEGER PRIMARY KEY, topic_type TEXT NOT NULL, encoding TEXT NOT NULL,
            encoded_message_definition TEXT NOT NULL, type_description_hash TEXT NOT NULL);
        CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL, timestamp INTEGER NOT NULL,
            data BLOB NOT NULL);
        CREATE INDEX timestamp_idx ON messages (timestamp ASC);
        INSERT INTO schema (schema_version, ros_distro) VALUES (4, 'jazzy');
    """)
    for topic_id, t in enumerate(topics, start=1):
        profiles = [profile(version, **p) for p in t["profiles"]]
        db.execute("INSERT INTO topics (id, name, type, serialization_format, offered_qos_profiles, "
                   "type_description_hash) VALUES (?, ?, ?, 'cdr', ?, ?)",
                   (topic_id, t["name"], t["type"], yaml.safe_dump(profiles, sort_keys=False), t["hash"]))
        db.executemany("INSERT INTO messages (topic_id, timestamp, data) VALUES (?, ?, ?)",
                       [(topic_id, 1000 + i, b"\x00\x01\x00\x00xxxx") for i in range(t["count"])])
    db.commit()
    db.close()


def bag(tmp_path: Path, topics: list[dict], *, storage: str = "mcap", version: int = 9, name: str = "rec") -> Path:
    """A bag directory as `ros2 bag record -o rec` leaves it: metadata.yaml and one storage file."""
    directory = tmp_path / name
    directory.mkdir()
    file = f"{name}_0.{'mcap' if storage == 'mcap' else 'db3'}"
    if storage == "mcap":
        write_mcap(directory / file, topics, version=version)
    else:
        write_db3(directory / file, topics, version=version)
    (directory / "metadata.yaml").write_text(
        yaml.safe_dump(metadata(topics, storage=storage, files=[file], version=version), sort_keys=False))
    return directory


@pytest.fixture
def contracts(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "talker.interfaces.yaml").write_text(TALKER)
    (tmp_path / "listener.interfaces.yaml").write_text(LISTENER)
    return ["talker.interfaces.yaml", "listener.interfaces.yaml"]


def check(*args: str) -> int:
    return cli.main(["check", *args])


# ---------------------------------------------------------------------------- verdicts


@pytest.mark.parametrize("storage", ["mcap", "sqlite3"])
def test_a_matching_recording_passes_and_says_the_counts(tmp_path, contracts, capsys, storage):
    rec = bag(tmp_path, [topic(count=5)], storage=storage)
    assert check("--bag", "rec", *contracts) == 0
    out, err = capsys.readouterr()
    assert "talker.interfaces.yaml: matches (1 publisher on recorded topics, 5 messages, in rec)" in out
    assert ("listener.interfaces.yaml: matches (0 publishers on recorded topics, 0 messages; 1 subscription fit the "
            "recorded publishers, in rec)") in out
    assert "rec: matches (every topic declared; 1 recorded topic, 5 messages: /chatter 5 messages)" in out
    assert "note: rec: a recording shows topics" in err and "not subscriptions, services" in err
    assert recording_model.read(rec).storage == storage


def test_a_plain_mcap_file_is_a_recording(tmp_path, contracts, capsys):
    write_mcap(tmp_path / "field_test.mcap", [topic(count=3)])
    assert check("--bag", "field_test.mcap", *contracts) == 0
    assert "field_test.mcap: matches (every topic declared; 1 recorded topic, 3 messages" in capsys.readouterr().out


def test_a_plain_db3_file_is_a_recording(tmp_path, contracts, capsys):
    write_db3(tmp_path / "field_test.db3", [topic(count=2)])
    assert check("--bag", "field_test.db3", *contracts) == 0
    assert "/chatter 2 messages" in capsys.readouterr().out


def test_metadata_version_8_spells_qos_as_integers_in_a_string(tmp_path, contracts, capsys):
    bag(tmp_path, [topic(profiles=[{"reliability": "best_effort"}])], storage="sqlite3", version=8)
    read = recording_model.read(tmp_path / "rec")
    assert read.version == 8 and read.topics[0].qos_profiles[0]["reliability"] == "BEST_EFFORT"
    assert read.topics[0].qos_profiles[0]["deadline_ns"] == -1 and read.topics[0].type_hash == STRING_HASH
    assert check("--bag", "rec", *contracts) == 1
    out = capsys.readouterr().out
    assert "[QOS_RELIABILITY_WEAKENED]" in out and "[QOS_INCOMPATIBLE]" in out


def test_a_changed_type_is_drift_of_the_contracts_publisher_and_breaks_its_subscriber(tmp_path, contracts, capsys):
    bag(tmp_path, [topic(type_name="std_msgs/msg/Int32", type_hash=OTHER_HASH)])
    assert check("--bag", "rec", *contracts) == 1
    out = capsys.readouterr().out
    assert "Interface drift of the recording rec against talker.interfaces.yaml: 1 change (1 breaking" in out
    assert "[TYPE_CHANGED]" in out and "std_msgs/msg/Int32" in out
    assert "[TYPE_MISMATCH]" in out and "subscription of /listener (listener.interfaces.yaml)" in out


def test_a_changed_type_hash_is_drift(tmp_path, contracts, capsys):
    bag(tmp_path, [topic(type_hash=OTHER_HASH)])
    assert check("--bag", "rec", *contracts) == 1
    out = capsys.readouterr().out
    assert "[TYPE_HASH_CHANGED]" in out and "[TYPE_HASH_MISMATCH]" in out


def test_a_type_hash_of_another_distribution_is_said_so(tmp_path, contracts, capsys):
    Path("talker.interfaces.yaml").write_text("ros_distribution: humble\n" + TALKER)
    bag(tmp_path, [topic(type_hash=OTHER_HASH)])
    assert check("--bag", "rec", "talker.interfaces.yaml") == 1
    out = capsys.readouterr().out
    assert "[TYPE_HASH_DISTRIBUTION_CHANGED]" in out and "between ROS 2 humble (the contract) and jazzy" in out


def test_the_projects_rule_levels_apply_to_a_recording_as_to_a_capture(tmp_path, contracts, capsys):
    bag(tmp_path, [topic(type_hash=OTHER_HASH), topic("/debug_image", "sensor_msgs/msg/Image", count=7)])
    assert check("--bag", "rec", *contracts, "--rule", "TYPE_HASH_*=note", "--rule", "RECORDED_TOPIC_UNDECLARED=off",
                 "--fail-on", "any") == 0
    out, err = capsys.readouterr()
    assert "[TYPE_HASH_CHANGED]" in out and "(NOTE, set by rules `TYPE_HASH_*`: in command line)" in out, out
    assert "[RECORDED_TOPIC_UNDECLARED]" not in out
    assert (out + err).count("1 finding turned off by the project's rules") == 1, out + err


def test_a_recording_without_type_hashes_compares_none(tmp_path, contracts, capsys):
    bag(tmp_path, [topic(type_hash="")], version=6)
    assert check("--bag", "rec", *contracts) == 0
    assert "TYPE_HASH" not in capsys.readouterr().out


def test_a_best_effort_publisher_breaks_a_reliable_subscriber_through_the_system_rules(tmp_path, contracts, capsys):
    bag(tmp_path, [topic(profiles=[{"reliability": "best_effort"}])])
    assert check("--bag", "rec", "listener.interfaces.yaml") == 1
    out = capsys.readouterr().out
    assert "System check of the recording rec against listener.interfaces.yaml" in out
    assert ("/chatter: publisher of (unknown node) (recording rec) -> subscription of "
            "/listener (listener.interfaces.yaml): BEST_EFFORT publisher and RELIABLE subscription") in out


def test_what_the_middleware_chose_for_a_system_default_is_not_drift(tmp_path, contracts, capsys):
    Path("talker.interfaces.yaml").write_text(TALKER.replace("qos: {history: KEEP_LAST, depth: 10, reliability: "
                                                             "RELIABLE, durability: VOLATILE}", "qos: system_default"))
    bag(tmp_path, [topic(profiles=[{"reliability": "reliable", "durability": "transient_local"}])])
    assert check("--bag", "rec", "talker.interfaces.yaml") == 0


def test_a_topic_no_contract_declares_is_reported_with_its_count(tmp_path, contracts, capsys):
    bag(tmp_path, [topic(), topic("/debug_image", "sensor_msgs/msg/Image", count=7)])
    assert check("--bag", "rec", *contracts) == 0  # RISKY: below system_fail_on (breaking)
    out = capsys.readouterr().out
    assert "[RECORDED_TOPIC_UNDECLARED]" in out
    assert "the recording holds /debug_image (sensor_msgs/msg/Image, 7 message(s)), which no contract's publisher" in out
    assert "/debug_image  sensor_msgs/msg/Image  7 messages" in out
    assert check("--bag", "rec", "--system-fail-on", "risky", *contracts) == 1


def test_a_declared_topic_with_more_publishers_than_declared_names_the_ones_declared(tmp_path, contracts, capsys):
    """Someone's node publishes /chatter too: the recorder found two publishers, one is declared."""
    bag(tmp_path, [topic(profiles=[{}, {}])])
    assert check("--bag", "rec", *contracts) == 0  # RISKY: below system_fail_on (breaking)
    out = capsys.readouterr().out
    assert "[RECORDED_TOPIC_EXTRA_PUBLISHER]" in out and "UNDECLARED" not in out
    assert ("the recorder found 2 publishers of /chatter (std_msgs/msg/String); the contracts declare 1: /talker "
            "(talker.interfaces.yaml). A node they do not know publishes it too") in out
    assert check("--bag", "rec", "--system-fail-on", "risky", *contracts) == 1
    capsys.readouterr()
    # a second node that declares it, or a pattern name (any number of nodes), accounts for it
    Path("relay.interfaces.yaml").write_text(TALKER.replace("/talker:", "/relay:"))
    assert check("--bag", "rec", "--system-fail-on", "risky", *contracts, "relay.interfaces.yaml") == 0
    Path("talker.interfaces.yaml").write_text(TALKER.replace("/talker:", "/talker_*:\n    unstable_name: one per robot arm"))
    bag(tmp_path, [topic(profiles=[{}, {}, {}])], name="three")
    assert check("--bag", "three", "--system-fail-on", "risky", *contracts) == 0, capsys.readouterr().out


def test_a_contract_topic_missing_from_the_recording_is_said_risky(tmp_path, contracts, capsys):
    bag(tmp_path, [topic("/other", count=1)])
    assert check("--bag", "rec", "--system-fail-on", "risky", "talker.interfaces.yaml") == 1
    out = capsys.readouterr().out
    assert "[CONTRACT_TOPIC_NOT_RECORDED]" in out
    assert ("/talker promises to publish /chatter (std_msgs/msg/String), which is not in the recording rec: it was "
            "not recorded (a recording of other topics), or nothing published it") in out


def test_a_promised_topic_recorded_without_a_message_is_silent(tmp_path, contracts, capsys):
    bag(tmp_path, [topic(count=0)])
    assert check("--bag", "rec", "talker.interfaces.yaml") == 0
    out = capsys.readouterr().out
    assert "[RECORDED_TOPIC_SILENT]" in out and "1 recorded topic, 0 messages: /chatter 0 messages" in out


def test_infrastructure_and_the_recorders_own_topics_are_left_out(tmp_path, contracts, capsys):
    bag(tmp_path, [topic(), topic("/rosout", "rcl_interfaces/msg/Log"), topic("/events/write_split",
                                                                              "rosbag2_interfaces/msg/WriteSplitEvent")])
    assert check("--bag", "rec", *contracts) == 0
    assert "UNDECLARED" not in capsys.readouterr().out


def test_an_accept_entry_accepts_drift_against_a_recording(tmp_path, contracts, capsys):
    Path("talker.interfaces.yaml").write_text(TALKER.replace("nodes:", "accept:\n  - {rule: TYPE_HASH_CHANGED, "
                                                             "name: /chatter, reason: rebuilt on the robot}\nnodes:"))
    bag(tmp_path, [topic(type_hash=OTHER_HASH)])
    assert check("--bag", "rec", "talker.interfaces.yaml") == 0
    assert "1 finding(s) accepted in the contract" in capsys.readouterr().out


def test_a_baseline_holds_todays_findings(tmp_path, contracts, capsys):
    bag(tmp_path, [topic(type_hash=OTHER_HASH)])
    assert check("--bag", "rec", "--write-baseline", "base.json", *contracts) == 0
    assert check("--bag", "rec", "--baseline", "base.json", *contracts) == 0


SYSTEM = f"""\
system_version: 1
launch: {{package: bringup, file: robot.launch.xml}}
options: {{system_fail_on: risky}}
external:
  publishers: {{/cmd_vel: teleop}}
processes:
  - {{package: demo, executable: talker, name: /talker, nodes: [/talker]}}
  - {{package: demo, executable: fibonacci, name: /fibonacci_server, nodes: [/fibonacci_server]}}
nodes:
{TALKER.split("nodes:" + chr(10), 1)[1]}\
  /fibonacci_server:
    publishers: []
    subscriptions: []
    service_servers: []
    service_clients: []
    action_servers:
      - {{name: /fibonacci, type: example_interfaces/action/Fibonacci}}
    action_clients: []
"""


def test_a_system_contract_knows_its_outside_publishers_and_its_actions_topics(tmp_path, contracts, capsys):
    Path("robot.system.yaml").write_text(SYSTEM)
    bag(tmp_path, [topic(), topic("/cmd_vel", "geometry_msgs/msg/Twist", count=9),
                   topic("/fibonacci/_action/status", "action_msgs/msg/GoalStatusArray", count=1),
                   topic("/fibonacci/_action/feedback", "example_interfaces/action/Fibonacci_FeedbackMessage"),
                   topic("/unknown", count=2)])
    # the recording's own result is judged by the strictest options of the contracts: system_fail_on risky
    assert check("--bag", "rec", "robot.system.yaml") == 1
    out = capsys.readouterr().out
    assert "robot.system.yaml: matches (1 publisher on recorded topics, 5 messages, in rec)" in out
    assert "/unknown" in out and "[RECORDED_TOPIC_UNDECLARED] 1 finding" in out
    assert "/cmd_vel (" not in out and "_action/status (" not in out


def test_a_system_contracts_system_fail_on_fails_on_a_missing_topic(tmp_path, contracts, capsys):
    Path("robot.system.yaml").write_text(SYSTEM)
    bag(tmp_path, [topic("/other")])
    assert check("--bag", "rec", "robot.system.yaml") == 1
    assert "[CONTRACT_TOPIC_NOT_RECORDED]" in capsys.readouterr().out


def test_a_split_recording_counts_every_file(tmp_path, contracts, capsys):
    rec = bag(tmp_path, [topic(count=3)])
    write_mcap(rec / "rec_1.mcap", [topic(count=4)])
    meta = yaml.safe_load((rec / "metadata.yaml").read_text())
    meta["rosbag2_bagfile_information"]["relative_file_paths"].append("rec_1.mcap")
    (rec / "metadata.yaml").write_text(yaml.safe_dump(meta, sort_keys=False))
    assert check("--bag", "rec", "-v", "talker.interfaces.yaml") == 0
    assert "matches (1 publisher on recorded topics, 7 messages: /talker /chatter 7 messages, in rec)" in \
        capsys.readouterr().out


def test_a_compressed_recording_is_read_from_its_metadata_and_says_so(tmp_path, contracts, capsys):
    rec = bag(tmp_path, [topic(count=3)])
    (rec / "rec_0.mcap").rename(rec / "rec_0.mcap.zstd")
    meta = yaml.safe_load((rec / "metadata.yaml").read_text())
    meta["rosbag2_bagfile_information"].update(compression_format="zstd", compression_mode="file",
                                               relative_file_paths=["rec_0.mcap.zstd"])
    (rec / "metadata.yaml").write_text(yaml.safe_dump(meta, sort_keys=False))
    assert recording_model.read(rec).notes == (
        "its files are compressed (zstd): topics, QoS and counts are metadata.yaml's, the files were not read",)
    assert check("--bag", "rec", *contracts) == 0
    assert "/chatter 3 messages" in capsys.readouterr().out


def test_infrastructure_topics_are_compared_when_asked(tmp_path, contracts, capsys):
    bag(tmp_path, [topic(), topic("/rosout", "rcl_interfaces/msg/Log")])
    assert check("--bag", "rec", "--include-ros-infra", "--system-fail-on", "risky", *contracts) == 1
    assert "the recording holds /rosout (rcl_interfaces/msg/Log" in capsys.readouterr().out


# ---------------------------------------------------------------------------- formats


@pytest.mark.parametrize("fmt", ["json", "markdown", "github", "sarif"])
def test_every_report_format(tmp_path, contracts, capsys, fmt):
    bag(tmp_path, [topic(profiles=[{"reliability": "best_effort"}]), topic("/debug", count=4)])
    assert check("--bag", "rec", "--format", fmt, *contracts) == 1
    out = capsys.readouterr().out
    if fmt == "json":
        items = json.loads(out)
        assert {item["rule"] for item in items} == {"QOS_RELIABILITY_WEAKENED", "QOS_INCOMPATIBLE",
                                                    "RECORDED_TOPIC_UNDECLARED"}
        assert {(item["name"], item["message_count"], item["recording"]) for item in items} == {
            ("/chatter", 5, "rec"), ("/debug", 4, "rec")}
    elif fmt == "markdown":
        assert "| `rec` | `/chatter (5 messages)`, `/debug (4 messages)` |" in out
        assert "`QOS_INCOMPATIBLE`" in out and "`talker.interfaces.yaml`" in out
    elif fmt == "github":
        assert "::error file=talker.interfaces.yaml,line=5,title=QOS_RELIABILITY_WEAKENED (BREAKING)::" in out
        assert "title=RECORDED_TOPIC_UNDECLARED (RISKY)::" in out
        assert "::notice file=rec,title=note::a recording shows topics" in out
    else:
        results = json.loads(out)["runs"][0]["results"]
        assert {r["ruleId"] for r in results} >= {"QOS_INCOMPATIBLE", "RECORDED_TOPIC_UNDECLARED"}


# ---------------------------------------------------------------------------- what cannot be read


def test_a_directory_without_metadata_names_what_to_do(tmp_path, contracts, capsys):
    (tmp_path / "cut").mkdir()
    write_mcap(tmp_path / "cut" / "cut_0.mcap", [topic()])
    assert check("--bag", "cut", *contracts) == 2
    assert capsys.readouterr().err.strip() == (
        "rmw-introspect: cut: a directory without metadata.yaml, so not a rosbag2 recording; it holds cut_0.mcap: "
        "give that file itself (--bag cut/cut_0.mcap), or write the metadata with `ros2 bag reindex cut`")


def test_an_unknown_storage_id_is_an_error(tmp_path, contracts, capsys):
    rec = bag(tmp_path, [topic()])
    meta = yaml.safe_load((rec / "metadata.yaml").read_text())
    meta["rosbag2_bagfile_information"]["storage_identifier"] = "leveldb"
    (rec / "metadata.yaml").write_text(yaml.safe_dump(meta))
    assert check("--bag", "rec", *contracts) == 2
    assert capsys.readouterr().err.strip() == (
        "rmw-introspect: rec/metadata.yaml: storage `leveldb` is not one this check reads (sqlite3, mcap); convert "
        "the recording (`ros2 bag convert` to sqlite3 or mcap) and check that")


def test_a_missing_storage_file_is_an_error(tmp_path, contracts, capsys):
    rec = bag(tmp_path, [topic()])
    (rec / "rec_0.mcap").unlink()
    assert check("--bag", "rec", *contracts) == 2
    assert capsys.readouterr().err.strip() == (
        "rmw-introspect: rec/rec_0.mcap: missing: rec/metadata.yaml lists it among the recording's files; copy the "
        "whole bag directory (or fix `relative_file_paths`)")


def test_a_truncated_mcap_file_is_an_error(tmp_path, contracts, capsys):
    rec = bag(tmp_path, [topic(count=50)])
    data = (rec / "rec_0.mcap").read_bytes()
    (rec / "rec_0.mcap").write_bytes(data[: len(data) // 2])
    assert check("--bag", "rec", *contracts) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("rmw-introspect: rec/rec_0.mcap: not a readable MCAP file (")
    assert err.endswith("the file is corrupt or truncated; if the recording was cut short, `ros2 bag reindex` (or "
                        "`mcap recover`) may rebuild it; otherwise record again")


def test_a_corrupt_db3_file_is_an_error(tmp_path, contracts, capsys):
    rec = bag(tmp_path, [topic()], storage="sqlite3")
    (rec / "rec_0.db3").write_bytes(b"not a database at all" * 10)
    assert check("--bag", "rec", *contracts) == 2
    assert capsys.readouterr().err.strip() == (
        "rmw-introspect: rec/rec_0.db3: not an SQLite database (rosbag2's sqlite3 storage): the file is corrupt or "
        "of another format; if the recording was cut short, `ros2 bag reindex` may rebuild it; otherwise record again")


def test_a_truncated_db3_file_is_an_error(tmp_path, contracts, capsys):
    rec = bag(tmp_path, [topic(count=400)], storage="sqlite3")
    data = (rec / "rec_0.db3").read_bytes()
    (rec / "rec_0.db3").write_bytes(data[: len(data) // 3])
    assert check("--bag", "rec", *contracts) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("rmw-introspect: rec/rec_0.db3: the SQLite database cannot be read (")
    assert "the file is corrupt or truncated" in err


@pytest.mark.parametrize("suffix", [".mcap", ".db3"])
def test_every_cut_or_damaged_storage_file_is_an_error_or_a_recording(tmp_path, monkeypatch, suffix):
    """Whatever bytes a damaged file holds, reading it ends in a RecordingError or a recording,
    never another exception (a traceback)."""
    import random

    monkeypatch.chdir(tmp_path)
    (write_mcap if suffix == ".mcap" else write_db3)(tmp_path / f"good{suffix}", [topic(count=30),
                                                                                  topic("/debug", count=30)])
    data = (tmp_path / f"good{suffix}").read_bytes()
    rng = random.Random(52)
    damaged = [data[:n] for n in (0, 3, 8, 9, 40, len(data) // 3, len(data) - 30, len(data) - 1)]
    for _ in range(40):
        flipped = bytearray(data)
        for _ in range(rng.randint(1, 8)):
            flipped[rng.randrange(len(flipped))] = rng.randrange(256)
        damaged.append(bytes(flipped))
    for i, payload in enumerate(damaged):
        (tmp_path / f"bad{suffix}").write_bytes(payload)
        try:
            recording_model.read(f"bad{suffix}")
        except recording_model.RecordingError as exc:
            assert str(exc).startswith(f"bad{suffix}: "), (i, exc)


@pytest.mark.parametrize(("text", "said"), [
    ("a: [1, 2\n", "rec/metadata.yaml: the metadata (`ros2 bag reindex rec` writes it anew) cannot be read (line 2): "
                   "YAML syntax error"),
    ("- just a list\n", "rec/metadata.yaml: not rosbag2 metadata (no `rosbag2_bagfile_information:`)"),
    ("rosbag2_bagfile_information: {version: nine}\n", "rec/metadata.yaml: no metadata `version:` (an integer)"),
    ("rosbag2_bagfile_information:\n  version: 9\n  storage_identifier: mcap\n  relative_file_paths: []\n"
     "  topics_with_message_count: [{topic_metadata: {name: /a, type: t, offered_qos_profiles: [{reliability: 7}]}}]\n",
     "rec/metadata.yaml: topic /a: QoS reliability 7 is not one of rmw's values"),
    ("a: &a [x, x, x, x, x, x, x, x, x, x]\nb: &b [*a, *a, *a, *a, *a, *a, *a, *a, *a, *a]\n"
     "c: &c [*b, *b, *b, *b, *b, *b, *b, *b, *b, *b]\nd: &d [*c, *c, *c, *c, *c, *c, *c, *c, *c, *c]\n"
     "e: &e [*d, *d, *d, *d, *d, *d, *d, *d, *d, *d]\nf: &f [*e, *e, *e, *e, *e, *e, *e, *e, *e, *e]\n"
     "g: [*f, *f, *f, *f, *f, *f, *f, *f, *f, *f]\n", "an alias bomb?"),
])
def test_a_broken_metadata_file_is_an_error(tmp_path, monkeypatch, text, said):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "rec").mkdir()
    (tmp_path / "rec" / "metadata.yaml").write_text(text)
    with pytest.raises(recording_model.RecordingError) as caught:
        recording_model.read("rec")
    assert said in str(caught.value)


def test_a_missing_path_is_an_error(tmp_path, contracts, capsys):
    assert check("--bag", "nowhere", *contracts) == 2
    assert capsys.readouterr().err.strip() == (
        "rmw-introspect: nowhere: no such file or directory; give a rosbag2 bag directory (with metadata.yaml) or an "
        ".mcap file")


def test_nothing_runs_and_nothing_is_written_with_a_recording(tmp_path, contracts, capsys, monkeypatch):
    monkeypatch.delenv("CI", raising=False)  # (in CI, `check --update` is refused first, for being in CI)
    bag(tmp_path, [topic()])
    assert check("--bag", "rec", "--update", *contracts) == 2
    assert "--bag checks a recording and writes nothing: leave out --update" in capsys.readouterr().err
    assert check("--bag", "rec", "--script", "node.py", *contracts) == 2
    assert "nothing runs, so target and launch options" in capsys.readouterr().err
    assert check("--bag", "rec", "--shard", "1/2", *contracts) == 2
    assert "a recording is checked against every contract at once" in capsys.readouterr().err


# ---------------------------------------------------------------------------- offered QoS as rosbag2 writes it


@pytest.mark.parametrize(("profile", "expected"), [
    ({"reliability": "2", "durability": "transient_local", "liveliness": "manual_by_node", "depth": 7,
      "deadline": None, "lifespan": 5, "liveliness_lease_duration": {"sec": 2147483647, "nsec": 4294967295},
      "avoid_ros_namespace_conventions": True},
     {"reliability": "BEST_EFFORT", "durability": "TRANSIENT_LOCAL", "liveliness": "UNKNOWN", "depth": 7,
      "deadline_ns": 0, "lifespan_ns": 5, "liveliness_lease_duration_ns": -1, "avoid_ros_namespace_conventions": True}),
    ({"history": 1, "deadline": {"sec": 1, "nsec": 5}, "depth": -1},
     {"history": "KEEP_LAST", "deadline_ns": 1_000_000_005}),
])
def test_an_offered_profile_is_read_in_every_spelling_rosbag2_wrote(profile, expected):
    assert recording_model.parse_qos_profile(profile, "rec/metadata.yaml") == expected


@pytest.mark.parametrize(("value", "said"), [
    ("not a profile", "an offered QoS profile is not a mapping"),
    ({"reliability": True}, "QoS reliability True is not a policy value"),
    ({"reliability": 9}, "QoS reliability 9 is not one of rmw's values"),
    ({"durability": "sometimes"}, "QoS durability 'sometimes' is not one of rmw's values"),
    ({"deadline": "soon"}, "QoS deadline 'soon' is not a duration"),
])
def test_an_offered_profile_that_is_no_qos_names_the_file_and_the_policy(value, said):
    with pytest.raises(recording_model.RecordingError, match=re.escape(f"rec/metadata.yaml: {said}")):
        recording_model.parse_qos_profile(value, "rec/metadata.yaml")


def test_offered_profiles_as_a_yaml_string_a_list_or_nothing():
    assert recording_model.parse_qos_profiles(None, "x") == () == recording_model.parse_qos_profiles("", "x")
    assert recording_model.parse_qos_profiles("# nothing\n", "x") == ()
    assert recording_model.parse_qos_profiles("- {reliability: 1}\n", "x") == ({"reliability": "RELIABLE"},)
    with pytest.raises(recording_model.RecordingError, match="x: offered_qos_profiles is not a list"):
        recording_model.parse_qos_profiles("reliability: 1\n", "x")


def test_a_contract_that_cannot_be_read_is_an_error_of_its_own_and_the_others_are_checked(tmp_path, contracts, capsys):
    bag(tmp_path, [topic(count=5)])
    Path("broken.interfaces.yaml").write_text("contract_version: 1\nnodez: {}\n")
    assert check("--bag", "rec", "broken.interfaces.yaml", *contracts) == 2
    out, err = capsys.readouterr()
    assert "broken.interfaces.yaml" in err and "'nodes' is required" in err, err
    assert "talker.interfaces.yaml: matches" in out
