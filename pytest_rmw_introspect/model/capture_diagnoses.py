"""What a capture that went wrong says about why: diagnoses for the runner's errors.

Built from the capture's typed records (``model.capture_file``), like the notes beside them
(``model.capture_notes``), and handed to the errors as text (``errors`` knows no capture):
:func:`diagnose_unsettled` is why a target did not settle within its timeout
(``errors.TargetTimeout``), told from the last snapshot the middleware wrote;
:func:`stimulus_problems` what went wrong with the target's stimuli (``errors.StimulusFailed``).
Each says what to do.
"""

from __future__ import annotations

from .capture import Capture


def diagnose_unsettled(partial: Capture | None) -> str:
    """Why a capture did not settle, told from the last snapshot the middleware wrote, and what to do."""
    if partial is None:
        return (
            "It wrote no capture: it never initialised ROS 2 on the recording middleware (busy or blocked "
            "before rclpy.init() / rcl_init, or not a ROS program). Raise `timeout` if it is only slow to start."
        )
    if not partial.raw_nodes:
        return "It initialised ROS 2 but created no node yet. Raise `timeout` if it is only slow to start."
    blocked = _blocked_in_callback(partial)
    if blocked:
        return blocked
    if partial.state == "probing":
        return (
            f"It settled after {partial.time_to_settle_ms or 0:.0f} ms, then never finished answering the "
            "middleware's questions (its parameter services, or a lifecycle transition that never settled). "
            "Set `lifecycle: none` or `read_parameters: false` on the target to capture it without them, or raise "
            "`timeout` if a transition is only slow."
        )
    seen = _what_was_seen(partial)
    if partial.state == "warping":
        vt = partial.virtual_time
        age = f" (virtual age {vt.virtual_elapsed_ms / 1000:.3g} s)" if vt is not None else ""
        if seen:
            return (f"It settled after {partial.time_to_settle_ms or 0:.0f} ms; virtual time was then advanced{age} "
                    f"but it never went quiet again: {seen} Lower `horizon`, or set it to 0 to capture only what "
                    "exists at the first settle.")
        return (
            f"It settled after {partial.time_to_settle_ms or 0:.0f} ms; virtual time was then advanced{age} but it "
            "never went quiet again: does it keep creating or destroying interfaces? Lower `horizon`, or set it "
            "to 0 to capture only what exists at the first settle."
        )
    if not partial.ever_waited:
        return (
            "No thread ever waited in an executor (rmw_wait) and it did not keep using ROS (publish, take, "
            "graph queries; log lines and parameter events do not count: a loop that only logs is still setting "
            "up) after its last new interface: it is busy or blocked outside ROS (a long "
            "computation, a blocking read, input(), a long time.sleep before it spins). A loop that never "
            "spins settles once it makes two such calls with no new interface for the settle time. Raise "
            "`timeout` if it is only slow."
        )
    if seen:
        return f"It waits in an executor but was never quiet for the settle time: {seen} Raise `timeout` if it is only slow."
    return (
        "It waits in an executor but kept creating or destroying interfaces, so it was never quiet for the "
        "settle time. Raise `timeout` if it is only slow to finish starting."
    )


def _blocked_in_callback(partial: Capture) -> str:
    """A request of the middleware's own that the node took and never answered (a lifecycle
    transition, a stimulus' service call, a parameter read): its callback is blocked. "" otherwise."""
    settled = f"It settled after {partial.time_to_settle_ms or 0:.0f} ms; "
    for raw_node in partial.raw_nodes:
        lifecycle = raw_node.lifecycle
        for transition in (lifecycle.transitions if lifecycle is not None else ()):
            if transition.result in ("pending", "no_answer"):
                return (f"{settled}the middleware then asked lifecycle node {raw_node.fqn} to {transition.label}, and "
                        f"the transition never returned: the node is blocked in its on_{transition.label} callback "
                        "(waiting for something that never comes, or looping), its interfaces did not change. Fix "
                        "the callback, or capture the node without driving it: `lifecycle: none` on the target (or "
                        "the state before that transition).")
    for stimulus in partial.stimuli:
        for target in stimulus.targets:
            if target.kind == "service" and target.result in ("pending", "no_answer"):
                return (f"{settled}the stimulus {stimulus.name} then called the service of node "
                        f"{target.node}, and its callback never returned: the node is blocked in it (waiting "
                        "for something that never comes, or looping), its interfaces did not change. Fix the "
                        "callback, or leave that name out of `stimuli`.")
    probe = partial.probe
    if probe is not None and probe.unanswered:
        return (f"{settled}the middleware then read the nodes' parameters and {probe.unanswered} request(s) got no "
                "answer: a node is blocked in a callback (its executor no longer serves its parameter services), its "
                "interfaces did not change. Set `read_parameters: false` on the target to capture it without them.")
    return ""


def _what_was_seen(partial: Capture) -> str:
    """What the last snapshot shows of a process that did not settle, when its interfaces stopped
    changing well before it ended ("" when they changed until the end: then that is the reason)."""
    last = partial.last_change_ms()
    elapsed = partial.elapsed_ms
    settle = partial.settle_ms or 0
    if last is None or elapsed is None or elapsed - last <= max(2 * settle, 1000):
        return ""
    facts = [f"its last interface was created at {last:.0f} ms and nothing changed in the {(elapsed - last) / 1000:.3g} s after"]
    if partial.not_idle:
        facts.append(f"the middleware last saw {partial.not_idle}")
    if partial.polls:
        facts.append(f"it returned from rmw_wait {partial.polls} times without waiting (zero-timeout polls, or a "
                     "guard condition it had just triggered itself)")
    facts.append(f"{partial.activity_calls or 0} calls into ROS (publish, take, graph queries) in all")
    return ("; ".join(facts) + ". It runs without waiting in an executor (a busy loop: a task spun with spin_once "
            "that awaits an answer that never comes, a callback that never returns, a sleep loop).")


def stimulus_problems(capture: Capture, returncode: int | None) -> list[str]:
    """What went wrong with the stimuli ``capture`` records (``Capture.stimuli``), one line each
    for people; empty when every name reached its subscriptions and services and the process
    did not fail after them. ``returncode``: the process's exit status."""
    problems: list[str] = []
    last: str | None = None  # the last delivery made (or in flight)
    settled = capture.state == "settled"
    for stimulus in capture.stimuli:
        name, state, error = stimulus.name, stimulus.state, stimulus.error
        if state == "no_match":
            problems.append(str(error or f"no subscription or service named {name}"))
        elif state == "skipped":
            problems.append(f"{name}: {error or 'not delivered'}")
        elif state == "pending" and not settled:
            problems.append(f"{name}: not delivered: the process ended before its turn")
        for target in stimulus.targets:
            result = target.result
            where = f"the {target.kind} {name} of {target.node}"
            if result in ("not_taken", "no_answer", "failed"):
                problems.append(f"{name} ({target.kind} of {target.node}): {target.error or result}")
            elif result in ("taken", "answered") or (result == "pending" and not settled):
                last = where
    ended_early = bool(capture.ended_before_settle)
    if returncode not in (None, 0) and last is not None and (ended_early or not settled):
        how = f"was killed by signal {-returncode}" if returncode < 0 else f"exited with status {returncode}"
        problems.append(
            f"the process {how} after the middleware delivered a stimulus (the last: a default message or "
            f"request to {last}): a default-constructed message is input the node acts on (an empty image, "
            "a zero command, an empty frame id); make the node cope with it, or leave the stimulus out"
        )
    return problems
