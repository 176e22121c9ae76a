"""Untrusted input, fuzzed: contracts, launch files, the target's parameters, the capture-file reader, git trees
for the gate, unstable_names patterns, stand_ins: and baselines.

A fixed seed and a bounded number of cases (``RMWI_FUZZ_CASES``, default 150 per input kind, a
fraction of that for git trees, stand-ins and baselines;
`make fuzz` runs many more): no traceback (only the documented errors), no hang (each case
under a few seconds), and the command line's exit status is 0, 1 or 2.
"""

from __future__ import annotations

import contextlib
import copy
import io
import json
import os
import random
import signal
import time
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest

from pytest_rmw_introspect import cli
from pytest_rmw_introspect.errors import CaptureFormatError, ContractError, LaunchError, TargetConfigError
from pytest_rmw_introspect.launch import python_file as launch_python
from pytest_rmw_introspect.launch import reader as launch_reader
from pytest_rmw_introspect.model.capture import Capture
from pytest_rmw_introspect.model.contract import loads, normalize_nodes, render
from pytest_rmw_introspect.model.unstable_names import contract_keys
from pytest_rmw_introspect.run.target import TargetSpec, ros_arguments

CASES = int(os.environ.get("RMWI_FUZZ_CASES", "150"))
SEED = int(os.environ.get("RMWI_FUZZ_SEED", "20261123"))
CASE_SECONDS = 5.0

CONTRACT = """\
# a contract
contract_version: 1
target:
  script: talker.py
  parameters: {rate: 10.0, names: [a, b], nested: {x: 1}}
options:
  fail_on: risky
  ignore_qos: [depth]
nodes:
  /talker:
    publishers:
      - name: /chatter
        type: std_msgs/msg/String
        type_hash: RIHS01_df668c740482bbd48fb39d76a70dfd4bd59db1288021743503259e948f6b1a18
        qos: {history: KEEP_LAST, depth: 10, reliability: RELIABLE, durability: VOLATILE}
    subscriptions:
      - name: /cmd
        type: std_msgs/msg/String
        qos: sensor_data
    service_servers:
      - {name: /talker/reset, type: std_srvs/srv/Empty}
    action_servers:
      - name: /fib
        type: test_msgs/action/Fibonacci
        type_hash: {send_goal: RIHS01_0000000000000000000000000000000000000000000000000000000000000000}
    parameters:
      - name: rate
        type: double
        default_value: 10.0
        read_only: true
        floating_point_range: {from_value: 0.0, to_value: .inf, step: 0.0}
      - {name: ids, type: integer_array, default_value: [1, 2], integer_range: {from_value: 0, to_value: 9, step: 1}}
  /managed:
    lifecycle: active
    parameters: [{name: topic, type: string, default_value: status, declared_in: configure}]
"""


class _Expired(AssertionError):
    """Raised by the alarm wherever the code under test is (possibly thousands of frames deep)."""


@contextlib.contextmanager
def deadline(seconds: float, what: str) -> Iterator[None]:
    def expired(signum, frame):
        raise _Expired()

    # pytest-timeout may have an alarm running for the whole test: put it back afterwards
    outer_remaining, _ = signal.getitimer(signal.ITIMER_REAL)
    started = time.monotonic()
    previous = signal.signal(signal.SIGALRM, expired)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    hung = False
    try:
        yield
    except _Expired as exc:
        exc.__traceback__ = None
        hung = True
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)
        if outer_remaining > 0:
            signal.setitimer(signal.ITIMER_REAL, max(0.001, outer_remaining - (time.monotonic() - started)))
    if hung:
        # raised here, without the alarm's traceback: an alarm inside a deep recursion (the
        # pure-Python YAML composer on a busy machine) left frames whose report crashed pytest
        # under xdist (INTERNALERROR, the whole session ended)
        raise AssertionError(f"hang: {what} took more than {seconds} s") from None


# ---------------------------------------------------------------------------- mutations


def _flip(rng: random.Random, text: str) -> str:
    i = rng.randrange(len(text))
    return text[:i] + chr(rng.randrange(0, 0x2FF)) + text[i + 1:]


def _control(rng: random.Random, text: str) -> str:
    i = rng.randrange(len(text))
    return text[:i] + chr(rng.choice([0, 1, 7, 8, 0x1B, 0x7F, 0x85, 0xFEFF])) + text[i:]


def _cut(rng: random.Random, text: str) -> str:
    i, j = sorted(rng.randrange(len(text)) for _ in range(2))
    return text[:i] + text[j:]


def _repeat_line(rng: random.Random, text: str) -> str:
    lines = text.splitlines(keepends=True)
    i = rng.randrange(len(lines))
    return "".join(lines[:i] + [lines[i]] * rng.randint(2, 4) + lines[i:])


def _odd_key(rng: random.Random, text: str) -> str:
    key = rng.choice(["1", "null", "true", "~", "[a]", "{b: c}", "1.5", "0x10", "'/ok'", "!!binary aGk="])
    lines = text.splitlines(keepends=True)
    i = rng.randrange(len(lines))
    indent = len(lines[i]) - len(lines[i].lstrip())
    return "".join(lines[:i] + [" " * indent + f"{key}: x\n"] + lines[i:])


def _odd_value(rng: random.Random, text: str) -> str:
    value = rng.choice(["null", "[]", "{}", "-1", "1e309", ".nan", "'" + "x" * 2000 + "'", "!!python/none ''",
                        "*nope", "&a [*a]", "2026-11-23", "0b101", "[[[[[[1]]]]]]"])
    lines = [line for line in text.splitlines(keepends=True)]
    candidates = [i for i, line in enumerate(lines) if ": " in line]
    i = rng.choice(candidates)
    head = lines[i].split(": ", 1)[0]
    lines[i] = f"{head}: {value}\n"
    return "".join(lines)


MUTATORS: list[Callable[[random.Random, str], str]] = [_flip, _control, _cut, _repeat_line, _odd_key, _odd_value]


def mutated_contracts(count: int) -> Iterator[str]:
    rng = random.Random(SEED)
    for _ in range(count):
        text = CONTRACT
        for _ in range(rng.randint(1, 3)):
            text = rng.choice(MUTATORS)(rng, text)
        yield text


