"""Event handlers of Python launch files, with the meaning a capture can give them.

A capture starts every process of a launch at once, lets them settle, and stops them itself at
the end; it never waits for a process to exit and is not a launch that shuts down. So:

==============================  ===============================================================
``OnProcessStart``              its actions are part of the launch: the target process starts in
                                a capture, so what follows its start does too (once per started
                                process the handler matches: an action, a matcher function, or
                                every process when no target is given)
``OnProcessExit``               accepted when its actions only end the launch or log
                                (``Shutdown``, ``EmitEvent(event=Shutdown())``, ``LogInfo``: the
                                common "stop everything when this one exits"): a capture stops
                                every process itself. Actions that would start something once the
                                target exited are unsupported: a capture does not wait for an exit
``on_exit=`` of a Node or       the same as ``OnProcessExit`` for that process
``ExecuteProcess``
``OnShutdown``                  the same: ending and logging actions are accepted, anything else
                                (it would run while the system stops) is unsupported
any other handler               unsupported (``OnProcessIO``, ``OnExecutionComplete``,
                                ``OnIncludeLaunchDescription``, launch_ros ``OnStateTransition``)
==============================  ===============================================================

Handlers given as a function (``on_exit=lambda event, context: ...``) are unsupported: what they
do depends on the event, which a capture does not have.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any


@dataclass
class Handling:
    """What a handler comes to: the actions to walk as part of the launch (``now``), or why it
    cannot be captured (``unsupported``; None: accepted)."""

    now: list[Any] = field(default_factory=list)
    unsupported: str | None = None


def actions_of(value: Any) -> list[Any] | None:
    """Handler actions given as an action or a list of them (None: given as a function)."""
    if value is None:
        return []
    if callable(value) and not hasattr(value, "visit"):
        return None
    return list(value) if isinstance(value, (list, tuple)) else [value]


def ends_or_logs(launch: Any, action: Any) -> bool:
    """An action that only ends the launch or logs: nothing for a capture to start."""
    actions = launch.actions
    if isinstance(action, actions.LogInfo):
        return True
    if isinstance(action, actions.EmitEvent):  # Shutdown is one
        return isinstance(action.event, launch.events.Shutdown)
    return False


def after_the_end(launch: Any, actions: list[Any] | None, when: str) -> str | None:
    """None when ``actions`` (run ``when``) only end the launch or log; else why not capturable."""
    if actions is None:
        return (f"its actions are given as a function, run {when}; a capture cannot run it (it has no such "
                "event): give a list of actions")
    others = [type(a).__name__ for a in actions if not ends_or_logs(launch, a)]
    if not others:
        return None
    return (f"{', '.join(others)} would run only {when}, which a capture does not wait for (it stops every "
            "process itself); only Shutdown, EmitEvent(Shutdown) and LogInfo are accepted there")


def handle(launch: Any, handler: Any, started: Sequence[Any]) -> Handling:
    """What the event handler ``handler`` means for a capture; ``started``: the process actions
    of the launch (what an ``OnProcessStart`` matches)."""
    handlers = launch.event_handlers
    kind = type(handler).__name__
    if isinstance(handler, handlers.OnProcessStart):
        actions = actions_of(handler.describe()[1]) if handler.handler_description == "<actions>" else None
        if actions is None:
            return Handling(unsupported=f"{kind}: its actions are given as a function of the start event, which a "
                                        "capture does not have: give a list of actions")
        matches = [action for action in started if handler.matches(_started_event(launch, action))]
        return Handling(now=[a for _ in matches for a in actions])
    if isinstance(handler, handlers.OnProcessExit):
        actions = actions_of(handler.describe()[1]) if handler.handler_description == "<actions>" else None
        why = after_the_end(launch, actions, "after the process exits")
        return Handling(unsupported=f"{kind}: {why}" if why else None)
    if isinstance(handler, handlers.OnShutdown):
        why = after_the_end(launch, shutdown_actions(handler), "when the launch shuts down")
        return Handling(unsupported=f"{kind}: {why}" if why else None)
    return Handling(unsupported=f"{kind}: this event handler is not supported (a capture handles OnProcessStart, "
                                "OnProcessExit and OnShutdown)")


def shutdown_actions(handler: Any) -> list[Any] | None:
    """The actions of an ``OnShutdown`` given as a list (launch wraps them in a function of its
    own, ``gen_handler``, which returns them whatever the event); None for a function of the
    launch file's."""
    function = getattr(handler, "_OnShutdown__on_shutdown", None)
    if function is None or not getattr(function, "__qualname__", "").startswith("gen_handler."):
        return None
    return actions_of(function(None, None))


def _started_event(launch: Any, action: Any) -> Any:
    """The ProcessStarted event ``action`` would emit (what a handler's matcher looks at)."""
    return launch.events.process.ProcessStarted(action=action, name="", cmd=[], cwd=None, env=None, pid=0)
