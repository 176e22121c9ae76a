"""A deliberate drift: this test FAILS, on purpose, to show the report.

Run it on demand (it is not collected by the package's test suite, its name does not start
with ``test_``)::

    pytest drift_demo/demo_drift.py

The report lists every difference between drift_demo/talker.drift-demo.yaml and what the
talker creates now, most severe first, each with its rule id, and ends with the command
that would accept the change.
"""

import pytest


@pytest.mark.interfaces('talker.drift-demo.yaml')
def test_talker_against_an_outdated_contract(interfaces):
    pass
