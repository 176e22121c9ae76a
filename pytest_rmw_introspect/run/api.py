"""The library's one-call capture: ``pytest_rmw_introspect.capture(script="talker.py")`` builds a
:class:`~pytest_rmw_introspect.run.target.TargetSpec` from keyword arguments and runs it
(:func:`pytest_rmw_introspect.run.runner.run`). Apart from the runner so that the capture model is
imported here, at module level (``typing.get_type_hints`` of the public function resolves), while
the runner imports it only once its first target is starting."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

from ..model.capture import Capture
from .ros_env import RosEnvironment
from .runner import run
from .target import TargetSpec


def capture(
    target: TargetSpec | Mapping[str, Any] | None = None,
    *,
    include_infrastructure: bool = False,
    library: str | Path | None = None,
    ros: RosEnvironment | None = None,
    base_dir: str | Path | None = None,
    keep_files: bool | None = None,
    **options: Any,
) -> Capture:
    """Capture the interfaces of a target: the library function behind ``pytest_rmw_introspect.capture``.

    Give the target as keyword arguments (the keys of :mod:`pytest_rmw_introspect.run.target`:
    ``package``/``executable``, ``command``, ``script``, ``module``, ``arguments``,
    ``namespace``, ``node_name``, ``remappings``, ``parameters``, ``params_file``, ``env``,
    ``cwd``, ``settle``, ``timeout``, ``horizon``, ``lifecycle``, ``read_parameters``, ``stimuli``), as a
    mapping, or as a :class:`TargetSpec`; keyword
    arguments override the mapping. Relative paths are relative to ``base_dir`` (default:
    the current directory).

    >>> cap = capture(script="talker.py", namespace="/robot1")   # doctest: +SKIP
    >>> cap["/robot1/talker"].publishers[0].name                 # doctest: +SKIP
    '/robot1/chatter'

    Raises :class:`~pytest_rmw_introspect.errors.SetupError` when ROS 2 or the middleware is
    missing and a :class:`~pytest_rmw_introspect.errors.TargetError` when the target fails (a
    :class:`~pytest_rmw_introspect.errors.LifecycleTransitionFailed` when a lifecycle node
    fails a transition the capture drives).
    """
    base = Path(base_dir) if base_dir is not None else Path.cwd()
    if isinstance(target, TargetSpec):
        spec = target
    else:
        spec = TargetSpec.from_mapping(target or {}, base_dir=base, source="capture()")
    if options:
        spec = spec.merged(options, base_dir=base, source="capture()")
    return run(spec, library=library, ros=ros, include_infrastructure=include_infrastructure, keep_files=keep_files)
