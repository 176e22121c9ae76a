"""The words every layer shares, defined once: interface lists, their labels, action parts,
severities and the ``fail_on`` thresholds.

A node's interface is six lists (the NoDL v2 names). The middleware records four raw endpoint
kinds; actions are grouped from their services and topics. Drift and system checks rate what
they find with a :class:`Severity`; ``fail_on`` names the least severe one that fails.
"""

from __future__ import annotations

import enum

#: The six interface lists of a node, in contract order.
LISTS: tuple[str, ...] = (
    "publishers",
    "subscriptions",
    "service_servers",
    "service_clients",
    "action_servers",
    "action_clients",
)
TOPIC_LISTS: tuple[str, ...] = ("publishers", "subscriptions")
SERVICE_LISTS: tuple[str, ...] = ("service_servers", "service_clients")
ACTION_LISTS: tuple[str, ...] = ("action_servers", "action_clients")
#: Lists whose peers depend on them (they offer something). The others request.
OFFERING_LISTS: frozenset[str] = frozenset({"publishers", "service_servers", "action_servers"})
#: Requesting list → the list that provides to it.
PROVIDER_OF: dict[str, str] = {
    "subscriptions": "publishers",
    "service_clients": "service_servers",
    "action_clients": "action_servers",
}

#: Singular words for people, per list (and ``node`` for drift of a whole node).
LABELS: dict[str, str] = {
    "node": "node",
    "publishers": "publisher",
    "subscriptions": "subscription",
    "service_servers": "service server",
    "service_clients": "service client",
    "action_servers": "action server",
    "action_clients": "action client",
}

#: Raw endpoint kind (as the middleware records it) → interface list.
KIND_TO_LIST: dict[str, str] = {
    "publisher": "publishers",
    "subscription": "subscriptions",
    "service": "service_servers",
    "client": "service_clients",
}

#: The services and topics an action is made of (``/fib/_action/send_goal``, ...).
ACTION_SERVICES: tuple[str, ...] = ("send_goal", "cancel_goal", "get_result")
ACTION_TOPICS: tuple[str, ...] = ("feedback", "status")
#: The parts whose type depends on the action definition: the keys of an action's type_hash,
#: each with the word people use for it.
ACTION_HASHED_PARTS: dict[str, str] = {
    "send_goal": "goal",
    "get_result": "result",
    "feedback": "feedback",
}


class Severity(enum.IntEnum):
    """How much a change or a mismatch can hurt the node's peers."""

    SAFE = 0
    RISKY = 1
    BREAKING = 2


#: ``fail_on`` words (contract options, ini, command lines) → the least severity that fails.
THRESHOLDS: dict[str, Severity] = {
    "any": Severity.SAFE,
    "risky": Severity.RISKY,
    "breaking": Severity.BREAKING,
}
FAIL_ON: tuple[str, ...] = tuple(THRESHOLDS)
THRESHOLD_WORDS: dict[Severity, str] = {severity: word for word, severity in THRESHOLDS.items()}


def parse_threshold(text: str) -> Severity:
    """'any' | 'risky' | 'breaking' (any case) → Severity; ValueError otherwise."""
    if isinstance(text, str) and text.strip().lower() in THRESHOLDS:
        return THRESHOLDS[text.strip().lower()]
    raise ValueError(f"invalid fail threshold {text!r}: expected one of {', '.join(THRESHOLDS)}")
