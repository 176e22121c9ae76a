"""`rmw-introspect check` of several contracts forks their targets from one warm start server,
which ends with the run; a run with one capture (`check` of one contract, `capture`) starts it
cold; `--cold-start` asks for cold."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
import time
from pathlib import Path

from rmwi_processes import wait_gone

WARM_PID = Path(__file__).resolve().parents[1] / "middleware" / "nodes_warm" / "warm_pid.py"
CLI = Path(sys.executable).parent / "rmw-introspect"


def _contracts(tmp_path: Path, pids: Path, names: list[str]) -> list[str]:
    out = []
    for name in names:
        contract = tmp_path / f"{name}.interfaces.yaml"
        contract.write_text(textwrap.dedent(f"""\
            contract_version: 1
            target:
              script: {WARM_PID}
              settle: 0.02
              env: {{WARM_PID_FILE: {pids}, WARM_NODE_NAME: {name}}}
            nodes: {{}}
        """))
        out.append(str(contract))
    return out


def _parents(pids: Path) -> list[int]:
    return [int(line.split()[1]) for line in pids.read_text().splitlines()]


def test_several_contracts_share_one_server_that_ends_with_the_run(tmp_path, middleware_library, monkeypatch):
    monkeypatch.setenv("RMW_INTROSPECT_LIBRARY", str(middleware_library))
    pids = tmp_path / "pids.txt"
    run = subprocess.run([str(CLI), "check", *_contracts(tmp_path, pids, ["first", "second", "third"])],
                         capture_output=True, text=True, timeout=120)
    assert run.returncode == 1, run.stderr  # drift: the contracts list no node
    parents = set(_parents(pids))
    assert len(parents) == 1  # one warm start server forked all three targets
    (server,) = parents
    assert wait_gone([server], 5) == []  # it ended with the run


def test_one_capture_and_cold_start_start_cold(tmp_path, middleware_library, monkeypatch):
    monkeypatch.setenv("RMW_INTROSPECT_LIBRARY", str(middleware_library))
    pids = tmp_path / "pids.txt"
    contracts = _contracts(tmp_path, pids, ["only", "one", "two"])
    single = subprocess.Popen([str(CLI), "check", contracts[0]], stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    single.communicate(timeout=120)
    cold = subprocess.Popen([str(CLI), "check", "--cold-start", *contracts[1:]], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE)
    cold.communicate(timeout=120)
    capture = subprocess.Popen([str(CLI), "capture", "--script", str(WARM_PID), "--settle", "0.02"],
                               env={**os.environ, "WARM_PID_FILE": str(pids)}, stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True)
    _out, err = capture.communicate(timeout=120)
    assert capture.returncode == 0, err
    # a cold start's parent is the CLI process itself
    assert _parents(pids) == [single.pid, cold.pid, cold.pid, capture.pid]


def test_a_terminated_run_leaves_no_server_or_target(tmp_path, middleware_library, monkeypatch):
    monkeypatch.setenv("RMW_INTROSPECT_LIBRARY", str(middleware_library))
    pids = tmp_path / "pids.txt"
    contracts = _contracts(tmp_path, pids, ["hangs", "later"])
    text = Path(contracts[0]).read_text().replace("WARM_NODE_NAME: hangs", "WARM_NODE_NAME: hangs, WARM_HANG: '1'")
    Path(contracts[0]).write_text(text)
    proc = subprocess.Popen([str(CLI), "check", *contracts], stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    try:
        deadline = time.monotonic() + 60
        while not (pids.exists() and pids.read_text().strip()) and time.monotonic() < deadline:
            time.sleep(0.05)
        target, server = (int(x) for x in pids.read_text().split()[:2])
        assert server != proc.pid
        proc.terminate()
        _out, err = proc.communicate(timeout=30)
        assert proc.returncode == 143, err
        assert wait_gone([target, server], 10) == []
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()


def test_a_system_contract_is_many_captures_and_starts_them_warm(tmp_path, middleware_library, monkeypatch):
    """One system contract is one capture per process: its processes start warm, as under
    `capture --launch` (counting files alone started them all cold, issue 42)."""
    monkeypatch.setenv("RMW_INTROSPECT_LIBRARY", str(middleware_library))
    monkeypatch.delenv("CI", raising=False)  # `check --update` writes the system contract (refused in CI)
    pids = tmp_path / "pids.txt"
    script = tmp_path / "warm_pid"  # an executable whose #! names this interpreter: it may start warm
    script.write_text(f"#!{sys.executable}\n" + WARM_PID.read_text())
    script.chmod(0o755)
    nodes = "".join(f'  <node exec="{script}" name="{name}"><env name="WARM_PID_FILE" value="{pids}"/></node>\n'
                    for name in ("first", "second", "third"))
    (tmp_path / "three.launch.xml").write_text(f"<launch>\n{nodes}</launch>\n")
    contract = tmp_path / "three.system.yaml"
    contract.write_text("system_version: 1\nlaunch:\n  path: three.launch.xml\ntarget: {settle: 0.02}\n")
    run = subprocess.Popen([str(CLI), "check", "--update", str(contract)], stdout=subprocess.PIPE,
                           stderr=subprocess.PIPE, text=True)
    _out, err = run.communicate(timeout=120)
    assert run.returncode == 0, err
    parents = set(_parents(pids))
    assert len(parents) == 1 and run.pid not in parents, err  # one warm start server forked all three
