"""Helpers of the warm start tests: capture a target cold and warm, and what a comparison looks at."""

from __future__ import annotations

import copy
import json
import os
import re
import time
from pathlib import Path
from typing import Any

from pytest_rmw_introspect.errors import TargetError
from pytest_rmw_introspect.model.capture import Capture
from pytest_rmw_introspect.run import middleware, prewarm, resolution, ros_env, runner
from pytest_rmw_introspect.run.target import TargetSpec
from pytest_rmw_introspect.run.warm import client as warm

HERE = Path(__file__).resolve().parent
REPO = HERE.parents[1]
NODES = HERE / "nodes"
PLUGIN_NODES = REPO / "tests" / "plugin" / "nodes"
WARM_NODES = HERE / "nodes_warm"
EXAMPLES = "rmw_introspect_examples"

#: capture fields that measure time or name the process: they differ between any two runs
#: (and ``quiescence``: how each settle ended, by detection or by the quiet window, says how the
#: capture was taken, not what it found; :func:`outcome` keeps it beside the capture)
VOLATILE = frozenset({"pid", "argv", "time_to_settle_ms", "elapsed_ms", "created_virtual_ms", "created_real_ms",
                      "destroyed_virtual_ms", "destroyed_real_ms", "time", "activity_calls", "quiescence"})


def example_executables() -> list[str]:
    ros = ros_env.detect()
    for prefix in ros.ament_prefixes:
        lib = Path(prefix) / "lib" / EXAMPLES
        if lib.is_dir():
            return sorted(p.name for p in lib.iterdir() if p.is_file() and os.access(p, os.X_OK))
    return []


def scrub(value: Any) -> Any:
    """A capture document without the fields that differ between any two runs."""
    if isinstance(value, dict):
        return {k: scrub(v) for k, v in value.items() if k not in VOLATILE}
    if isinstance(value, list):
        return [scrub(v) for v in value]
    return value


def _destruction_marked(value: Any) -> Any:
    """The contract view with each ``destroyed_at`` age as ``"destroyed"``: a virtual age at
    destruction counts from start-up, whose real time differs between runs (warm or cold) by
    more than its 0.1 s resolution; that something was destroyed must agree."""
    if isinstance(value, dict):
        return {k: "destroyed" if k == "destroyed_at" else _destruction_marked(v) for k, v in value.items()}
    if isinstance(value, list):
        return [_destruction_marked(v) for v in value]
    return value


def interface(cap: Capture | None) -> dict[str, Any] | None:
    """What a capture says about the program: every node and endpoint as created (names, types,
    type hashes, type supports, QoS, creation order, destruction, ``created_in``), each node's
    ``parameters``, ``parameters_error`` and ``lifecycle``, the contract view with
    infrastructure, the command line, the notes and the rest of the document (``types``,
    ``probe``, state, settle)."""
    if cap is None:
        return None
    raw = scrub(dict(cap.raw))
    entities = {"nodes": raw.pop("nodes", []), "endpoints": raw.pop("endpoints", [])}
    return {
        "entities": entities,
        "contract": _destruction_marked(cap.with_infrastructure(True).to_contract_nodes()),
        "argv": list(cap.argv),
        "rest": raw,  # state, settle_ms, settled_by, ever_waited, ended, future fields
        "notes": [re.sub(r"\d+(\.\d+)?", "#", note) for note in cap.notes()],  # numbers measure time
    }


def outcome(spec: TargetSpec, **kwargs: Any) -> dict[str, Any]:
    """The outcome of a capture as data: the capture's :func:`interface`, or the error's kind,
    status, the last line of stderr and the partial capture's interface. ``started`` says how."""
    t0 = time.monotonic()
    try:
        cap = runner.run(spec, **kwargs)
    except TargetError as exc:
        partial = getattr(exc, "partial", None)
        stderr = (getattr(exc, "stderr_tail", "") or "").strip().splitlines()
        return {"error": type(exc).__name__, "status": getattr(exc, "status", None),
                "stderr_last": stderr[-1] if stderr else "", "capture": interface(partial),
                "started": exc.started, "wall": time.monotonic() - t0}
    return {"error": None, "returncode": cap.returncode, "capture": interface(cap), "started": cap.started,
            "start_note": cap.start_note, "wall": time.monotonic() - t0, "pid": cap.pid,
            "quiescence": cap.raw.get("quiescence")}


def comparable(result: dict[str, Any]) -> dict[str, Any]:
    kept = {k: v for k, v in result.items() if k not in ("started", "start_note", "wall", "pid", "quiescence")}
    return _names_as_patterns(kept)


def _names_as_patterns(value: dict[str, Any]) -> dict[str, Any]:
    """``value`` with every node name that changes every run (a program that names itself anew,
    tests/middleware/nodes/anonymous_talker.py) written as its pattern, as a contract writes it
    (``model.unstable_names``): two runs of such a program are compared like two checks of it."""
    from pytest_rmw_introspect.model.unstable_names import recognise

    text = json.dumps(value, sort_keys=True, default=str)
    for name in sorted(set(re.findall(r'"(/[^"\s]*)"', text)), key=len, reverse=True):
        found = recognise(name)
        if found is not None:  # the name, the names under it, and the node's own base name
            text = text.replace(f'"{name.rsplit("/", 1)[1]}"', f'"{found.pattern.rsplit("/", 1)[1]}"')
            text = text.replace(name, found.pattern)
    folded: dict[str, Any] = json.loads(text)
    return folded


