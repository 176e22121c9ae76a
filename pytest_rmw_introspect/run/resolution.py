"""How a target is started: :func:`resolve` turns a :class:`~.target.TargetSpec` into a
:class:`ResolvedTarget` (command line, complete environment with the middleware's activation,
working directory, warm or cold start and why), the one value the runner starts."""

from __future__ import annotations

import os
from collections.abc import Mapping
from dataclasses import dataclass, replace
from pathlib import Path
from types import MappingProxyType

from ..errors import ExecutableNotFound
from . import middleware, ros_env
from .executables import build_argv, command_as_typed
from .target import TargetSpec
from .warm.plan import Plan, plan

#: the directory of a capture's files that rcl's log files go to (``ROS_LOG_DIR``)
LOG_DIR = "ros_log"
#: the capture file of each process (the middleware substitutes the process id: every ROS
#: process of the target writes its own file)
OUTPUT_PATTERN = "capture.<pid>.json"


def environment(
    spec: TargetSpec,
    library: Path,
    ros: ros_env.RosEnvironment,
    output: Path,
    base: Mapping[str, str] | None = None,
) -> dict[str, str]:
    """The complete environment of the target process; ``output`` may contain ``<pid>``, which
    the middleware replaces with each process's id. rcl's log files of the capture go to
    ``ros_log`` beside ``output`` (``ROS_LOG_DIR``), unless the environment or the target's
    ``env`` says where logs go (``ROS_LOG_DIR`` or ``ROS_HOME``)."""
    env = dict(os.environ if base is None else base)
    # the target's own variables first, then the activation merged with them: a target's
    # LD_PRELOAD, LD_LIBRARY_PATH or AMENT_PREFIX_PATH extends the middleware's, never drops it
    env.update(spec.env)
    if "ROS_LOG_DIR" not in env and "ROS_HOME" not in env:
        # A capture is an analysis of the node, not a run of it: its log file (one per process,
        # as `ros2 run` writes) is removed with the capture's files instead of piling up in
        # ~/.ros/log, a file per capture and CI run; RMW_INTROSPECT_KEEP_FILES keeps it.
        env["ROS_LOG_DIR"] = str(Path(output).parent / LOG_DIR)
    env.update(ros_env.activation_env(library, ros, base=env))
    env["RMW_INTROSPECT_OUTPUT"] = str(output)
    env["RMW_INTROSPECT_FORMAT"] = "json"
    env["RMW_INTROSPECT_EXIT"] = "1"
    env["RMW_INTROSPECT_AUTO_EXPORT"] = "1"
    env["RMW_INTROSPECT_SETTLE_MS"] = str(max(0, round(spec.effective_settle() * 1000)))
    env["RMW_INTROSPECT_HORIZON_MS"] = str(max(0, round(spec.effective_horizon() * 1000)))
    env["RMW_INTROSPECT_LIFECYCLE"] = spec.effective_lifecycle()
    env["RMW_INTROSPECT_PARAMETERS"] = "1" if spec.effective_read_parameters() else "0"
    if spec.stimuli:
        env["RMW_INTROSPECT_STIMULI"] = ",".join(spec.stimuli)
    env.setdefault("PYTHONUNBUFFERED", "1")
    # numpy's OpenBLAS (rclpy imports numpy) starts a worker thread per core that spins for 2^28
    # cycles before it sleeps: ~40 ms of a core, at the start of every cold Python target, during
    # which the middleware cannot prove the process idle. 2^4 cycles: they sleep at once. (A warm
    # child has no such threads: its server loaded OpenBLAS single-threaded.)
    env.setdefault("OPENBLAS_THREAD_TIMEOUT", "4")
    return env


