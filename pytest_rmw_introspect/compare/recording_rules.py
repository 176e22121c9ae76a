"""The rules only a recording can break (``rmw-introspect check --bag``, ``compare.recordings``):
system problems, merged into ``compatibility.RULES`` (so that `accept:` entries, baselines and
SARIF know them), with their summaries (docs/drift-rules.md, "Compatibility rules")."""

from __future__ import annotations

from ..model.vocabulary import Severity

#: rule id → severity (merged into ``compatibility.RULES``: they are system problems)
RULES: dict[str, Severity] = {
    "CONTRACT_TOPIC_NOT_RECORDED": Severity.RISKY,
    "RECORDED_TOPIC_SILENT": Severity.RISKY,
    "RECORDED_TOPIC_UNDECLARED": Severity.RISKY,
    "RECORDED_TOPIC_EXTRA_PUBLISHER": Severity.RISKY,
}
#: rule id → what it reports (docs/drift-rules.md, "Compatibility rules")
SUMMARIES: dict[str, str] = {
    "CONTRACT_TOPIC_NOT_RECORDED": (
        "`check --bag`: a topic a contract's publisher promises is not in the recording (a recording may hold "
        "a subset of the topics)"
    ),
    "RECORDED_TOPIC_SILENT": (
        "`check --bag`: a topic a contract's publisher promises is in the recording without a message (the "
        "recorder found a publisher, nothing was published)"
    ),
    "RECORDED_TOPIC_UNDECLARED": (
        "`check --bag`: a recorded topic that no contract's publisher declares, nor a system contract's "
        "`external:` publishers"
    ),
    "RECORDED_TOPIC_EXTRA_PUBLISHER": (
        "`check --bag`: the recorder found more publishers of a declared topic than the contracts declare (a node "
        "they do not know publishes it too)"
    ),
}
