"""model.capture_diagnoses.diagnose_unsettled: what a timeout's message says was seen, from the partial capture."""

from __future__ import annotations

from pytest_rmw_introspect.model.capture import Capture
from pytest_rmw_introspect.model.capture_diagnoses import diagnose_unsettled

QOS = {"history": "KEEP_LAST", "depth": 10, "reliability": "RELIABLE", "durability": "VOLATILE",
       "liveliness": "SYSTEM_DEFAULT", "deadline_ns": 0, "lifespan_ns": 0, "liveliness_lease_duration_ns": 0,
       "avoid_ros_namespace_conventions": False}


def partial(**fields):
    doc = {"format": "rmw_introspect_capture", "format_version": 1, "format_minor": 4, "state": "running",
           "settle_ms": 100, "elapsed_ms": 6000.0, "ever_waited": True, "activity_calls": 3,
           "nodes": [{"id": 1, "seq": 1, "name": "n", "namespace": "/", "created_real_ms": 10.0}],
           "endpoints": []}
    doc.update(fields)
    return Capture.from_dict(doc)


def test_a_loop_that_returns_from_rmw_wait_without_waiting_is_named():
    text = diagnose_unsettled(partial(quiescence={"polls": 50}))
    assert "its last interface was created at 10 ms and nothing changed in the 5.99 s after" in text
    assert "returned from rmw_wait 50 times without waiting" in text
    assert "kept creating or destroying" not in text


def test_a_lifecycle_transition_that_never_returned_names_the_node_and_the_callback():
    lifecycle = {"target": "active", "initial_state": "unconfigured", "state": "unconfigured",
                 "transitions": [{"id": 1, "label": "configure", "result": "pending", "success": None}],
                 "error": None}
    cap = partial(state="shutdown", time_to_settle_ms=20.0,
                  nodes=[{"id": 1, "seq": 1, "name": "lc", "namespace": "/", "lifecycle": lifecycle}])
    text = diagnose_unsettled(cap)
    assert text.startswith("It settled after 20 ms; the middleware then asked lifecycle node /lc to configure")
    assert "blocked in its on_configure callback" in text and "lifecycle: none" in text


def test_a_stimulus_whose_service_never_answered_names_it():
    stimuli = [{"name": "/reset", "state": "done", "error": None,
                "targets": [{"kind": "service", "node": "/n", "type": "std_srvs/srv/Trigger",
                             "result": "no_answer", "error": "no answer"}]}]
    text = diagnose_unsettled(partial(time_to_settle_ms=20.0, stimuli=stimuli))
    assert "the stimulus /reset then called the service of node /n, and its callback never returned" in text


def test_unanswered_parameter_reads_say_a_callback_is_blocked():
    probe = {"state": "running", "parameters": True, "lifecycle": "active", "answer_timeout_ms": 5000,
             "requests": 2, "unanswered": 1}
    text = diagnose_unsettled(partial(time_to_settle_ms=20.0, probe=probe))
    assert "1 request(s) got no answer" in text and "read_parameters: false" in text
