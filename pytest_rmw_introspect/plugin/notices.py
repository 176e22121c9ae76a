"""The run layer's progress lines (``run.progress``: a middleware build, a wait for another
process's build, a warm start server or a system capture that takes a while) on pytest's
terminal, past its output capture. In a pytest-xdist worker they go to the terminal the workers
share with their controller (the worker's stderr), and a line all workers would say (a wait for
the same build) is said by one of them."""

from __future__ import annotations

import sys
import threading

import pytest

from ..run import progress

_PREVIOUS = pytest.StashKey[progress.Sink]()


def install(config: pytest.Config) -> None:
    """Send the progress lines of this session to its terminal until :func:`uninstall`."""
    workerinput = getattr(config, "workerinput", None)

    def on_terminal(line: str) -> None:
        # (looked up when a line comes: pytest registers them after this plugin's pytest_configure)
        capture = config.pluginmanager.getplugin("capturemanager")
        reporter = None if workerinput is not None else config.pluginmanager.getplugin("terminalreporter")
        if threading.current_thread() is not threading.main_thread():
            # only the main thread may suspend pytest's capture: a line of another thread goes
            # where its stderr goes now (the terminal, or the running test's captured output)
            _write(None, line)
            return
        if capture is None:
            _write(reporter, line)
            return
        with capture.global_and_fixture_disabled():
            _write(reporter, line)

    config.stash[_PREVIOUS] = progress.set_sink(on_terminal)
    if workerinput is not None:
        progress.set_scope(str(workerinput.get("testrunuid") or "") or None)


def _write(reporter: pytest.TerminalReporter | None, line: str) -> None:
    if reporter is not None:
        reporter.ensure_newline()
        reporter.write_line(progress.PREFIX + line)
        reporter.flush()
    else:
        sys.stderr.write(progress.PREFIX + line + "\n")
        sys.stderr.flush()


def uninstall(config: pytest.Config) -> None:
    previous = config.stash.get(_PREVIOUS, None)
    if previous is not None:
        progress.set_sink(previous)
        progress.set_scope(None)
        del config.stash[_PREVIOUS]
