"""Targets start with SIGINT and SIGQUIT at their default action although the runner ignores
them (issue 50, N30): a runner started with `cmd &` by a non-interactive shell, as CI scripts
do, ignores both, an ignored signal is inherited, and each stop (SIGINT first) waited out its
2 s grace period. The CLI (cold starts) and pytest (a warm start server) are started here with
both signals ignored; each target says how it found them, and its stop by SIGINT shows."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import textwrap
from pathlib import Path

#: the target: how it found SIGINT and SIGQUIT, and what started it (the CLI, pytest or the warm
#: start server), written to the file named by argv[1]; then it sleeps (stopped at its timeout).
#: Not in nodes/: every script there is an equivalence target of warm and cold starts.
RECORDS = textwrap.dedent("""
    import os, signal, sys, time
    with open(sys.argv[1], "a", encoding="utf-8") as out:
        parent = open(f"/proc/{os.getppid()}/cmdline", encoding="utf-8").read().replace("\\0", " ").replace("\\n", " ")
        out.write(f"{signal.getsignal(signal.SIGINT)!r}|{signal.getsignal(signal.SIGQUIT)!r}|{parent}\\n")
    time.sleep(60)
""")
DEFAULTS = "<built-in function default_int_handler>|<Handlers.SIG_DFL: 0>|"


def _ignoring_stop_signals() -> None:
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGQUIT, signal.SIG_IGN)


def _run_ignoring(argv: list[str], env: dict[str, str], cwd: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run(argv, capture_output=True, text=True, env=env, cwd=cwd, timeout=180,
                          preexec_fn=_ignoring_stop_signals)


def _env(middleware_library: Path) -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if k not in ("CI", "PYTEST_ADDOPTS")}
    env["RMW_INTROSPECT_LIBRARY"] = str(middleware_library)
    return env


def _target(tmp_path: Path) -> Path:
    script = tmp_path / "records_signals.py"
    script.write_text(RECORDS)
    return script


def test_the_cli_with_sigint_ignored_stops_its_cold_target_with_sigint(middleware_library, tmp_path):
    record = tmp_path / "signals.txt"
    done = _run_ignoring([sys.executable, "-m", "pytest_rmw_introspect", "capture", "--cold-start", "--timeout", "1",
                          "--script", str(_target(tmp_path)), "--arg", str(record)], _env(middleware_library), tmp_path)
    assert done.returncode == 2 and "did not settle within 1 s" in done.stderr, done.stderr
    assert "The tool stopped it with SIGINT" in done.stderr  # a KeyboardInterrupt: not SIGTERM 2 s later
    found, = record.read_text().splitlines()
    assert found.startswith(DEFAULTS) and "pytest_rmw_introspect capture" in found


WARM_TEST = textwrap.dedent("""
    import signal
    from pathlib import Path

    import pytest

    from pytest_rmw_introspect.errors import TargetTimeout
    from pytest_rmw_introspect.run import prewarm, runner
    from pytest_rmw_introspect.run.target import TargetSpec


    def test_a_warm_target_is_stopped_by_sigint():
        assert signal.getsignal(signal.SIGINT) == signal.SIG_IGN  # pytest, and so its server, ignore it
        spec = TargetSpec(script=Path({records!r}), arguments=({record!r},), timeout=1)
        assert prewarm.warm_up(spec, wait=60) is None
        with pytest.raises(TargetTimeout) as stopped:
            runner.run(spec, warm_wait=60)
        assert stopped.value.started == "warm"
        assert stopped.value.interrupt_left_out  # it ended on KeyboardInterrupt, not SIGTERM 2 s later
""")


def test_pytest_with_sigint_ignored_stops_its_warm_target_with_sigint(middleware_library, tmp_path):
    record = tmp_path / "signals.txt"
    (tmp_path / "test_warm_stop.py").write_text(WARM_TEST.format(records=str(_target(tmp_path)), record=str(record)))
    done = _run_ignoring([sys.executable, "-m", "pytest", "-p", "no:cacheprovider", "-q", "test_warm_stop.py"],
                         _env(middleware_library), tmp_path)
    assert done.returncode == 0, done.stdout + done.stderr
    found, = record.read_text().splitlines()
    assert found.startswith(DEFAULTS) and "warm" in found.split("|")[2]  # forked by the warm start server
