"""Warm starts are equivalent to cold starts, proven by capturing every example executable and
every end-to-end test node both ways (issue 12): the same nodes and endpoints in the same order
(names, types, type hashes, type supports, QoS, destruction), the same contract view, command
line, state, exit status and notes; for targets that fail, the same error, status and last line
of stderr; what the middleware asked the nodes (parameters, lifecycle states, the probe) and the
type descriptions (``types``) too. Fields that measure time or name the process (pid) are left out.

A few programs' outcome depends on timing under load (a program that ends by itself right when
its final settle expires is captured ``settled`` or ``exit``; a node whose parameter events come
more than ``settle`` apart from its next interface settles by activity before it), cold as well as
warm: a pair that differs is captured again, up to ``ATTEMPTS`` pairs, before the test fails.
"""

from __future__ import annotations

import copy
import os
import stat
import sys
from pathlib import Path

import pytest
import warm_helpers as w

TARGETS = w.equivalence_targets()


#: pairs captured before a difference fails the test: some programs' outcome depends on timing
#: under load (cold as well as warm); a real difference of warm starts shows in every pair
ATTEMPTS = 3


def _comparable(result: dict, options: dict) -> dict:
    return w.comparable_for(result, options)


def _assert_equivalent(options: dict, base_dir: Path | None = None) -> tuple[dict, dict]:
    for _ in range(ATTEMPTS):
        cold, warm = w.cold_and_warm(options, base_dir)
        if _comparable(cold, options) == _comparable(warm, options):
            break
    assert _comparable(warm, options) == _comparable(cold, options)
    return cold, warm


def test_the_list_covers_the_examples_and_the_test_nodes():
    names = [name for name, _ in TARGETS]
    assert sum(n.startswith(w.EXAMPLES) for n in names) >= 16
    assert sum(n.startswith("middleware/") for n in names) >= 20
    assert sum(n.startswith("plugin/") for n in names) >= 5


@pytest.mark.parametrize("options", [o for _, o in TARGETS], ids=[n for n, _ in TARGETS])
def test_cold_and_warm_captures_are_identical(options):
    cold, warm = _assert_equivalent(options)
    assert cold["started"] == "cold"
    if options.get("executable") == "c_talker":
        assert warm["started"] == "cold" and warm["start_note"] == "a compiled executable"
    elif warm["error"] != "NoNodeCreated" or warm["started"] is not None:
        assert warm["started"] == "warm", warm.get("start_note")


def test_the_comparison_covers_parameters_lifecycle_and_types():
    """What the middleware learns after the first settle (parameters, lifecycle states, the
    probe) and the type descriptions are part of what cold and warm must agree on: present in
    what is compared, and a difference there is a difference."""
    cold, warm = _assert_equivalent({"script": str(w.NODES / "lc_managed.py")})
    assert warm["started"] == "warm"
    compared = w.comparable(warm)["capture"]
    (node,) = compared["entities"]["nodes"]
    assert {p["name"] for p in node["parameters"]} >= {"use_sim_time", "start_type_description_service"}
    assert node["lifecycle"]["state"] == "active" and len(node["lifecycle"]["transitions"]) == 2
    assert compared["rest"]["probe"]["state"] == "done"
    assert "lifecycle_msgs/msg/TransitionEvent" in compared["rest"]["types"]
    assert any("created_in" in e for e in compared["entities"]["endpoints"])
    for change in (lambda c: c["entities"]["nodes"][0]["parameters"].pop(),
                   lambda c: c["entities"]["nodes"][0]["lifecycle"].update(state="inactive"),
                   lambda c: c["rest"]["types"].popitem(),
                   lambda c: c["rest"]["probe"].update(requests=0)):
        changed = w.comparable(copy.deepcopy(warm))
        change(changed["capture"])
        assert changed != w.comparable(cold)


# ---------------------------------------------------------------------------- process facts


def _facts(result: dict) -> dict[str, str]:
    names = [e["name"] for e in result["capture"]["entities"]["endpoints"] if e["name"].startswith("/facts/")]
    return {n.split("/")[2]: n.split("/")[3] for n in names}


def test_a_script_sees_the_process_a_cold_start_gives_it(tmp_path):
    options = {"script": str(w.WARM_NODES / "warm_facts.py"), "arguments": ["first"], "env": {"WARM_FACT": "yes"},
               "cwd": str(tmp_path)}
    cold, warm = _assert_equivalent(options)
    assert warm["started"] == "warm"
    facts = _facts(warm)
    # not only equal: what a script run as `python script.py first --ros-args ...` is given
    assert facts["argv1"] == "v_first" and facts["env"] == "v_yes" and facts["name"] == "v___main__"
    assert facts["path0_script_dir"] == "v_True" and facts["main_is_this"] == "v_True"
    assert facts["stdin"] == "v__dev_null" and facts["stdout"] == "v_pipe"
    assert facts["group_leader"] == facts["session_leader"] == "v_True"
    assert facts["sigint"] == "v_True" and facts["blocked"] == "v___"
    assert facts["cwd"].endswith(tmp_path.name)