def cold_and_warm(spec_options: dict[str, Any], base_dir: Path | None = None) -> tuple[dict, dict]:
    """Capture the target cold, then warm (waiting for the server), with the same options."""
    spec = TargetSpec.from_mapping(spec_options, base_dir=base_dir)
    cold = outcome(spec.merged({"cold_start": True}))
    warm_result = outcome(spec, warm_wait=60.0)
    return cold, warm_result


def server_for(spec_options: dict[str, Any] | None = None) -> warm.WarmServer:
    """The (ready) warm start server for targets with these options."""
    spec = TargetSpec.from_mapping(spec_options or {})
    reason = prewarm.warm_up(spec, wait=60.0)
    assert reason is None, reason
    library = middleware.ensure_library()
    env = resolution.environment(spec, Path(library), ros_env.detect(), Path("/unused"))
    server = warm.POOL.server(env, str(spec.cwd or os.getcwd()), wait=60.0)
    assert isinstance(server, warm.WarmServer), server
    return server




# ---------------------------------------------------------------------------- equivalence targets

#: options per target where the defaults would only cost time (a target that never settles)
EQUIVALENCE_OPTIONS = {
    "hanging_node.py": {"timeout": 3},
    # creates its publisher 0.3 s of *real* time (a thread's time.sleep) after start: with
    # the default settle both captures may end before or after it, whichever way started
    "guard_wake.py": {"settle": 1.0},
    # its main thread waits 0.3 s twice on the real clock while a thread is parked in rmw_wait
    # (issue 50 item 1): detection waits for it, the default window alone (0.1 s) does not; with
    # a 1 s window both captures hold everything it creates
    "parked_then_sleep.py": {"settle": 1.0},
    # 10 000 jumps in the default 10 s horizon take about the warp's real-time budget
    # (3 s) here: whether a capture notes that virtual time stopped early was timing
    # (cold or warm alike). 100 s is ten times what the budget allows on any machine
    # here: both stop early, and their notes are compared
    "vt_1khz.py": {"horizon": 100},
    # blocked in on_configure forever: fails alike, the sooner the better
    "stuck_on_configure.py": {"timeout": 3},
    # reading 15 000 parameters back costs seconds and says nothing about warm or cold starts
    "many_parameters.py": {"read_parameters": False},
}
#: capture fields that depend on timing alone for a target, left out of its comparison: a 1 kHz
#: timer keeps running in real time after the warp, so at its final settle its executor is as
#: likely inside rmw_wait ("wait") as in the callback ("activity"), cold or warm alike
TIMING_FIELDS = {"vt_1khz.py": ("settled_by",)}


def equivalence_targets() -> list[tuple[str, dict]]:
    """Every example executable and every end-to-end test node, as (label, target options):
    what two ways of capturing must agree on (warm and cold starts; detected quiescence and the
    quiet window)."""
    out: list[tuple[str, dict]] = []
    for exe in example_executables():
        out.append((f"{EXAMPLES}/{exe}", {"package": EXAMPLES, "executable": exe}))
    for label, directory in (("middleware", NODES), ("plugin", PLUGIN_NODES)):
        for script in sorted(directory.glob("*.py")):
            out.append((f"{label}/{script.name}", {"script": str(script), **EQUIVALENCE_OPTIONS.get(script.name, {})}))
    return out


#: targets whose threads create endpoints at once (a multi-threaded executor's callback groups): the
#: order of their endpoints, and so their ids, differs from run to run, cold or warm (seen on Kilted)
CONCURRENT_CREATION = {"vt_mt_groups.py"}


def _unordered_endpoints(value: Any) -> Any:
    """``value`` with every ``endpoints`` list in one order, without their creation ids and sequence numbers."""
    if isinstance(value, dict):
        out = {k: _unordered_endpoints(v) for k, v in value.items()}
        if isinstance(out.get("endpoints"), list):
            out["endpoints"] = sorted(({k: v for k, v in e.items() if k not in ("id", "seq")} if isinstance(e, dict) else e
                                       for e in out["endpoints"]), key=lambda e: json.dumps(e, sort_keys=True))
        return out
    if isinstance(value, list):
        return [_unordered_endpoints(v) for v in value]
    return value


def comparable_for(result: dict[str, Any], options: dict[str, Any]) -> dict[str, Any]:
    """:func:`comparable`, without the target's :data:`TIMING_FIELDS` (and, for a target of
    :data:`CONCURRENT_CREATION`, with its endpoints in no particular order)."""
    out = comparable(result)
    if Path(str(options.get("script", ""))).name in CONCURRENT_CREATION:
        out = _unordered_endpoints(out)
    fields = TIMING_FIELDS.get(Path(str(options.get("script", ""))).name, ())
    if fields and out.get("capture") is not None:
        out = copy.deepcopy(out)
        for field in fields:
            out["capture"]["rest"].pop(field, None)
    return out
