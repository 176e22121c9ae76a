"""``composition_interfaces`` for reading Python launch files where it cannot be imported.

launch_ros imports ``composition_interfaces.srv`` (in ``actions/load_composable_nodes.py``) to
build the LoadNode request of each composable node. That package is a message package built
with CMake: there is no wheel of it on PyPI, so a venv with the ROS 2 wheels and the launch
packages that ``rmw-introspect install-launch`` installs (pure Python) has none. Reading a launch
file only builds the requests (``get_composable_node_load_request``) and never sends them, so a
request needs its fields and nothing else: :func:`imported_with_stand_in` imports launch_ros with
this module's ``LoadNode`` (the fields of composition_interfaces/srv/LoadNode.srv, Jazzy and
Kilted alike) in place of the real package, and takes the stand-in out of ``sys.modules`` again,
so nothing else in the process sees it (``import composition_interfaces`` still fails as before).
A real package, where there is one (a standard install, the overlay), is always used instead.
"""

from __future__ import annotations

import contextlib
import importlib.util
import sys
from collections.abc import Iterator
from types import ModuleType
from typing import Any


class _Message:
    """A message of plain attributes with the defaults of its fields (no type support: it is
    never sent)."""

    FIELDS: dict[str, Any] = {}

    def __init__(self, **values: Any) -> None:
        for name, default in self.FIELDS.items():
            setattr(self, name, values.pop(name, list(default) if isinstance(default, list) else default))
        if values:
            raise TypeError(f"{type(self).__name__}: unknown field(s) {', '.join(sorted(values))}")

    def __repr__(self) -> str:
        return f"{type(self).__name__}({', '.join(f'{k}={getattr(self, k)!r}' for k in self.FIELDS)})"


class LoadNode:
    """composition_interfaces/srv/LoadNode (the request and response fields only)."""

    class Request(_Message):
        FIELDS = {"package_name": "", "plugin_name": "", "node_name": "", "node_namespace": "", "log_level": 0,
                  "remap_rules": [], "parameters": [], "extra_arguments": []}

    class Response(_Message):
        FIELDS = {"success": False, "error_message": "", "full_node_name": "", "unique_id": 0}


def _stand_in() -> dict[str, ModuleType]:
    package = ModuleType("composition_interfaces", "stand-in of pytest_rmw_introspect.launch.composition_stand_in")
    srv = ModuleType("composition_interfaces.srv")
    srv.LoadNode = LoadNode  # type: ignore[attr-defined]
    package.srv = srv  # type: ignore[attr-defined]
    package.__path__ = []  # a package, so that `import composition_interfaces.srv` finds srv in sys.modules
    return {"composition_interfaces": package, "composition_interfaces.srv": srv}


def needed() -> bool:
    """Whether this Python environment lacks composition_interfaces."""
    return "composition_interfaces" not in sys.modules and importlib.util.find_spec("composition_interfaces") is None


@contextlib.contextmanager
def imported_with_stand_in() -> Iterator[None]:
    """While in force, and only when the real package is missing: ``import
    composition_interfaces.srv`` gives the stand-in (import launch_ros inside)."""
    if not needed():
        yield
        return
    modules = _stand_in()
    sys.modules.update(modules)
    try:
        yield
    finally:
        for name, module in modules.items():
            if sys.modules.get(name) is module:
                del sys.modules[name]