@dataclass(frozen=True)
class ResolvedTarget:
    """A target resolved into what the runner starts (:func:`resolve`): everything the runner
    needs to start it, wait for it and word its errors, so that it asks the spec nothing more.
    Frozen, its mappings read-only."""

    #: a short name for messages (``TargetSpec.describe``)
    name: str
    #: where each of its processes writes its capture file (``<pid>``: the process id)
    output: Path
    #: the full command line
    argv: tuple[str, ...]
    #: the command line as messages show it (:func:`command_as_typed`: a console script as itself)
    shown_argv: tuple[str, ...]
    #: the complete environment of the process (:func:`environment`)
    env: Mapping[str, str]
    #: its working directory (None: the runner's)
    cwd: Path | None
    #: seconds to wait for it before it is stopped
    timeout: float
    #: the lifecycle state the middleware drives lifecycle nodes to
    lifecycle: str
    #: the topics and services the middleware sends a default message or request to
    stimuli: tuple[str, ...]
    #: how it starts warm (forked from a warm start server); None: it starts cold
    warm: Plan | None
    #: why it starts cold (None: it starts warm)
    cold_because: str | None
    #: the module of a ``module`` target and the target's own ``env:`` (where ``python -m``
    #: finds it: asked only when it created no node)
    module: str | None
    own_env: Mapping[str, str]
    #: the ament prefixes its executables and packages were looked up in
    prefixes: tuple[Path, ...]
    #: the ROS 2 distribution it runs on (None: not known)
    ros_distribution: str | None

    @property
    def how(self) -> str:
        """``warm`` or ``cold``."""
        return "cold" if self.warm is None else "warm"

    def started_cold(self, because: str) -> ResolvedTarget:
        """The same target, started cold ``because`` (a warm start that failed)."""
        return replace(self, warm=None, cold_because=because)


def resolve(
    spec: TargetSpec,
    *,
    workdir: Path,
    library: str | Path | None = None,
    ros: ros_env.RosEnvironment | None = None,
    python: str | None = None,
    cold_note: str | None = None,
) -> ResolvedTarget:
    """Resolve ``spec`` into what the runner starts, its capture files in ``workdir``
    (:data:`OUTPUT_PATTERN`) and its log files beside them. ``library``: the middleware library (default: ``middleware.ensure_library``);
    ``ros``: the ROS environment (default: ``ros_env.detect()``); ``python``: the interpreter of
    Python targets (default: this one); ``cold_note``: start it cold, for this reason, without
    asking whether it could start warm. Raises :class:`TargetConfigError` for a spec that names
    no target (or two), :class:`ExecutableNotFound` for one that cannot be found."""
    spec.validate()
    ros = ros or ros_env.detect()
    if library is None:
        library = middleware.ensure_library(ros)
    # like `ros2 run`: AMENT_PREFIX_PATH as it is now, then the prefixes of the detected install
    prefixes = ros_env.ament_prefixes(tuple(getattr(ros, "ament_prefixes", ())))
    argv = build_argv(spec, prefixes, python=python)
    output = workdir / OUTPUT_PATTERN
    env = environment(spec, Path(library), ros, output)
    describe = spec.describe()
    if spec.cwd is not None and not spec.cwd.is_dir():
        raise ExecutableNotFound(f"Working directory {spec.cwd} of target {describe} does not exist.", target=describe)
    warm: Plan | None = None
    because = cold_note
    if because is None:
        because = "cold_start asked for it" if spec.cold_start else None
    if because is None:
        how = plan(argv, env, python)
        if isinstance(how, Plan):
            warm = how
        else:
            because = how
    return ResolvedTarget(
        name=describe,
        output=output,
        argv=tuple(argv),
        shown_argv=tuple(command_as_typed(argv)),
        env=MappingProxyType(env),
        cwd=spec.cwd,
        timeout=spec.effective_timeout(),
        lifecycle=spec.effective_lifecycle(),
        stimuli=spec.stimuli,
        warm=warm,
        cold_because=because,
        module=spec.module,
        own_env=MappingProxyType(dict(spec.env)),
        prefixes=tuple(prefixes),
        ros_distribution=getattr(ros, "distro", None),
    )
