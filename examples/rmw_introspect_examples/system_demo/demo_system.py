"""A deliberately broken robot: this test FAILS, on purpose, to show a system check's report.

Run it on demand (it is not collected by the package's test suite, its name does not start
with ``test_``)::

    pytest system_demo/demo_system.py

broken_robot.launch.xml starts the package's nodes with three mistakes: a String listener
remapped onto the OccupancyGrid map (TYPE_MISMATCH), two talkers with one node name
(DUPLICATE_NODE_NAME), and a client remapped to a service nobody serves, one letter away from
the service the server offers (SERVICE_NAME_MISMATCH). The system contract matches what the launch file starts, so there is
no drift: the failure is the system rules'. `rmw-introspect graph` draws it.
"""

import pytest


@pytest.mark.system_contract("broken_robot.system-demo.yaml", system_fail_on="risky")
def test_broken_robot(system_capture):
    assert len(system_capture.processes) == 6
