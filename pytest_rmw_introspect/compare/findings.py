"""What identifies a finding (a drift item or a system-check problem) across runs: the same
rule about the same interface of the same node, whatever its message or severity threshold.
SARIF's fingerprints and the baselines of ``compat`` are built from it."""

from __future__ import annotations

import hashlib

from .compatibility import CompatItem, ContractEndpoint
from .drift import DriftItem


def _endpoint(endpoint: ContractEndpoint | None) -> list[str]:
    return ["", "", ""] if endpoint is None else [endpoint.label, endpoint.node, endpoint.kind]


def key(item: DriftItem | CompatItem) -> tuple[str, ...]:
    """The identity of ``item``: its rule and where it is (node, interface list, name, and the
    change of a drift item; the topic, service or action name and both ends of a system problem,
    each end with its contract)."""
    if isinstance(item, DriftItem):
        return (item.rule, item.node, item.kind, item.name, item.change)
    return (item.rule, item.name, *_endpoint(item.requester), *_endpoint(item.provider))


def fingerprint(item: DriftItem | CompatItem) -> str:
    """:func:`key` as a short stable hex digest (SARIF ``partialFingerprints``)."""
    return hashlib.sha256("\0".join(key(item)).encode()).hexdigest()[:32]
