"""Set-up loops are not steady state (issue 24 item 7): a program that only logs while it waits
for its device, or declares thousands of parameters, before it creates its interface is captured
with that interface; a node blocked inside a callback the middleware drove (a lifecycle
transition, a stimulus' service call) is told so, not that it kept changing its interfaces."""

from __future__ import annotations

import pytest
import rmwi_helpers as h

from pytest_rmw_introspect.errors import TargetTimeout
from pytest_rmw_introspect.run import runner
from pytest_rmw_introspect.run.target import TargetSpec


def capture(script, **options):
    return runner.run(TargetSpec.from_mapping({"script": str(h.NODES / script), "timeout": 30, **options}))


def test_a_driver_that_logs_while_it_waits_for_its_device_is_captured_with_its_publisher():
    cap = capture("setup_logging_wait.py")
    assert cap.state == "settled"
    assert cap["/device_driver"].names("publishers") == ["/scan"]
    # its log lines were not taken for a steady loop: it settled once it waited in its executor
    assert cap.settled_by == "wait"


def test_a_node_that_declares_many_parameters_first_is_captured_with_its_publisher():
    cap = capture("many_parameters.py", env={"PARAMETER_COUNT": "15000"}, read_parameters=False)
    assert cap.state == "settled"
    assert cap["/big_config"].names("publishers") == ["/configured"]


@pytest.mark.parametrize("how", ["event", "sleep"])
def test_a_lifecycle_node_blocked_in_on_configure_is_said_to_be_blocked(how):
    with pytest.raises(TargetTimeout) as info:
        capture("stuck_on_configure.py", timeout=4, env={"STUCK_HOW": how})
    message = str(info.value)
    assert "lifecycle node /stuck_configure to configure" in message
    assert "blocked in its on_configure callback" in message and "lifecycle: none" in message
    assert "kept creating or destroying" not in message


@pytest.mark.parametrize("how", ["event", "sleep"])
def test_a_service_callback_that_never_returns_is_said_to_be_blocked(how):
    with pytest.raises(TargetTimeout) as info:
        capture("stuck_service_callback.py", timeout=7, stimuli=["/stuck_service"], env={"STUCK_HOW": how})
    message = str(info.value)
    assert "the stimulus /stuck_service then called the service of node /stuck_service_node" in message
    assert "blocked in it" in message
    assert "kept creating or destroying" not in message
