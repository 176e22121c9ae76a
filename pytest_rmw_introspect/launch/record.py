"""A ``record.json`` written by play_launch's ``dump_launch``: the nodes a launch started, as a list.

``dump_launch`` walks a launch description where ``launch_ros`` is installed and writes every
node it would start: ``package``, ``executable``, ``name``, ``namespace``, ``params``
(``[name, value]`` pairs), ``params_files`` (the files' *contents*), ``remaps``, ``args``,
``ros_args``, ``env`` and the ``cmd`` it built. A record is accepted as a launch source, so a
Python launch file can be dumped once on a machine with ROS 2 and checked anywhere.

The command line is rebuilt from the fields rather than taken from ``cmd`` (which names paths
of the machine that wrote it, temporary parameter files among them): the executable is found
through the ament index like ``ros2 run``; the parameter files' contents are written to
temporary files when the process starts. Containers and composable nodes (``container``,
``load_node``) are :class:`Unsupported`.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from ..errors import InputError, LaunchError
from ..model import untrusted
from ..model.paths import shown
from .entities import MAX_FILE_BYTES, yaml_value
from .result import LaunchedNode, LaunchParameter, LaunchResult, Unsupported, Where


def _fail(path: Path, reason: str) -> LaunchError:
    return LaunchError(f"{shown(path)}: {reason} (expected a record.json written by play_launch's dump_launch: "
                       '{"node": [{"package": ..., "executable": ..., "name": ..., ...}], ...})')


def _pairs(value: Any, path: Path, what: str, index: int) -> list[tuple[str, Any]]:
    if value is None:
        return []
    if not isinstance(value, list) or not all(isinstance(v, (list, tuple)) and len(v) == 2 for v in value):
        raise _fail(path, f"node[{index}].{what} is not a list of [name, value] pairs")
    return [(str(a), b) for a, b in value]


def _value(text: Any, path: Path, index: int) -> Any:
    if not isinstance(text, str):
        return text
    try:
        return yaml_value(text)
    except ValueError as exc:
        raise _fail(path, f"node[{index}].params: {exc}") from None


def _strings(value: Any, path: Path, what: str, index: int) -> tuple[str, ...]:
    if value is None:
        return ()
    if not isinstance(value, list):
        raise _fail(path, f"node[{index}].{what} is not a list of strings")
    return tuple(str(v) for v in value)


def read(path: Path, result: LaunchResult) -> None:
    """The nodes of a record.json into ``result`` (raises LaunchError)."""
    try:
        data = json.loads(untrusted.read_text(path, max_bytes=MAX_FILE_BYTES))
    except (OSError, InputError) as exc:
        raise LaunchError(f"cannot read {shown(path)}: {exc}") from None
    except (json.JSONDecodeError, RecursionError) as exc:
        reason = f"not valid JSON: {exc}" if isinstance(exc, json.JSONDecodeError) else "nested too deep"
        raise _fail(path, reason) from None
    if not isinstance(data, dict) or not isinstance(data.get("node"), list):
        raise _fail(path, "no `node` list")
    result.files.append(path)
    for index, record in enumerate(data["node"]):
        if not isinstance(record, dict) or not record.get("executable"):
            raise _fail(path, f"node[{index}] has no `executable`")
        where = Where(path, None)
        name = record.get("name")
        namespace = record.get("namespace")
        if isinstance(name, str) and name.startswith("/"):
            # a fully qualified name: split it
            prefix, _, name = name.rpartition("/")
            namespace = namespace or prefix or "/"
        parameters = [LaunchParameter(file_text=str(text)) for text in record.get("params_files") or []]
        for key, value in _pairs(record.get("params"), path, "params", index):
            if ":=" in key:  # `name:=value` as launch_ros passes it after -p
                key, _, value = key.partition(":=")
            parameters.append(LaunchParameter(name=key, value=_value(value, path, index)))
        env = {k: str(v) for k, v in _pairs(record.get("env"), path, "env", index)}
        package = record.get("package")
        cmd = record.get("cmd") or []
        executable = str(record["executable"])
        if not package and cmd:
            executable = str(cmd[0])
        result.nodes.append(LaunchedNode(
            executable=executable, package=str(package) if package else None, where=where,
            name=name or None, namespace=namespace if namespace not in (None, "") else None,
            arguments=_strings(record.get("args"), path, "args", index),
            ros_arguments=_strings(record.get("ros_args"), path, "ros_args", index),
            parameters=tuple(parameters),
            remappings=tuple((a, str(b)) for a, b in _pairs(record.get("remaps"), path, "remaps", index)),
            env=env,
        ))
    for what in ("container", "load_node"):
        for index, entry in enumerate(data.get(what) or []):
            label = entry.get("name") or entry.get("node_name") or index if isinstance(entry, dict) else index
            result.unsupported.append(Unsupported(
                Where(path), f"{what}[{index}] ({label}): composable nodes and their containers are not supported"))