# ---------------------------------------------------------------------------- contracts


def _load(text: str) -> None:
    with deadline(CASE_SECONDS, "loading a contract"):
        try:
            loads(text, path="fuzzed.interfaces.yaml")
        except ContractError as exc:
            assert "fuzzed.interfaces.yaml" in str(exc)
            assert len(exc.reason) < 600, exc.reason  # values are cut in messages


def test_mutated_contracts_load_or_fail_with_a_contract_error():
    for text in mutated_contracts(CASES):
        _load(text)


def test_fuzzed_unstable_names_patterns_key_nodes_quickly_or_are_refused():
    """Issue 50, N17 and N18: random `unstable_names` patterns (many `*`, catch-alls) against long
    names: each is refused as matching every node, or keys the nodes within the case deadline."""
    rng = random.Random(SEED)
    node = normalize_nodes({"/n": {}})["/n"]
    names = ["/" + "a" * 60, "/" + "a_" * 40 + "b", "/ns/" + "a" * 59 + "b", "/a/b/c"]
    for case in range(CASES):
        pattern = "/" + "/".join("".join(rng.choice("aab_*") for _ in range(rng.randint(1, 30)))
                                 for _ in range(rng.randint(1, 3))) + "*"
        if case == 0:
            pattern = "/*a*a*a*a*a*a*a*a*b"  # 68 s a match as a regular expression
        text = f"contract_version: 1\nunstable_names:\n  - {{pattern: '{pattern}', reason: r}}\nnodes: {{}}\n"
        with deadline(CASE_SECONDS, f"keying nodes by the pattern {pattern}"):
            try:
                contract = loads(text, path="fuzzed.interfaces.yaml")
            except ContractError as exc:
                assert pattern.rpartition("/")[2].strip("*") == "", pattern  # refused: a catch-all only
                assert "matches every node name in its namespace" in exc.reason
                continue
            contract_keys([(name, node, None) for name in names], contract.name_rules())


def _bomb(levels: int = 9, width: int = 9) -> str:
    lines = ["a0: &a0 [x, x, x, x, x, x, x, x, x]"]
    for level in range(1, levels):
        lines.append(f"a{level}: &a{level} [" + ", ".join([f"*a{level - 1}"] * width) + "]")
    return "\n".join(lines) + "\n"


@pytest.mark.parametrize(("text", "reason"), [
    ("contract_version: 1\nnodes:\n  /t:\n    publishers: \x07\n", "control characters"),
    ("contract_version: 1\nnodes:\n  1: {}\n", "mapping keys must be strings, got '1'"),
    ("contract_version: 1\nnodes:\n  null: {}\n", "mapping keys must be strings, got 'null'"),
    ("contract_version: 1\nnodes:\n  true: {}\n", "mapping keys must be strings, got 'true'"),
    ("contract_version: 1\nnodes:\n  ? [a, b]\n  : {}\n", "mapping keys must be strings, got a list or mapping"),
    ("contract_version: 1\nnodes: " + "[" * 2000 + "]" * 2000 + "\n", "nested more than 64 levels deep"),
    ("contract_version: 1\nnodes: " + "{a: " * 200 + "1" + "}" * 200 + "\n", "nested more than 64 levels"),
    (_bomb() + "contract_version: 1\nnodes: {}\n", "alias bomb"),
    ("contract_version: 1\ntarget:\n  script: a.py\n  parameters:\n"
     + "".join(f"    {line}\n" for line in _bomb().splitlines()) + "nodes: {}\n", "alias bomb"),
    ("contract_version: 1\nnodes:\n", "write `nodes: {}` for a contract without nodes"),
    ("contract_version: 1\nnodes:\n  /t:\n    publishers:\n      - name: /x\n        type: '" + "y" * 900 + "'\n",
     "..."),
])
def test_hostile_contracts_are_refused_quickly_with_a_reason(text, reason):
    started = time.monotonic()
    with deadline(CASE_SECONDS, "a hostile contract"), pytest.raises(ContractError) as info:
        loads(text, path="hostile.interfaces.yaml")
    assert time.monotonic() - started < CASE_SECONDS
    assert reason in info.value.reason, info.value.reason
    assert len(str(info.value)) < 400, str(info.value)


DEEP_DOCUMENTS = {
    # libyaml (PyYAML >= 6.0.4's wheels) refuses flow nesting past 1000 levels with its own
    # message; the pure-Python composer runs out of recursion
    "flow lists": "contract_version: 1\nnodes: " + "[" * 2000 + "]" * 2000 + "\n",
    "unclosed flow lists": "contract_version: 1\nnodes: " + "[" * 5000 + "\n",
    "flow mappings": "contract_version: 1\nnodes: " + "{a: " * 1200 + "1" + "}" * 1200 + "\n",
    "block mappings": "contract_version: 1\nnodes:\n" + "".join("  " * (i + 1) + f"k{i}:\n" for i in range(1200)) + "  " * 1201 + "x\n",
    "just past the limit": "contract_version: 1\nnodes: " + "[" * 66 + "]" * 66 + "\n",
}


def _yaml_loaders() -> list:
    import yaml

    loaders = [pytest.param(yaml.SafeLoader, id="pure-Python")]
    c_loader = getattr(yaml, "CSafeLoader", None)
    loaders.append(pytest.param(c_loader, id="libyaml", marks=pytest.mark.skipif(
        c_loader is None, reason="this PyYAML was built without libyaml")))
    return loaders


@pytest.mark.parametrize("loader", _yaml_loaders())
@pytest.mark.parametrize("text", DEEP_DOCUMENTS.values(), ids=DEEP_DOCUMENTS.keys())
def test_deep_nesting_is_refused_with_the_projects_own_message_by_either_parser(text, loader, monkeypatch):
    from pytest_rmw_introspect.model import untrusted

    monkeypatch.setattr(untrusted, "LOADER", loader)
    with deadline(CASE_SECONDS, "a deeply nested contract"), pytest.raises(ContractError) as info:
        loads(text, path="deep.interfaces.yaml")
    assert info.value.reason.endswith("nested more than 64 levels deep"), info.value.reason
    assert str(info.value).startswith("invalid contract deep.interfaces.yaml:"), str(info.value)
    assert info.value.line is not None and info.value.line >= 2


