"""Behaviour of the middleware in real processes: blocking waits, guard-condition wake-up,
progress snapshots, the environment variables."""

import signal
import time

import rmwi_helpers as h
from rmwi_helpers import ep, node
from rmwi_helpers import rclpy_node_infrastructure as infra

TALKER = [ep("publisher", "/talker", "/chatter", "std_msgs/msg/String")]


def test_idle_spinning_node_uses_no_cpu(middleware_library, tmp_path):
    path = tmp_path / "idle.json"
    proc = h.spawn(middleware_library, h.python_node("idle_spinner.py"), path, {"RMW_INTROSPECT_EXIT": "0"})
    try:
        h.wait_for(lambda: h.read_capture_if(path, state="settled"))
        before = h.cpu_ticks(proc.pid)
        time.sleep(1.0)
        after = h.cpu_ticks(proc.pid)
    finally:
        h.stop(proc, signal.SIGINT)
    used = after - before
    print(f"idle spinning rclpy node: {used} clock ticks of CPU in 1.0 s")
    # A wait that returned at once would burn ~100 ticks (a full core) here.
    assert used <= 5


def test_guard_condition_trigger_wakes_the_wait(run):
    # Nothing but a guard condition triggered from another thread after 0.3 s can wake
    # this executor; its callback creates /woken. Settling takes 1 s of quiet.
    result = run(h.python_node("guard_wake.py"), settle_ms=1000)
    h.assert_settled_process(result)
    n = "/guard_wake"
    h.assert_capture(result.capture, [node("guard_wake")],
                     infra(n) + [ep("publisher", n, "/woken", "std_msgs/msg/String")])


def test_sigkill_after_first_write_loses_nothing(middleware_library, tmp_path):
    # A settle time the test never reaches: only progress snapshots are written.
    path = tmp_path / "killed.json"
    proc = h.spawn(middleware_library, h.python_node("talker.py"), path,
                   {"RMW_INTROSPECT_EXIT": "1", "RMW_INTROSPECT_SETTLE_MS": "600000"})
    try:
        h.wait_for(lambda: (c := h.read_capture_if(path)) and len(c["endpoints"]) == 10)
    finally:
        out, err = h.stop(proc, signal.SIGKILL)
    assert proc.returncode == -signal.SIGKILL
    capture = h.load_capture(path)
    h.assert_capture(capture, [node("talker")], infra("/talker") + TALKER, state="running")
    assert capture["time_to_settle_ms"] is None


def test_exit_0_keeps_running_and_rewrites_on_change(middleware_library, tmp_path):
    path = tmp_path / "later.json"
    proc = h.spawn(middleware_library, h.python_node("changes_later.py"), path, {"RMW_INTROSPECT_EXIT": "0"})
    n = "/changer"
    first = [ep("publisher", n, "/first", "std_msgs/msg/String")]
    second = [ep("publisher", n, "/second", "std_msgs/msg/String")]
    try:
        early = h.wait_for(lambda: h.read_capture_if(path, state="settled"))
        h.assert_capture(early, [node("changer")], infra(n) + first)
        assert proc.poll() is None, "RMW_INTROSPECT_EXIT=0 must not end the process"
        late = h.wait_for(
            lambda: (c := h.read_capture_if(path, state="settled")) and len(c["endpoints"]) == 11 and c)
        h.assert_capture(late, [node("changer")], infra(n) + first + second)
        assert late["time_to_settle_ms"] > early["time_to_settle_ms"]
        assert proc.poll() is None
    finally:
        h.stop(proc, signal.SIGINT)
    # SIGINT: rclpy shuts the context down (state "shutdown"); Python then ends with
    # KeyboardInterrupt, re-raising SIGINT (no C atexit: "shutdown" stays) or exiting
    # normally ("exit"). Teardown destroys nothing in the record.
    final = h.load_capture(path)
    assert final["state"] in ("shutdown", "exit")
    h.assert_capture(final, [node("changer")], infra(n) + first + second, state=None)


def test_yaml_format(run):
    result = run(h.python_node("talker.py"), fmt="yaml")
    h.assert_settled_process(result)
    assert result.raw.startswith("# rmw_introspect capture")
    assert "\nendpoints:\n- seq: 2\n" in result.raw
    h.assert_capture(result.capture, [node("talker")], infra("/talker") + TALKER)


def test_auto_export_0_writes_nothing(run):
    result = run(h.python_node("talker.py"), env={"RMW_INTROSPECT_AUTO_EXPORT": "0"})
    assert result.returncode == 0, str(result)  # still settles and exits
    assert result.capture is None and not result.path.exists()


def test_server_available_0_keeps_the_client_waiting(run):
    # wait_for_service() polls rmw_service_server_is_available without ever entering rmw_wait:
    # since issue 9 those calls are activity (vt-spec), so the waiting client is a steady loop
    # and settles by activity (before: it never settled and was killed at the timeout).
    result = run(h.python_node("service_client.py"),
                 env={"RMW_INTROSPECT_SERVER_AVAILABLE": "0"}, timeout=10.0)
    assert result.returncode == 0, str(result)
    n = "/flag_client"
    # The subscription created after wait_for_service() is missing.
    h.assert_capture(result.capture, [node("flag_client")],
                     infra(n) + [ep("client", n, "/set_flag", "std_srvs/srv/SetBool")])
    assert result.capture["settled_by"] == "activity"
    # Its spin_once(timeout_sec=0) between the attempts polls rmw_wait (issue 10): enough for
    # the middleware to read the node's parameters through those polls after the settle.
    assert result.capture["ever_waited"] is True
    assert [p["name"] for p in result.capture["nodes"][0]["parameters"]] == [
        "use_sim_time", "start_type_description_service"]


