"""The comparison layer: what differs and how much it matters.

One line per module:

- ``options``: comparison options and their validation
- ``drift``: contract vs capture, or two contracts: classified drift items
- ``type_drift``: field-level differences between two descriptions of a type
- ``parameter_drift``: parameters and lifecycle state, expected against actual
- ``destruction_drift``: drift of when the program destroys a node or an interface
- ``compatibility``: do the nodes of several contracts (or a launch file's processes) fit together
- ``wiring``: dangling endpoints of a launched system, the declared outside world, mis-wired names
- ``launch_given``: what a launch file gives a node that the node silently ignores
- ``recordings``: contracts against a recording's topics (``check --bag``): drift, connections, topics missing or unknown
- ``recording_rules``: the rules only a recording can break, merged into the compatibility rules
- ``similarity``: how close two names are (one typo apart, or not)
- ``versioning``: ``interface_version`` judged by semantic versioning against the drift
- ``consumers``: a node contract's changed interfaces judged by who uses them in system contracts
- ``acceptance``: which findings the contracts' ``accept:`` entries accept, and stale entries
- ``baseline``: baseline files: today's findings, a later run's split into new and known
- ``findings``: what identifies a finding across runs (rule and place)
- ``type_lock``: a capture's interface types against the package's type lock
- ``report``: text for people and JSON for machines
- ``ci_report``: Markdown and GitHub workflow annotations
- ``rule_levels``: the option ``rules``, a project's level of each rule, and the list of every rule id
- ``sarif``: SARIF 2.1.0 logs
- ``junit``: JUnit XML (a test case per contract)
- ``graph``: a system drawn (Mermaid, Graphviz DOT, HTML) with the findings on it

It may import ``model`` and ``errors``; it never runs anything.
"""