def test_a_module_sees_the_process_a_cold_start_gives_it():
    options = {"module": "warm_facts", "cwd": str(w.WARM_NODES), "env": {"WARM_FACT": "module"}}
    cold, warm = _assert_equivalent(options)
    assert warm["started"] == "warm"
    facts = _facts(warm)
    assert facts["path0_cwd"] == "v_True" and facts["name"] == "v___main__" and facts["spec"] == "v_ModuleSpec"


@pytest.mark.parametrize("shebang", ["interpreter", "env"])
def test_an_executable_whose_shebang_names_this_interpreter(tmp_path, shebang):
    exe = tmp_path / "bin" / "facts_node"
    exe.parent.mkdir()
    line = f"#!{sys.executable}" if shebang == "interpreter" else f"#!/usr/bin/env {Path(sys.executable).name}"
    exe.write_text(line + "\n" + (w.WARM_NODES / "warm_facts.py").read_text())
    exe.chmod(exe.stat().st_mode | stat.S_IXUSR)
    env = {"PATH": f"{Path(sys.executable).parent}{os.pathsep}{os.environ.get('PATH', '')}"}
    cold, warm = _assert_equivalent({"command": [str(exe), "arg"], "env": env})
    assert warm["started"] == "warm"
    facts = _facts(warm)
    assert facts["argv0"] == "v_facts_node" and facts["argv1"] == "v_arg"
    assert warm["capture"]["argv"][:3] == [line.split()[-1] if shebang == "env" else sys.executable, str(exe), "arg"]


# ---------------------------------------------------------------------------- state, env, atexit


def test_module_level_state_is_the_targets_own_every_time():
    options = {"script": str(w.WARM_NODES / "warm_state.py")}
    cold, warm = _assert_equivalent(options)
    again = w.outcome(w.TargetSpec.from_mapping(options), warm_wait=60.0)
    assert again["started"] == "warm" and w.comparable(again) == w.comparable(cold)
    names = {e["name"] for e in warm["capture"]["entities"]["endpoints"]}
    assert {"/state/loads_v_1", "/state/marks_v_1", "/state/counter_v_1"} <= names


def test_environment_and_arguments_read_at_import_time_are_each_captures_own():
    script = str(w.WARM_NODES / "warm_env_argv.py")
    seen = []
    for name, topic in (("alpha", "first_topic"), ("beta", "second_topic")):
        options = {"script": script, "env": {"WARM_NODE_NAME": name}, "arguments": [topic]}
        cold, warm = _assert_equivalent(options)
        assert warm["started"] == "warm"
        seen.append(sorted(warm["capture"]["contract"]))
    assert seen == [["/alpha"], ["/beta"]]


def test_a_target_that_ends_with_os_exit_right_after_creating_its_node():
    """Captured cold, and warm it was "no node created" every time. Its capture is the
    middleware's progress snapshot (os._exit runs no exit handler), due 20 ms after the last
    change: a cold start spends that time importing what the node uses, so a snapshot falls
    somewhere inside the node's creation; a warm child has it all imported and ended before any
    was due. A warm child's os._exit now lets the pending snapshot be written first, so warm
    captures the node with everything it created (a cold capture may miss its last endpoints:
    what they are depends on when the snapshot fell, so the two are not compared field by field)."""
    spec = w.TargetSpec.from_mapping({"script": str(w.WARM_NODES / "warm_os_exit.py")})
    for _ in range(3):
        cold, warm = w.cold_and_warm({"script": str(w.WARM_NODES / "warm_os_exit.py")})
        for result in (cold, warm):
            assert result["error"] is None, result
            assert sorted(result["capture"]["contract"]) == ["/quitter"]
        assert warm["started"] == "warm", warm.get("start_note")
        assert "/last_words" in [e["name"] for e in warm["capture"]["entities"]["endpoints"]]
    again = w.outcome(spec, warm_wait=60.0)
    assert again["started"] == "warm" and again["capture"] == warm["capture"]


def test_atexit_handlers_run_in_the_target_as_in_a_cold_start(tmp_path):
    records = {}
    for how in ("cold", "warm"):
        out = tmp_path / f"{how}.txt"
        options = {"script": str(w.WARM_NODES / "warm_atexit.py"), "env": {"WARM_ATEXIT_FILE": str(out)}}
        spec = w.TargetSpec.from_mapping(options)
        result = w.outcome(spec.merged({"cold_start": True}) if how == "cold" else spec, warm_wait=60.0)
        assert result["started"] == how and result["error"] is None
        lines = out.read_text().splitlines()
        assert [line.split()[1] for line in lines] == [str(result["pid"])] * 2  # ran in the target itself
        records[how] = (w.comparable(result), [line.split()[0] for line in lines])
    assert records["warm"] == records["cold"]
    assert records["warm"][1] == ["last-registered", "first-registered"]
