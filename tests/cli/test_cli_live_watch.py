"""`check --live --watch` (issue 52 item 2): the check, then each change of a running graph as it
happens (a node started, a node gone), then the check again at `--duration` and a summary. Real
processes on Fast DDS in a ROS_DOMAIN_ID of their own with localhost discovery."""

from __future__ import annotations

import re
import subprocess
import time
from pathlib import Path

from cli_helpers import console_script

from pytest_rmw_introspect.live import bringup
from pytest_rmw_introspect.run.target import TargetSpec

CONTRACTS = Path(__file__).resolve().parents[2] / "examples" / "rmw_introspect_examples" / "contracts"


def _example(executable: str) -> TargetSpec:
    return TargetSpec(package="rmw_introspect_examples", executable=executable)


def test_watch_reports_each_change_and_checks_again_at_the_end(tmp_path):
    domain = bringup.reserve_domain()
    talker = bringup.start([_example("talker")], domain=domain)
    listener = None
    try:
        watch = subprocess.Popen([console_script(), "check", "--live", "--watch", "--duration", "14", "--settle", "1",
                                  CONTRACTS / "talker.interfaces.yaml", CONTRACTS / "listener.interfaces.yaml"],
                                 env=talker.env, cwd=tmp_path, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                 text=True)
        assert watch.stdout is not None
        first = watch.stdout.readline()  # the first check: the talker matches
        assert "talker.interfaces.yaml: matches (1 node running" in first, first
        listener = bringup.start([_example("listener")], domain=domain)
        time.sleep(4)
        talker.stop()
        out, err = watch.communicate(timeout=60)
    finally:
        talker.stop()
        if listener is not None:
            listener.stop()
        domain.release()
    assert watch.returncode == 1, (out, err)  # at the end the talker is gone
    assert "[NODE_ADDED] /listener: new node /listener" in out, out
    assert "[NODE_REMOVED] /talker: node removed" in out, out
    assert "/parameter_events" not in out  # infrastructure stays out, as in a check
    assert out.rstrip().endswith("listener.interfaces.yaml: matches (1 node running in ROS_DOMAIN_ID "
                                 f"{domain.id})"), out
    assert re.search(r"watched ROS_DOMAIN_ID \d+ for \d+ s: \d+ change\(s\) in [1-9]\d* update\(s\) of the graph", err), err
