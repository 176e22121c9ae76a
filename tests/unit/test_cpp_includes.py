"""The middleware's C++ includes point down (issue 41 item 4): each file of
``rmw_introspect_cpp/src`` includes only the ``detail/`` headers of its own module and of the
modules in the layers below its own, in the one order written here. A module is a ``detail/``
header with its ``.cpp``; the entry points (``src/*.cpp``) are the top layer."""

from __future__ import annotations

import re
from pathlib import Path

SRC = Path(__file__).resolve().parents[2] / "rmw_introspect_cpp" / "src"

#: The layers, lowest first: a module may include the modules of the layers before its own.
LAYERS: list[tuple[str, set[str]]] = [
    ("leaves: clocks, identity, plain values, the wait hub, the thread census, logging",
     {"clock", "dynamic_value", "identifier", "inbox", "json_writer", "log", "message_layout",
      "node_probe", "qos", "real_sleep", "rmw_api", "thread_census", "thread_marks", "wait_hub"}),
    ("the introspection traits, handle checks, graph guards, the Session's parts, python",
     {"common", "graph_guards", "idle_proof", "introspection", "probing", "python"}),
    ("messages in memory, type descriptions", {"members", "type_description"}),
    ("the recorder, type supports resolved", {"recorder", "typesupport"}),
    ("CDR, message walking, the prober, stimuli, component loads, rendered types",
     {"cdr", "component_loads", "message_walker", "prober", "stimuli", "type_text_cache"}),
    ("configuration, content filters", {"config", "content_filter"}),
    ("the capture writer, a subscription's filter", {"capture_writer", "subscription_filter"}),
    ("rcl's handles, the warp", {"handles", "warp"}),
    ("the injector, the Session", {"injector", "session"}),
    ("in-process delivery, the probe driver", {"delivery", "probe_driver"}),
    ("the Runtime", {"runtime"}),
    ("what the entry points share, the interposed sleeps", {"endpoint_common", "sleep"}),
    ("the entry points (src/*.cpp)", {"entry"}),
]

INCLUDE = re.compile(r'^#include "detail/([a-z_]+)\.hpp"', re.MULTILINE)


def _module(path: Path) -> str:
    return path.stem if path.parent.name == "detail" else "entry"


def _level() -> dict[str, int]:
    level: dict[str, int] = {}
    for index, (_, modules) in enumerate(LAYERS):
        for module in modules:
            assert module not in level, f"{module} is in two layers"
            level[module] = index
    return level


def _includes() -> list[tuple[Path, str]]:
    files = sorted((SRC / "detail").glob("*.[ch]pp")) + sorted(SRC.glob("*.cpp"))
    return [(path, header) for path in files for header in INCLUDE.findall(path.read_text())]


def test_every_module_has_a_layer():
    level = _level()
    modules = {_module(path) for path in (SRC / "detail").glob("*.[ch]pp")} | {"entry"}
    assert sorted(modules - set(level)) == [], "add the new modules to a layer of LAYERS"
    assert sorted(set(level) - modules) == [], "modules of LAYERS that no longer exist"


def test_includes_point_only_down():
    level = _level()
    upward = []
    for path, header in _includes():
        module = _module(path)
        if header != module and level[header] >= level[module]:
            upward.append((path.name, header))
    assert upward == [], f"includes of a header of the same or a higher layer (move the shared part down): {upward}"


def test_the_order_catches_an_include_that_points_up():
    """The rule itself: the named case of issue 41 (the introspection traits reaching up to the
    type supports for MessageLayout) would be caught."""
    level = _level()
    assert level["typesupport"] > level["introspection"]
    assert level["sleep"] > level["python"]
