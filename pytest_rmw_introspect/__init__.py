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
fails the test unless the nodes of the contracts fit together (a compatibility check), and
``diff_contracts(old, new)`` compares two contract files without running anything.

The package is layered (docs/design.md): ``model`` (the vocabulary, captures, contracts),
``compare`` (options, drift, compatibility checks, reports), ``launch`` (reading launch files)
and ``run`` (targets, the runner, ROS detection, the middleware library, system captures), then
``check`` (the pipeline, outcomes, the golden writer), ``live`` (a running graph read on the real
middleware and checked against contracts) and the two front ends, ``plugin`` (pytest)
and ``cli`` (``rmw-introspect``). Beside them: ``errors`` (every exception class of the package:
the errors a user can cause and the few that stay inside it), ``_version`` (the one version) and
``__main__`` (``python -m pytest_rmw_introspect``); ``options_reference`` renders the option tables
(``model.option_tables``) as reference pages and writes the contract schema's generated definitions.
"""

from __future__ import annotations

import importlib
import warnings
from typing import TYPE_CHECKING, Any

from ._version import __version__

if TYPE_CHECKING:
    from .check.diff import DiffResult, diff_contracts
    from .check.pipeline import CompatibilityResult
    from .compare.compatibility import CompatItem
    from .compare.drift import DriftItem
    from .compare.options import ComparisonOptions
    from .errors import (
        CaptureFormatError,
        ContractError,
        ExecutableNotFound,
        LifecycleTransitionFailed,
        NoNodeCreated,
        RmwIntrospectError,
        SetupError,
        StimulusFailed,
        TargetConfigError,
        TargetError,
        TargetExited,
        TargetNotStopped,
        TargetTimeout,
    )
    from .model.capture import Capture
    from .model.capture_file import Endpoint, RawNode, VirtualTime
    from .model.capture_view import Interface, Node
    from .model.contract import Contract
    from .model.contract import load as load_contract
    from .model.parameters import Lifecycle, Parameter, ParameterRange, Probe, Transition
    from .model.types import Constant, Field, MessageType, ServiceType
    from .model.vocabulary import Severity
    from .plugin.assertions import check_compatible
    from .run.api import capture
    from .run.target import TargetSpec

#: public name → (module, attribute). Imported on first use: importing the package (which every
#: `rmw-introspect` command and the pytest plugin do first) stays cheap, and nothing here pulls
#: in pytest (``check_compatible``) or the whole pipeline until it is used. Measured with
#: `python -X importtime`: eager imports made `rmw-introspect --help` ~60 ms slower.
_LAZY: dict[str, tuple[str, str]] = {
    "CompatibilityResult": ("check.pipeline", "CompatibilityResult"),
    "DiffResult": ("check.diff", "DiffResult"),
    "diff_contracts": ("check.diff", "diff_contracts"),
    "DriftItem": ("compare.drift", "DriftItem"),
    "ComparisonOptions": ("compare.options", "ComparisonOptions"),
    "CompatItem": ("compare.compatibility", "CompatItem"),
    "Capture": ("model.capture", "Capture"),
    "Endpoint": ("model.capture_file", "Endpoint"),
    "Interface": ("model.capture_view", "Interface"),
    "Node": ("model.capture_view", "Node"),
    "RawNode": ("model.capture_file", "RawNode"),
    "VirtualTime": ("model.capture_file", "VirtualTime"),
    "Contract": ("model.contract", "Contract"),
    "load_contract": ("model.contract", "load"),
    **{name: ("model.parameters", name) for name in ("Lifecycle", "Parameter", "ParameterRange", "Probe", "Transition")},
    **{name: ("model.types", name) for name in ("Constant", "Field", "MessageType", "ServiceType")},
    "Severity": ("model.vocabulary", "Severity"),
    "check_compatible": ("plugin.assertions", "check_compatible"),
    "capture": ("run.api", "capture"),
    "TargetSpec": ("run.target", "TargetSpec"),
    **{name: ("errors", name) for name in (
        "CaptureFormatError", "ContractError", "ExecutableNotFound", "LifecycleTransitionFailed", "NoNodeCreated",
        "RmwIntrospectError", "SetupError", "StimulusFailed", "TargetConfigError", "TargetError", "TargetExited",
        "TargetNotStopped", "TargetTimeout")},
}


#: deprecated public name → the name that replaced it (still importable, with a DeprecationWarning)
_DEPRECATED: dict[str, str] = {
    "SystemResult": "CompatibilityResult",  # "system" means system contracts (launch files) now
}


def __getattr__(name: str) -> Any:
    if name in _DEPRECATED:
        new = _DEPRECATED[name]
        warnings.warn(f"pytest_rmw_introspect.{name} is deprecated: use pytest_rmw_introspect.{new}",
                      DeprecationWarning, stacklevel=2)
        return __getattr__(new)
    if name not in _LAZY:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    module, attribute = _LAZY[name]
    value = getattr(importlib.import_module(f".{module}", __name__), attribute)
    globals()[name] = value  # later lookups skip __getattr__
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_LAZY))


__all__ = [
    "Capture",
    "CaptureFormatError",
    "CompatItem",
    "CompatibilityResult",
    "ComparisonOptions",
    "Constant",
    "Contract",
    "ContractError",
    "DiffResult",
    "DriftItem",
    "Endpoint",
    "ExecutableNotFound",
    "Field",
    "Interface",
    "Lifecycle",
    "LifecycleTransitionFailed",
    "MessageType",
    "NoNodeCreated",
    "Node",
    "Parameter",
    "ParameterRange",
    "Probe",
    "RawNode",
    "RmwIntrospectError",
    "Severity",
    "ServiceType",
    "SetupError",
    "StimulusFailed",
    "TargetConfigError",
    "TargetError",
    "TargetExited",
    "TargetNotStopped",
    "TargetSpec",
    "TargetTimeout",
    "Transition",
    "VirtualTime",
    "__version__",
    "capture",
    "check_compatible",
    "diff_contracts",
    "load_contract",
]