def test_verbose_logs_each_entity(run):
    result = run(h.python_node("talker.py"), env={"RMW_INTROSPECT_VERBOSE": "1"})
    h.assert_settled_process(result)
    assert "[rmw_introspect] node talker" in result.stderr
    assert "[rmw_introspect] publisher /chatter [std_msgs/msg/String]" in result.stderr
    assert "[rmw_introspect] wrote settled capture" in result.stderr


def _default_output(err: str) -> h.Path:
    """The default output the middleware says it writes to (once, on stderr)."""
    line = next(x for x in err.splitlines() if "the capture goes to " in x)
    return h.Path(line.split("the capture goes to ", 1)[1].split(" (RMW_INTROSPECT_OUTPUT unset)")[0])


def test_default_output_path_is_in_a_private_directory(middleware_library, tmp_path):
    proc = h.spawn(middleware_library, h.python_node("talker.py"), tmp_path / "unused",
                   {"RMW_INTROSPECT_EXIT": "1", "RMW_INTROSPECT_OUTPUT": "", "TMPDIR": str(tmp_path)})
    out, err = proc.communicate(timeout=30)
    assert proc.returncode == 0, err
    default = _default_output(err)
    assert default.name == f"rmw_introspect_{proc.pid}.json"
    assert default.parent.parent == tmp_path and default.parent.name.startswith(f"rmw_introspect_{proc.pid}.")
    assert oct(default.parent.stat().st_mode & 0o777) == oct(0o700)  # mkdtemp: only the user enters it
    h.assert_capture(h.load_capture(default), [node("talker")], infra("/talker") + TALKER)
    assert err.count("the capture goes to ") == 1  # said once, not at every snapshot


def test_a_symlink_planted_at_the_predictable_default_name_is_not_followed(middleware_library, tmp_path):
    # The default output was /tmp/rmw_introspect_<pid>.json: another user could plant a symlink
    # (or a file) there before the process starts. `exec` keeps the shell's pid, so the link sits
    # at exactly that name, in the directory the middleware uses as its temporary directory.
    victim = tmp_path / "victim.txt"
    victim.write_text("precious\n")
    shared_tmp = tmp_path / "tmp"
    shared_tmp.mkdir()
    script = f'ln -s {victim} {shared_tmp}/rmw_introspect_$$.json && exec "$@"'
    proc = h.spawn(middleware_library, ["sh", "-c", script, "sh", *h.python_node("talker.py")], tmp_path / "unused",
                   {"RMW_INTROSPECT_EXIT": "1", "RMW_INTROSPECT_OUTPUT": "", "TMPDIR": str(shared_tmp)})
    out, err = proc.communicate(timeout=30)
    assert proc.returncode == 0, err
    planted = shared_tmp / f"rmw_introspect_{proc.pid}.json"
    assert planted.is_symlink() and victim.read_text() == "precious\n"  # neither followed nor replaced
    default = _default_output(err)
    assert default.parent != shared_tmp and default.parent.parent == shared_tmp
    h.assert_capture(h.load_capture(default), [node("talker")], infra("/talker") + TALKER)


def test_a_planted_symlink_at_the_temporary_name_is_not_followed(middleware_library, tmp_path):
    # The capture used to be written to `<output>.tmp.<pid>` opened with O_TRUNC: in /tmp (the
    # default output) another user could plant a symlink there and have the capture overwrite
    # any file the user may write. `exec` keeps the shell's pid, so the link sits at exactly the
    # name the old writer used.
    victim = tmp_path / "victim.txt"
    victim.write_text("precious\n")
    output = tmp_path / "capture.json"
    script = f'ln -s {victim} {output}.tmp.$$ && exec "$@"'
    proc = h.spawn(middleware_library, ["sh", "-c", script, "sh", *h.python_node("talker.py")], output,
                   {"RMW_INTROSPECT_EXIT": "1"})
    out, err = proc.communicate(timeout=30)
    assert proc.returncode == 0, err
    assert victim.read_text() == "precious\n"
    h.assert_capture(h.load_capture(output), [node("talker")], infra("/talker") + TALKER)
    assert oct(output.stat().st_mode & 0o777) == oct(0o644)
    # only the planted link is left: every temporary file was renamed over the output
    assert [p.name for p in tmp_path.glob("capture.json.tmp.*")] == [f"capture.json.tmp.{proc.pid}"]


def test_pid_placeholder_in_output(middleware_library, tmp_path):
    proc = h.spawn(middleware_library, h.python_node("talker.py"), tmp_path / "cap_<pid>.json",
                   {"RMW_INTROSPECT_EXIT": "1"})
    out, err = proc.communicate(timeout=30)
    assert proc.returncode == 0, err
    capture = h.load_capture(tmp_path / f"cap_{proc.pid}.json")
    assert capture["pid"] == proc.pid
