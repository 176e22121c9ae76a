"""pytest-rmw-introspect: interface contract tests for ROS 2 nodes.

A node's process runs on a recording middleware (``rmw_introspect_cpp``) that writes down
every node, publisher, subscription, service and client it creates. The pytest plugin
compares that capture with a golden YAML contract; ``pytest --update-golden`` rewrites it.

Outside pytest::

    import pytest_rmw_introspect

    cap = pytest_rmw_introspect.capture(script="talker.py", namespace="/robot1")
    for node in cap:
        print(node.fqn, [p.name for p in node.publishers])
    cap.to_contract_nodes()        # the `nodes` mapping of a contract

In a test, ``pytest_rmw_introspect.check_compatible("a.interfaces.yaml", "b.interfaces.yaml")``
fails the test unless the nodes of the contracts fit together (a system check), and
``diff_contracts(old, new)`` compares two contract files without running anything.

``pytest_rmw_introspect.capture`` is :func:`pytest_rmw_introspect.runner.capture`; the model it
returns lives in :mod:`pytest_rmw_introspect.capture_model`.
"""

from .capture_model import Capture, Endpoint, Interface, Node, RawNode
from .checking import check_compatible, diff_contracts
from .contract import Contract
from .contract import load as load_contract
from .errors import (
    CaptureFormatError,
    ContractError,
    ExecutableNotFound,
    NoNodeCreated,
    RmwIntrospectError,
    SetupError,
    TargetConfigError,
    TargetError,
    TargetExited,
    TargetTimeout,
)
from .runner import capture
from .target import TargetSpec

__version__ = "0.1.0"

__all__ = [
    "Capture",
    "CaptureFormatError",
    "Contract",
    "ContractError",
    "Endpoint",
    "ExecutableNotFound",
    "Interface",
    "NoNodeCreated",
    "Node",
    "RawNode",
    "RmwIntrospectError",
    "SetupError",
    "TargetConfigError",
    "TargetError",
    "TargetExited",
    "TargetSpec",
    "TargetTimeout",
    "capture",
    "check_compatible",
    "diff_contracts",
    "load_contract",
]