def test_a_fifo_a_directory_and_a_huge_file_are_refused(tmp_path, monkeypatch):
    from pytest_rmw_introspect.model import contract, untrusted

    fifo = tmp_path / "pipe.interfaces.yaml"
    os.mkfifo(fifo)
    with deadline(CASE_SECONDS, "reading a FIFO"), pytest.raises(ContractError, match="not a regular file"):
        contract.load(fifo)
    with pytest.raises(ContractError, match="a directory"):
        contract.load(tmp_path)
    big = tmp_path / "big.interfaces.yaml"
    big.write_text("contract_version: 1\nnodes: {}\n" + "#" * 2000 + "\n")
    monkeypatch.setattr(untrusted, "MAX_FILE_BYTES", 1000)
    with pytest.raises(ContractError, match="more than the"):
        contract.load(big)


@pytest.mark.parametrize("argv", [
    ["diff", "pipe.yaml", "pipe.yaml"], ["diff", "good.interfaces.yaml", "pipe.yaml"],
    ["compat", "good.interfaces.yaml", "pipe.yaml"], ["graph", "pipe.yaml"], ["check", "pipe.yaml"],
    ["check", "--update", "pipe.yaml"], ["validate", "pipe.yaml"],
], ids=" ".join)
def test_a_fifo_given_as_contract_is_never_opened_for_reading(tmp_path, monkeypatch, capsys, argv):
    """Telling a node contract from a system contract reads the first bytes of a file: of a
    regular file only (a FIFO would block until someone writes to it)."""
    monkeypatch.chdir(tmp_path)
    monkeypatch.delenv("CI", raising=False)
    Path("good.interfaces.yaml").write_text(CONTRACT)
    os.mkfifo("pipe.yaml")
    with deadline(CASE_SECONDS, " ".join(argv)):
        status = cli.main(argv)
    err = capsys.readouterr().err
    assert status == 2, err
    assert "pipe.yaml: it is a FIFO (named pipe), not a regular file; give the path of a file" in err, err


def test_a_fifo_or_a_directory_given_as_launch_file_says_what_it_is(tmp_path, monkeypatch):
    from pytest_rmw_introspect.errors import LaunchError
    from pytest_rmw_introspect.launch import reader as launch_reader

    monkeypatch.chdir(tmp_path)  # paths in messages are shown relative to it
    os.mkfifo(tmp_path / "pipe.launch.xml")
    (tmp_path / "dir.launch.xml").mkdir()
    include = tmp_path / "main.launch.xml"
    include.write_text('<launch>\n  <include file="pipe.launch.xml"/>\n</launch>\n')
    for path, error in [
        (tmp_path / "pipe.launch.xml", "launch file pipe.launch.xml is a FIFO (named pipe), not a regular file"),
        (tmp_path / "dir.launch.xml", "launch file dir.launch.xml is a directory, not a file"),
        (include, "main.launch.xml:2: launch file pipe.launch.xml is a FIFO (named pipe), not a regular file"),
    ]:
        with deadline(CASE_SECONDS, f"reading {path.name}"), pytest.raises(LaunchError) as info:
            launch_reader.read(path)
        assert str(info.value) == error


# ---------------------------------------------------------------------------- the command line


