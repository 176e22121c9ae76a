"""Helpers of the middleware tests: spawning processes on the middleware, expected captures."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import jsonschema
import yaml

from pytest_rmw_introspect.model import tally
from pytest_rmw_introspect.run import ros_env

REPO = Path(__file__).resolve().parents[2]
NODES = Path(__file__).resolve().parent / "nodes"
SCHEMA = REPO / "rmw_introspect_cpp" / "schema" / "capture.schema.json"
PYTHON = sys.executable


# ----------------------------------------------------------------------------- environment
# The ROS install comes from the package's own detection, so these tests run where users do.
def ament_prefixes() -> list[Path]:
    return list(ros_env.detect().ament_prefixes)


def ament_prefix_path() -> str:
    return os.pathsep.join(str(p) for p in ament_prefixes())


def library_dirs() -> list[str]:
    return [str(d) for d in ros_env.detect().library_dirs]


def ros_environment(extra: dict | None = None) -> dict:
    env = dict(os.environ)
    env["AMENT_PREFIX_PATH"] = ament_prefix_path()
    env["LD_LIBRARY_PATH"] = os.pathsep.join(library_dirs() + [p for p in env.get("LD_LIBRARY_PATH", "").split(os.pathsep) if p])
    for key in list(env):
        if key.startswith("RMW_INTROSPECT_"):
            del env[key]
    env.pop("LD_PRELOAD", None)
    env["ROS_DOMAIN_ID"] = env.get("ROS_DOMAIN_ID", "77")
    env["PYTHONUNBUFFERED"] = "1"
    if extra:
        env.update(extra)
    return env


# ----------------------------------------------------------------------------- running
@dataclass
class Run:
    returncode: int | None
    stdout: str
    stderr: str
    path: Path
    wall_s: float
    pid: int
    capture: dict | None = None
    raw: str = ""

    def __str__(self) -> str:
        return f"rc={self.returncode} wall={self.wall_s:.3f}s\n--- stdout\n{self.stdout}\n--- stderr\n{self.stderr}"


def load_capture(path: Path, fmt: str = "json") -> dict | None:
    if not path.exists():
        return None
    text = path.read_text()
    data = yaml.safe_load(text) if fmt == "yaml" else json.loads(text)
    jsonschema.validate(data, json.loads(SCHEMA.read_text()))
    return data


def run_on_middleware(library: Path, argv, tmp_path: Path, *, env: dict | None = None,
                      exit_on_settle: bool = True, settle_ms: int | None = None,
                      timeout: float = 30.0, fmt: str = "json", output: Path | None = None) -> Run:
    path = output or tmp_path / f"capture_{time.monotonic_ns()}.{fmt}"
    extra = {"LD_PRELOAD": str(library), "RMW_INTROSPECT_OUTPUT": str(path),
             "RMW_INTROSPECT_EXIT": "1" if exit_on_settle else "0"}
    if settle_ms is not None:
        extra["RMW_INTROSPECT_SETTLE_MS"] = str(settle_ms)
    if fmt != "json":
        extra["RMW_INTROSPECT_FORMAT"] = fmt
    extra.update(env or {})
    argv = [str(a) for a in argv]
    t0 = time.monotonic()
    tally.note("start", "direct")  # make test-cost (tests/support/cost_report.py)
    proc = subprocess.Popen(argv, env=ros_environment(extra), stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    try:
        out, err = proc.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        proc.send_signal(signal.SIGKILL)
        out, err = proc.communicate()
        err += f"\n[test harness: killed after {timeout}s]"
    wall = time.monotonic() - t0
    result = Run(proc.returncode, out, err, path, wall, proc.pid)
    result.capture = load_capture(path, fmt)
    result.raw = path.read_text() if path.exists() else ""
    return result


def python_node(name: str, *args) -> list[str]:
    return [PYTHON, str(NODES / name), *args]


# ----------------------------------------------------------------------------- expectations
@lru_cache(maxsize=None)
def type_hash(type_name: str) -> str:
    """The RIHS01 hash of `pkg/kind/Name` from the package's own type description JSON."""
    pkg, kind, name = type_name.split("/")
    candidates = [name]
    if "_" in name:
        candidates.append(name.split("_")[0])
    for prefix in ament_prefixes():
        for candidate in candidates:
            path = prefix / "share" / pkg / kind / f"{candidate}.json"
            if path.exists():
                for entry in json.loads(path.read_text())["type_hashes"]:
                    if entry["type_name"] == type_name:
                        return entry["hash_string"]
    raise LookupError(f"no type description for {type_name}")


