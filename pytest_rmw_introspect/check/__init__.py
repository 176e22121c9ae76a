"""The check layer: the pipeline from a contract file to an outcome, and the one writer.

One line per module:

- ``pipeline``: contract → layered target and options → capture → drift → result; compatibility
  checks over files
- ``system_pipeline``: the same for a system contract (a launch file's processes), and the
  compatibility rules over contract files of either kind
- ``diff``: the one diff core: a contract against another version of itself, any kind (``diff``,
  the gate) → ``DiffResult``
- ``recording_check``: ``check --bag``: contracts checked against a recording, a result per contract and one for it
- ``result``: the one result core of node and system checks (findings, thresholds, the golden's nodes)
- ``launch_settings``: what a launch file gives each process, as ``compare.launch_given`` reads it
- ``outcome``: the pure decision: pass, warn, fail, write, error
- ``golden``: every contract write: atomic, locked, CI-aware; a marker test's target into its golden
- ``golden_tests``: the marker tests that name a golden (for the command that gives it a target)
- ``golden_record``: what a session wrote and whether it may write (the part a pytest-xdist
  controller needs without the writer)
- ``baselines``: a baseline file applied to check results
- ``sharding``: which contracts one CI job of several checks
- ``gate``: the pull-request gate: every contract against its version at a git revision
- ``contract_files``: the contract files under a directory, found by their content
- ``revision``: contract files at a git revision (git ``rev-parse``, ``ls-tree``, ``diff -M``, ``cat-file``)

It may import ``compare``, ``run``, ``launch``, ``model`` and ``errors``; the front ends
(``plugin``, ``cli``) sit on top of it.
"""