def test_diff_and_compat_of_mutated_contracts_exit_0_1_or_2(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    Path("good.interfaces.yaml").write_text(CONTRACT)
    for n, text in enumerate(mutated_contracts(max(10, CASES // 5))):
        Path("fuzzed.interfaces.yaml").write_text(text, encoding="utf-8", errors="surrogatepass")
        for argv in (["diff", "good.interfaces.yaml", "fuzzed.interfaces.yaml"],
                     ["compat", "good.interfaces.yaml", "fuzzed.interfaces.yaml"],
                     ["validate", "fuzzed.interfaces.yaml"]):
            err = io.StringIO()
            with deadline(CASE_SECONDS, " ".join(argv)), contextlib.redirect_stderr(err), \
                    contextlib.redirect_stdout(io.StringIO()):
                status = cli.main(argv)
            assert status in (0, 1, 2), (n, argv, status)
            assert "Traceback" not in err.getvalue()


# ---------------------------------------------------------------------------- target parameters


def _random_value(rng: random.Random, depth: int = 0):
    choice = rng.randrange(9 if depth < 3 else 6)
    if choice == 0:
        return rng.choice([True, False, None])
    if choice == 1:
        return rng.choice([0, -1, 2**63, 1e309, float("nan"), 3.5])
    if choice == 2:
        return "".join(chr(rng.randrange(0, 0x500)) for _ in range(rng.randrange(6)))
    if choice == 3:
        return rng.choice(["true", "1", "", ":=", "a: b", "[1, 2]", "'", "\n"])
    if choice == 4:
        return b"bytes"
    if choice == 5:
        return object()
    if choice in (6, 7):
        return [_random_value(rng, depth + 1) for _ in range(rng.randrange(4))]
    return {rng.choice(["a", "b.c", "", 1, None]): _random_value(rng, depth + 1) for _ in range(rng.randrange(3))}


def test_fuzzed_parameters_are_accepted_or_refused_with_a_target_config_error():
    rng = random.Random(SEED)
    for _ in range(CASES):
        params = {rng.choice(["rate", "x.y", "", "n"]): _random_value(rng) for _ in range(rng.randrange(1, 4))}
        with deadline(CASE_SECONDS, "target parameters"):
            try:
                ros_arguments(TargetSpec.from_mapping({"script": "a.py", "parameters": params}))
            except TargetConfigError as exc:
                assert "parameter" in str(exc), exc


# ---------------------------------------------------------------------------- the capture-file reader

CAPTURE = {
    "format": "rmw_introspect_capture", "format_version": 1, "rmw_implementation": "rmw_introspect_cpp",
    "pid": 1, "argv": ["x"], "state": "settled", "settle_ms": 10, "time_to_settle_ms": 1.0, "elapsed_ms": 1.0,
    "format_minor": 1,
    "probe": {"state": "done", "parameters": True, "lifecycle": "active", "answer_timeout_ms": 5000, "requests": 5,
              "unanswered": 0},
    "nodes": [{"id": 1, "seq": 1, "name": "t", "namespace": "/", "fqn": "/t", "enclave": "/", "destroyed": False,
               "parameters": [
                   {"name": "rate", "type": "double", "value": 1.5, "read_only": False, "dynamic_typing": False,
                    "description": "Hz", "additional_constraints": "", "integer_range": None,
                    "floating_point_range": {"from_value": 0.0, "to_value": "inf", "step": 0.0}, "declared_in": None},
                   {"name": "ids", "type": "integer_array", "value": [1, 2], "read_only": True,
                    "dynamic_typing": False, "description": "", "additional_constraints": "",
                    "integer_range": {"from_value": 0, "to_value": 9, "step": 1}, "floating_point_range": None,
                    "declared_in": "configure"}],
               "parameters_error": None,
               "lifecycle": {"target": "active", "initial_state": "unconfigured", "state": "active",
                             "transitions": [{"id": 1, "label": "configure", "result": "success", "success": True}],
                             "error": None}}],
    "endpoints": [
        {"seq": 2, "kind": "publisher", "node_id": 1, "node": "/t", "name": "/c", "type": "std_msgs/msg/String",
         "type_hash": None, "typesupport": "rosidl_typesupport_c",
         "qos": {"history": "KEEP_LAST", "depth": 7, "reliability": "RELIABLE", "durability": "VOLATILE",
                 "liveliness": "SYSTEM_DEFAULT", "deadline_ns": 0, "lifespan_ns": 0,
                 "liveliness_lease_duration_ns": 0, "avoid_ros_namespace_conventions": False},
         "destroyed": False, "created_in": "configure"},
        {"seq": 3, "kind": "service", "node_id": 1, "node": "/t", "name": "/f/_action/send_goal",
         "type": "test_msgs/action/Fibonacci_SendGoal", "type_hash": None, "qos": {}, "destroyed": False},
    ],
    "time": {"horizon_ms": 10000, "virtual_elapsed_ms": 5.0, "real_elapsed_ms": 1.0, "jumps": 2},
}


def _paths(value, prefix=()):
    yield prefix
    if isinstance(value, dict):
        for k, v in value.items():
            yield from _paths(v, prefix + (k,))
    elif isinstance(value, list):
        for i, v in enumerate(value):
            yield from _paths(v, prefix + (i,))


def test_mutated_capture_documents_parse_or_fail_with_a_capture_format_error():
    rng = random.Random(SEED)
    paths = [p for p in _paths(CAPTURE) if p]
    for _ in range(CASES):
        doc = copy.deepcopy(CAPTURE)
        for _ in range(rng.randint(1, 3)):
            path = rng.choice(paths)
            parent = doc
            try:
                for part in path[:-1]:
                    parent = parent[part]
                if rng.random() < 0.3 and isinstance(parent, dict):
                    parent.pop(path[-1], None)
                else:
                    parent[path[-1]] = _random_value(rng)
            except (KeyError, IndexError, TypeError):
                continue
        with deadline(CASE_SECONDS, "a capture document"):
            try:
                capture = Capture.from_dict(json.loads(json.dumps(doc, default=str)))
            except CaptureFormatError:
                continue
            capture.summary()
            capture.notes()
            render(capture.to_contract_nodes())


# ---------------------------------------------------------------------------- launch files

LAUNCH_XML = """\
<launch>
  <arg name="ns" default="robot" description="namespace"/>
  <arg name="lidar" default="true"><choice value="true"/><choice value="false"/></arg>
  <let name="rate" value="$(var ns)_5.5"/>
  <set_env name="COLOR" value="$(optenv COLOR red)"/>
  <group scoped="true">
    <push_ros_namespace namespace="$(var ns)"/>
    <node pkg="demo" exec="talker" name="talker" args="--a 'b c'" if="$(var lidar)">
      <param name="rate" value="$(var rate)"/>
      <param name="list" value="[1, 2, 3]"/>
      <param name="outer"><param name="inner" value="x" value_sep=","/></param>
      <remap from="chatter" to="$(var ns)/chat"/>
      <env name="K" value="$(anon k)"/>
    </node>
  </group>
  <include file="$(dirname)/inner.launch.xml"><arg name="who" value="$(var ns)"/></include>
  <node pkg="demo" exec="listener" unless="false" ros_args="--log-level warn"/>
</launch>
"""
LAUNCH_YAML = """\
launch:
- arg: {name: ns, default: robot}
- let: {name: rate, value: "$(var ns)_5.5"}
- group:
    scoped: true
    children:
    - push_ros_namespace: {namespace: "$(var ns)"}
    - node:
        pkg: demo
        exec: talker
        name: talker
        param:
        - {name: rate, value: "$(var rate)"}
        - {name: list, value: [1, 2, 3]}
        remap:
        - {from: chatter, to: "$(var ns)/chat"}
- include:
    file: "$(dirname)/inner.launch.yaml"
    arg:
    - {name: who, value: "$(var ns)"}
- node: {pkg: demo, exec: listener, if: "true"}
"""
LAUNCH_INNER = {
    "xml": '<launch><arg name="who" default="x"/><node pkg="demo" exec="inner" name="$(var who)_inner"/></launch>\n',
    "yaml": "launch:\n- arg: {name: who, default: x}\n- node: {pkg: demo, exec: inner, name: \"$(var who)_inner\"}\n",
}


_HOSTILE_TEXTS = ["", "$(", "$(var", "$(var nope)", "$(eval 1)", "$(env NOPE)", "$(find-pkg-share nope)",
                  "$(var ns)$(var ns)", "'", "&amp;a [*a]", "[[[[1]]]]", "true", "2", "x" * 3000, "$(dirname)/..",
                  "$(anon $(var ns))", "/", "fuzzed.launch.xml", "$(filename)"]


def _xml_attribute(rng: random.Random, text: str) -> str:
    """An attribute's value replaced by a hostile one."""
    starts = [i for i in range(len(text)) if text.startswith('="', i)]
    i = rng.choice(starts) + 2
    j = text.index('"', i)
    return text[:i] + rng.choice(_HOSTILE_TEXTS).replace('"', "&quot;") + text[j:]


def _xml_element(rng: random.Random, text: str) -> str:
    """An element (or a stray end tag) inserted at the start of a line."""
    element = rng.choice(["<group>", "</group>", "<x/>", "<node/>", '<include file="fuzzed.launch.xml"/>',
                          '<include file="inner.launch.xml"/>', "<let/>", '<arg name="ns"/>', "<![CDATA[x]]>",
                          "<!DOCTYPE l [<!ENTITY a 'aaaa'>]>", "&a;", "<?pi x?>", "<node_container/>"])
    lines = text.splitlines(keepends=True)
    i = rng.randrange(len(lines))
    return "".join(lines[:i] + [element + "\n"] + lines[i:])


XML_MUTATORS: list[Callable[[random.Random, str], str]] = [_flip, _control, _cut, _repeat_line, _xml_attribute,
                                                           _xml_element]


def _read_launch(path: Path) -> None:
    """Read a launch file: a result, or a LaunchError that names the file in a message of bounded size."""
    with deadline(CASE_SECONDS, f"reading {path.name}"):
        try:
            result = launch_reader.read(path)
        except LaunchError as exc:
            assert path.name in str(exc) or "inner.launch" in str(exc), str(exc)
            assert len(str(exc)) < 1500, str(exc)[:3000]
            return
    for node in result.nodes:  # what a capture does with the result next
        node.ros_argument_list(lambda parameter: path)


@pytest.mark.parametrize("kind", ["xml", "yaml"])
def test_mutated_launch_files_are_read_or_refused_with_a_launch_error(tmp_path, kind):
    base = LAUNCH_XML if kind == "xml" else LAUNCH_YAML
    mutators = XML_MUTATORS if kind == "xml" else MUTATORS
    (tmp_path / f"inner.launch.{kind}").write_text(LAUNCH_INNER[kind], encoding="utf-8")
    path = tmp_path / f"fuzzed.launch.{kind}"
    rng = random.Random(SEED)
    for _ in range(CASES):
        text = base
        for _ in range(rng.randint(1, 3)):
            text = rng.choice(mutators)(rng, text)
        path.write_text(text, encoding="utf-8", errors="surrogatepass")
        _read_launch(path)


def _python_launch_files_readable() -> bool:
    try:
        launch_python.modules()
    except ImportError:
        return False
    return True


LAUNCH_PY = """\
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node


def generate_launch_description():
    return LaunchDescription([
        DeclareLaunchArgument("ns", default_value="robot"),
        Node(package="demo", executable="talker", name="talker", namespace=LaunchConfiguration("ns"),
             parameters=[{"rate": 5.5}], remappings=[("chatter", "chat")]),
    ])
"""


def test_mutated_python_launch_files_are_read_or_refused_with_a_launch_error(tmp_path):
    """Python launch files are read through launch_ros where it is importable; elsewhere every one
    is the same LaunchError (launch_ros is missing), which is checked too."""
    path = tmp_path / "fuzzed.launch.py"
    rng = random.Random(SEED)
    cases = CASES if _python_launch_files_readable() else 3
    for _ in range(cases):
        text = LAUNCH_PY
        for _ in range(rng.randint(1, 2)):
            text = rng.choice([_flip, _cut, _repeat_line])(rng, text)
        path.write_text(text, encoding="utf-8", errors="surrogatepass")
        _read_launch(path)


def _include_bomb(directory: Path, files: int = 18) -> Path:
    for i in range(files):
        following = f"inc{i + 1}.launch.xml"
        body = f'<include file="{following}"/><include file="{following}"/>' if i < files - 1 else \
            '<node pkg="p" exec="e"/>'
        (directory / f"inc{i}.launch.xml").write_text(f"<launch>{body}</launch>\n")
    return directory / "inc0.launch.xml"


def _alias_bomb_flow(levels: int = 9) -> str:
    anchors = ["&a0 [x, x, x, x, x, x, x, x, x]"]
    anchors += [f"&a{n} [" + ", ".join([f"*a{n - 1}"] * 9) + "]" for n in range(1, levels)]
    return "[" + ", ".join(anchors) + "]"


HOSTILE_LAUNCH_FILES = {
    "ESC in YAML": ("e.launch.yaml", "launch:\n- let: {name: a, value: \"x\x1by\"}\n", "control characters"),
    "3000 nested $(var)": ("v.launch.xml", '<launch><let name="a" value="' + "$(var " * 3000 + "a" + ")" * 3000
                            + '"/></launch>\n', "nested more than 32 levels deep"),
    "5000 nested groups": ("g.launch.xml", "<launch>" + "<group>" * 5000 + "</group>" * 5000 + "</launch>\n",
                           "nested more than 64 levels deep"),
    "400-level YAML": ("d.launch.yaml", "launch:\n- let: {name: a, value: " + "[" * 400 + "]" * 400 + "}\n",
                       "nested more than 64 levels deep"),
    "400 nested YAML groups": ("n.launch.yaml", "launch:\n" + "".join(
        "  " * (2 * i) + "- group:\n" + "  " * (2 * i + 2) + "children:\n" for i in range(400)) + "  " * 800 + "- let: {name: a, value: b}\n",
        "nested more than 64 levels deep"),
    "<let> doubling chain": ("l.launch.xml", "<launch>\n<let name='a0' value='xx'/>\n" + "".join(
        f"<let name='a{n}' value='$(var a{n - 1})$(var a{n - 1})'/>\n" for n in range(1, 34)) + "</launch>\n",
        "more than 1,000,000 characters"),
    "alias bomb in a YAML let": ("b.launch.yaml", "launch:\n- let: {name: a, value: " + _alias_bomb_flow() + "}\n",
                                 "alias bomb"),
    "alias bomb in a let value used as a parameter": (
        "p.launch.xml", "<launch><let name='a' value='" + _alias_bomb_flow().replace("&", "&amp;") + "'/>"
        "<node pkg='p' exec='e'><param name='x' value='$(var a)'/></node></launch>\n", "alias bomb"),
    "not UTF-8": ("u.launch.xml", b"<launch><!-- caf\xe9 --></launch>\n", "u.launch.xml: it is not UTF-8 text"),
    "not UTF-8 YAML": ("u.launch.yaml", b"launch:\n- let: {name: a, value: caf\xe9}\n", "it is not UTF-8 text"),
    "keys that are not strings": ("k.launch.yaml", "launch:\n- node: {1: x, pkg: p, exec: e}\n",
                                  "mapping keys must be strings"),
}


@pytest.mark.parametrize(("name", "text", "reason"), HOSTILE_LAUNCH_FILES.values(), ids=HOSTILE_LAUNCH_FILES.keys())
def test_hostile_launch_files_are_refused_quickly_with_a_reason(tmp_path, name, text, reason, monkeypatch):
    """The launch reader has the contract loader's limits: no traceback (RecursionError), no
    memory exhausted, a LaunchError naming the file (and the line where known)."""
    monkeypatch.chdir(tmp_path)
    path = tmp_path / name
    if isinstance(text, bytes):
        path.write_bytes(text)
    else:
        path.write_text(text, encoding="utf-8")
    with deadline(CASE_SECONDS, name), pytest.raises(LaunchError) as info:
        launch_reader.read(path)
    assert reason in str(info.value), str(info.value)
    assert str(info.value).startswith(name), str(info.value)
    assert len(str(info.value)) < 400, str(info.value)


def test_an_include_bomb_is_refused_without_reading_every_include(tmp_path):
    """18 files that each include the next twice: 2^18 includes. Each file is parsed once and the
    includes followed are bounded, so the reader stops at once, saying why."""
    with deadline(CASE_SECONDS, "an include bomb"), pytest.raises(LaunchError) as info:
        launch_reader.read(_include_bomb(tmp_path))
    assert f"more than {launch_reader.MAX_INCLUDES:,} includes" in str(info.value), str(info.value)


def test_groups_nested_in_every_file_of_an_include_chain_are_bounded(tmp_path):
    """Each file nests groups below the per-file limit, the chain is below the include limit,
    together they would recurse past Python's limit: the reader counts both."""
    files = launch_reader.MAX_INCLUDE_DEPTH
    for i in range(files):
        inner = f'<include file="c{i + 1}.launch.xml"/>' if i < files - 1 else '<node pkg="p" exec="e"/>'
        (tmp_path / f"c{i}.launch.xml").write_text("<launch>" + "<group>" * 60 + inner + "</group>" * 60
                                                   + "</launch>\n")
    with deadline(CASE_SECONDS, "nested groups and includes"), pytest.raises(LaunchError) as info:
        launch_reader.read(tmp_path / "c0.launch.xml")
    assert f"nested more than {launch_reader.MAX_NESTING} levels deep" in str(info.value), str(info.value)


def test_a_launch_file_with_many_lets_and_includes_is_still_read(tmp_path):
    """The limits leave room for real launch files: 60 includes of one file, 200 lets each."""
    lets = "".join(f'<let name="v{n}" value="$(var who)_{n}"/>' for n in range(200))
    (tmp_path / "part.launch.xml").write_text(f'<launch><arg name="who"/>{lets}<node pkg="p" exec="e" '
                                              'name="$(var v199)"/></launch>\n')
    includes = "".join(f'<include file="part.launch.xml"><arg name="who" value="r{n}"/></include>'
                       for n in range(60))
    (tmp_path / "main.launch.xml").write_text(f"<launch>{includes}</launch>\n")
    with deadline(CASE_SECONDS, "many includes"):
        result = launch_reader.read(tmp_path / "main.launch.xml")
    assert [n.name for n in result.nodes] == [f"r{n}_199" for n in range(60)]


# ---------------------------------------------------------------------------- git trees (the gate, issue 50)

#: pieces of file names as git stores them (bytes): not UTF-8, a newline, a tab, quotes, a leading
#: dash, a right-to-left mark, glob characters
_NAME_PIECES = [b"driver", b"a b", b"a\nb", b"\xff\xfe", b"\xc3\xa9t\xc3\xa9", b"-x", b"*", b'"q"', b"back\\slash",
                b"tab\there", b"..x", b" lead", b"\xe2\x80\xae", b"x:y", b"[ab]"]
_LFS = "version https://git-lfs.github.com/spec/v1\noid sha256:{}\nsize 1234\n".format("0" * 64)
#: what a file of the base revision holds (or is): contracts, other YAML, and what the gate cannot read
_FILE_KINDS = ["contract", "contract", "golden", "not a contract", "lfs pointer", "empty", "latin-1", "too large",
               "link inside", "link outside", "dangling link"]
#: what the branch does to a file of the base
_CHANGES = ["keep", "keep", "edit", "remove", "rename", "fifo", "link outside", "lfs pointer", "directory",
            "not a contract"]


def _fuzzed_name(rng: random.Random, i: int) -> str:
    pieces = b"".join(rng.choice(_NAME_PIECES) for _ in range(rng.randint(1, 3)))
    folder = rng.choice([b"", b"contracts/", b"test/\xff/", b"a\nb/"])
    return os.fsdecode(folder + pieces + b"%d" % i + rng.choice([b".yaml", b".yml", b".interfaces.yaml"]))


def _fuzzed_text(rng: random.Random, i: int, kind: str) -> str | bytes:
    from git_history import endpoint, node_contract

    contract = node_contract(f"/n{i}", publishers=endpoint(f"/t{i}_{rng.randrange(3)}"),
                             version=rng.choice([None, "1.0.0", "2.0.0", "1" * 30 + ".0.0"]))
    return {"contract": contract.replace("nodes:", "target: {script: x.py}\nnodes:"), "golden": contract,
            "not a contract": "rate: 10\n", "lfs pointer": _LFS, "empty": "",
            "latin-1": b"contract_version: 1\n# \xff\xfe\nnodes: {}\n",
            "too large": contract + "# padding\n" * 300}.get(kind, contract)


def _place(path: Path, content: str | bytes | None, *, link: str | None = None) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    if link is not None:
        path.symlink_to(link)
    elif isinstance(content, bytes):
        path.write_bytes(content)
    else:
        path.write_text(content or "", encoding="utf-8")


def _unlink(path: Path) -> None:
    if path.is_dir() and not path.is_symlink():
        import shutil

        shutil.rmtree(path)
    else:
        path.unlink()


def _fuzzed_repository(rng: random.Random, root: Path, outside: Path) -> set[str]:
    """A base commit on ``main`` of random files (names, kinds, sizes) and a work tree that changes
    some of them; the names of the contracts it left as they were (regular files)."""
    from git_history import GitRepo

    repo = GitRepo(root)
    names = [_fuzzed_name(rng, i) for i in range(rng.randint(1, 8))]
    kinds = {name: rng.choice(_FILE_KINDS) for name in names}
    for i, name in enumerate(names):
        kind = kinds[name]
        link = {"link inside": os.path.relpath(root / names[0], (root / name).parent),
                "link outside": str(outside), "dangling link": "nope.yaml"}.get(kind)
        _place(root / name, _fuzzed_text(rng, i, kind), link=link if name != names[0] or kind != "link inside" else None)
    repo.commit("base")
    untouched: set[str] = set()
    for i, name in enumerate(names):
        change, path = rng.choice(_CHANGES), root / name
        if change == "keep":
            if kinds[name] in ("contract", "golden"):
                untouched.add(name)
            continue
        if not os.path.lexists(path):
            continue
        _unlink(path)
        if change == "edit":
            _place(path, _fuzzed_text(rng, i, "golden"))
        elif change == "rename":
            _place(root / (name + ".moved.yaml"), _fuzzed_text(rng, i, kinds[name]))
            repo.git("--literal-pathspecs", "add", "--", name + ".moved.yaml")
        elif change == "fifo":
            os.mkfifo(path)
        elif change == "link outside":
            _place(path, None, link=str(outside))
        elif change == "lfs pointer":
            _place(path, _LFS)
        elif change == "directory":
            _place(path / "inside.yaml", "x: 1\n")
        elif change == "not a contract":
            _place(path, "rate: 10\n")
    return untouched


def test_fuzzed_git_trees_never_crash_hang_or_misreport_an_unchanged_contract(tmp_path, monkeypatch):
    """Issue 50 (N19-N24): random base trees (names that are not UTF-8 or hold newlines, symlinks in
    and out of the repository, LFS pointers, files over the size limit, FIFOs and directories where
    a contract was): `diff --against main` exits 0, 1 or 2, prints only what a terminal can print,
    within a few seconds, and an untouched contract is never an error."""
    from pytest_rmw_introspect.check.contract_files import display

    monkeypatch.setattr("pytest_rmw_introspect.model.untrusted.MAX_FILE_BYTES", 2000)
    outside = tmp_path / "outside.yaml"
    outside.write_text(CONTRACT)
    rng = random.Random(SEED)
    for n in range(max(4, CASES // 25)):
        root = tmp_path / f"r{n}"
        untouched = _fuzzed_repository(rng, root, outside)
        monkeypatch.chdir(root)
        for form in ("text", "json"):
            out, err = io.StringIO(), io.StringIO()
            with deadline(CASE_SECONDS * 2, f"the gate on fuzzed tree {n}"), contextlib.redirect_stderr(err), \
                    contextlib.redirect_stdout(out):
                status = cli.main(["diff", "--against", "main", "--format", form])
            assert status in (0, 1, 2), (n, form, status, err.getvalue())
            assert "Traceback" not in err.getvalue()
            out.getvalue().encode("utf-8"), err.getvalue().encode("utf-8")  # no lone surrogate: it prints
            if form == "json" and out.getvalue():
                report = json.loads(out.getvalue())
                failed = {item["contract"] for item in report["items"] if "error" in item}
                assert not failed & {display(name) for name in untouched}, (n, failed, err.getvalue())


# ---------------------------------------------------------------------------- unstable_names patterns

def _fuzzed_pattern(rng: random.Random) -> str:
    segments = ["".join(rng.choice("ab_*9") for _ in range(rng.randint(1, 16))) for _ in range(rng.randint(1, 3))]
    pattern = "/" + "/".join(segments)
    if "*" not in pattern:
        pattern += "*"
    return pattern


def test_fuzzed_unstable_names_patterns_load_and_match_quickly():
    """Issue 50: random ``unstable_names:`` patterns (and some that are not patterns: empty, a lone
    ``/``, a byte that is not ASCII, 2,000 characters) in a whole contract load or are refused with
    a ContractError; those that load name random node names quickly, through the contract's rules
    (the many-star case of N17 is in test_fuzzed_unstable_names_patterns_key_nodes_quickly_or_are_refused)."""
    from pytest_rmw_introspect.model.unstable_names import NamePattern, NameRules

    rng = random.Random(SEED)
    for _ in range(CASES):
        pattern = _fuzzed_pattern(rng) if rng.random() < 0.8 else rng.choice(
            ["", "/", "*", "/a**", "/a/*/", "a_*", "/a b*", "/\xff*", "/*" * 30, "/a*" + "x" * 2000])
        text = CONTRACT + f"unstable_names:\n  - {{pattern: {json.dumps(pattern)}, reason: fuzzed}}\n"
        with deadline(CASE_SECONDS, f"loading unstable_names {pattern!r}"):
            try:
                contract = loads(text, path="fuzzed.interfaces.yaml")
            except ContractError as exc:
                assert "fuzzed.interfaces.yaml" in str(exc) and len(exc.reason) < 600, exc.reason
                continue
        rules = NameRules.of_contract(contract.unstable_names, contract.nodes)
        names = ["/" + "/".join("".join(rng.choice("ab_9") for _ in range(rng.randint(1, 30)))
                                for _ in range(rng.randint(1, 3))) for _ in range(5)]
        with deadline(CASE_SECONDS, f"matching {pattern!r}"):
            for name in names:
                rules.pattern_for(name, None)
                NamePattern(pattern).matches(name)


# ---------------------------------------------------------------------------- stand_ins

SYSTEM_WITH_STAND_INS = """\
system_version: 1
launch: {path: robot.launch.xml}
stand_ins:
  - package: drivers
    executable: lidar_driver
    name: /robot1/lidar
    contract: lidar.interfaces.yaml
    reason: needs the lidar on /dev/ttyUSB0
  - {executable: imu, contract: imu.nodl.yaml}
processes: []
nodes: {}
"""


_HOSTILE_VALUES = ["", "/", "..", "../../etc/passwd", "/dev/zero", "~", "a\nb", "x" * 3000, "/robot1/*", "imu.nodl.yaml",
                   "lidar.interfaces.yaml", "\u202e", 0, -1, 1e309, None, True, [], {}, ["a"], {"a": 1}]


def _stand_in_entries(rng: random.Random) -> str:
    """A ``stand_ins:`` block whose shape is right and whose values are hostile (JSON is YAML)."""
    entries = []
    for _ in range(rng.randint(0, 4)):
        entry = {key: rng.choice(_HOSTILE_VALUES) for key in ("package", "executable", "name", "contract", "reason")
                 if rng.random() < 0.8}
        entries.append(entry)
    return json.dumps(entries)


def test_fuzzed_stand_ins_load_or_fail_with_a_contract_error(tmp_path):
    """Issue 50: mutated ``stand_ins:`` blocks, and stand-in files that are missing, mutated, FIFOs,
    directories or links: a ContractError that names the system contract, never a traceback or a hang."""
    from pytest_rmw_introspect.model import stand_ins, system_contract

    system = tmp_path / "robot.system.yaml"
    os.mkfifo(tmp_path / "imu.nodl.yaml")
    rng = random.Random(SEED)
    mutated = list(mutated_contracts(CASES // 3))
    for n in range(CASES // 3):
        text = SYSTEM_WITH_STAND_INS
        if rng.random() < 0.5:
            text = _mutated(rng, text)
        else:
            head, _, tail = text.partition("stand_ins:\n")
            text = head + f"stand_ins: {_stand_in_entries(rng)}\n" + tail[tail.index("processes:"):]
        lidar = tmp_path / "lidar.interfaces.yaml"
        if os.path.lexists(lidar):
            _unlink(lidar)
        shape = rng.choice(["contract", "mutated", "missing", "fifo", "directory", "link outside"])
        if shape == "contract":
            lidar.write_text(CONTRACT)
        elif shape == "mutated":
            lidar.write_text(mutated[n], encoding="utf-8", errors="surrogatepass")
        elif shape == "fifo":
            os.mkfifo(lidar)
        elif shape == "directory":
            lidar.mkdir()
        elif shape == "link outside":
            lidar.symlink_to("/etc/hostname")
        with deadline(CASE_SECONDS, f"stand-ins case {n} ({shape})"):
            try:
                loaded = system_contract.loads(text, path=system)
                stand_ins.load_all(loaded.stand_ins, system)
            except ContractError as exc:
                assert "robot.system.yaml" in str(exc)


# ---------------------------------------------------------------------------- baselines

BASELINE = {"format": "rmw_introspect_baseline", "version": 1, "findings": [
    {"key": ["c.interfaces.yaml", "/talker", "publishers", "/chatter", "QOS_DEPTH_CHANGED"], "rule": "QOS_DEPTH_CHANGED",
     "contract": "c.interfaces.yaml", "message": "depth 10 -> 5"},
    {"key": ["", "/listener", "node", "/listener", "NODE_REMOVED"], "rule": "NODE_REMOVED", "contract": None,
     "message": "gone"}]}


def _mutated(rng: random.Random, text: str) -> str:
    """``text`` after 1 to 3 of the MUTATORS (those that need a ``key: value`` line or any text only
    where there is one)."""
    for _ in range(rng.randint(1, 3)):
        usable = [m for m in MUTATORS if text and (m is not _odd_value or ": " in text)]
        if not usable:
            break
        text = rng.choice(usable)(rng, text)
    return text


def test_fuzzed_baselines_load_or_fail_with_a_baseline_error(tmp_path):
    """Issue 50: mutated baseline files (and ones that are not files) load, apply to findings, or
    are refused with a BaselineError that names the file."""
    from pytest_rmw_introspect.compare import baseline as baseline_module
    from pytest_rmw_introspect.compare.drift import DriftItem
    from pytest_rmw_introspect.errors import BaselineError
    from pytest_rmw_introspect.model.vocabulary import Severity

    item = DriftItem("/talker", "publishers", "/chatter", "changed", 10, 5, "QOS_DEPTH_CHANGED", Severity.RISKY, "m")
    path = tmp_path / "baseline.json"
    text = json.dumps(BASELINE, indent=2)
    rng = random.Random(SEED)
    for n in range(CASES // 3):
        mutated = text
        if rng.random() < 0.5:
            mutated = _mutated(rng, mutated)
        else:  # the shape of a baseline, hostile values
            document = copy.deepcopy(BASELINE)
            for _ in range(rng.randint(1, 3)):
                finding = rng.choice(document["findings"])
                key = rng.choice(["key", "rule", "contract", "message", "findings", "version"])
                value = rng.choice(_HOSTILE_VALUES + [[rng.choice(_HOSTILE_VALUES) for _ in range(5)]])
                if key in ("findings", "version"):
                    document[key] = value
                elif isinstance(finding, dict):
                    finding[key] = value
                if not isinstance(document["findings"], list) or not document["findings"]:
                    break
            mutated = json.dumps(document)
        if os.path.lexists(path):
            _unlink(path)
        shape = rng.choice(["text"] * 6 + ["fifo", "directory", "latin-1"])
        if shape == "fifo":
            os.mkfifo(path)
        elif shape == "directory":
            path.mkdir()
        elif shape == "latin-1":
            path.write_bytes(mutated.encode("utf-8", "surrogatepass") + b"\xff")
        else:
            path.write_text(mutated, encoding="utf-8", errors="surrogatepass")
        with deadline(CASE_SECONDS, f"baseline case {n} ({shape})"):
            try:
                loaded = baseline_module.load(path)
            except BaselineError as exc:
                assert "baseline.json" in str(exc)
                continue
            loaded.split(tmp_path / "c.interfaces.yaml", [item])
            loaded.fixed_note()