def qos(history="KEEP_LAST", depth=10, reliability="RELIABLE", durability="VOLATILE",
        liveliness="SYSTEM_DEFAULT", deadline_ns=0, lifespan_ns=0, lease_ns=0, avoid=False) -> dict:
    return {"history": history, "depth": depth, "reliability": reliability,
            "durability": durability, "liveliness": liveliness, "deadline_ns": deadline_ns,
            "lifespan_ns": lifespan_ns, "liveliness_lease_duration_ns": lease_ns,
            "avoid_ros_namespace_conventions": avoid}


QOS_DEFAULT = qos()
QOS_SERVICES = qos()
QOS_PARAMETERS = qos(depth=1000)
QOS_ROSOUT = qos(depth=1000, durability="TRANSIENT_LOCAL", lifespan_ns=10_000_000_000)
QOS_SENSOR = qos(depth=5, reliability="BEST_EFFORT")
QOS_ACTION_STATUS = qos(depth=1, durability="TRANSIENT_LOCAL")


def ep(kind, node, name, type_name, qos_profile=QOS_DEFAULT, destroyed=False,
       typesupport="rosidl_typesupport_c") -> dict:
    return {"kind": kind, "node": node, "name": name, "type": type_name,
            "type_hash": type_hash(type_name), "typesupport": typesupport,
            "qos": qos_profile, "destroyed": destroyed}


PARAMETER_SERVICES = [
    ("describe_parameters", "rcl_interfaces/srv/DescribeParameters"),
    ("get_parameters", "rcl_interfaces/srv/GetParameters"),
    ("get_parameter_types", "rcl_interfaces/srv/GetParameterTypes"),
    ("list_parameters", "rcl_interfaces/srv/ListParameters"),
    ("set_parameters", "rcl_interfaces/srv/SetParameters"),
    ("set_parameters_atomically", "rcl_interfaces/srv/SetParametersAtomically"),
]


def rclpy_node_infrastructure(fqn: str) -> list[dict]:
    """What every rclpy Node creates itself, in order."""
    out = [
        ep("publisher", fqn, "/rosout", "rcl_interfaces/msg/Log", QOS_ROSOUT),
        ep("publisher", fqn, "/parameter_events", "rcl_interfaces/msg/ParameterEvent", QOS_PARAMETERS),
    ]
    out += [ep("service", fqn, f"{fqn}/{suffix}", t, QOS_PARAMETERS) for suffix, t in PARAMETER_SERVICES]
    out.append(ep("service", fqn, f"{fqn}/get_type_description",
                  "type_description_interfaces/srv/GetTypeDescription", QOS_SERVICES))
    return out


def lifecycle_infrastructure(fqn: str) -> list[dict]:
    """What an rclpy LifecycleNode adds to the infrastructure of every node, in order."""
    return [
        ep("publisher", fqn, f"{fqn}/transition_event", "lifecycle_msgs/msg/TransitionEvent"),
        ep("service", fqn, f"{fqn}/change_state", "lifecycle_msgs/srv/ChangeState", QOS_SERVICES),
        ep("service", fqn, f"{fqn}/get_state", "lifecycle_msgs/srv/GetState", QOS_SERVICES),
        ep("service", fqn, f"{fqn}/get_available_states", "lifecycle_msgs/srv/GetAvailableStates",
           QOS_SERVICES),
        ep("service", fqn, f"{fqn}/get_available_transitions",
           "lifecycle_msgs/srv/GetAvailableTransitions", QOS_SERVICES),
        ep("service", fqn, f"{fqn}/get_transition_graph",
           "lifecycle_msgs/srv/GetAvailableTransitions", QOS_SERVICES),
    ]


def node(name: str, namespace: str = "/", destroyed=False, enclave="/") -> dict:
    fqn = "/" + name if namespace == "/" else f"{namespace}/{name}"
    return {"name": name, "namespace": namespace, "fqn": fqn, "enclave": enclave, "destroyed": destroyed}


ENDPOINT_KEYS = ("kind", "node", "name", "type", "type_hash", "typesupport", "qos", "destroyed")
NODE_KEYS = ("name", "namespace", "fqn", "enclave", "destroyed")


def assert_capture(capture: dict, nodes: list[dict], endpoints: list[dict], state: str | None = "settled") -> None:
    """The capture holds exactly these nodes and endpoints, in creation order."""
    assert capture is not None, "no capture was written"
    assert capture["format"] == "rmw_introspect_capture" and capture["format_version"] == 1
    assert capture["rmw_implementation"] == "rmw_introspect_cpp"
    if state is not None:
        assert capture["state"] == state, (capture["state"], state)
    got_nodes = [{k: n[k] for k in NODE_KEYS} for n in capture["nodes"]]
    assert got_nodes == nodes
    got = [{k: e[k] for k in ENDPOINT_KEYS} for e in capture["endpoints"]]
    for i, (g, x) in enumerate(zip(got, endpoints, strict=False)):
        assert g == x, f"endpoint #{i} differs: {g} != {x}"
    assert len(got) == len(endpoints), [(e["kind"], e["name"]) for e in got]
    # One counter over nodes and endpoints, in creation order; node ids match node names.
    seqs = sorted([n["seq"] for n in capture["nodes"]] + [e["seq"] for e in capture["endpoints"]])
    assert seqs == list(range(1, len(seqs) + 1))
    assert [e["seq"] for e in capture["endpoints"]] == sorted(e["seq"] for e in capture["endpoints"])
    by_id = {n["id"]: n["fqn"] for n in capture["nodes"]}
    for e in capture["endpoints"]:
        assert by_id[e["node_id"]] == e["node"]


def assert_settled_process(result: Run) -> None:
    assert result.returncode == 0, str(result)
    assert result.capture is not None, str(result)
    assert result.capture["state"] == "settled"
    assert result.capture["time_to_settle_ms"] is not None
    if not result.capture.get("quiescence", {}).get("detected"):
        # every settle waited for the quiet window (none was detected: docs/design.md)
        assert result.capture["time_to_settle_ms"] >= result.capture["settle_ms"]


def cpu_ticks(pid: int) -> int:
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return int(fields[11]) + int(fields[12])  # utime + stime (fields 14, 15)


# ----------------------------------------------------------------------------- long-running
def spawn(library: Path | None, argv, capture: Path, env: dict | None = None) -> subprocess.Popen:
    """Start a process (on the middleware when `library` is given) and return at once."""
    extra = {"RMW_INTROSPECT_OUTPUT": str(capture)}
    if library is not None:
        extra["LD_PRELOAD"] = str(library)
    extra.update(env or {})
    if library is not None:
        tally.note("start", "direct")  # make test-cost (tests/support/cost_report.py)
    return subprocess.Popen([str(a) for a in argv], env=ros_environment(extra),
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def wait_for(predicate, timeout: float = 20.0, interval: float = 0.02):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        value = predicate()
        if value:
            return value
        time.sleep(interval)
    raise AssertionError(f"condition not met within {timeout}s")


def read_capture_if(path: Path, fmt: str = "json", state: str | None = None):
    try:
        data = load_capture(path, fmt)
    except (ValueError, FileNotFoundError):
        return None
    if data is None or (state is not None and data["state"] != state):
        return None
    return data


def stop(proc: subprocess.Popen, sig=signal.SIGKILL) -> tuple[str, str]:
    if proc.poll() is None:
        proc.send_signal(sig)
    try:
        return proc.communicate(timeout=10)
    except subprocess.TimeoutExpired:
        proc.kill()
        return proc.communicate()
