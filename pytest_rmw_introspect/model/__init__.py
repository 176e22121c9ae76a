"""The model layer: the vocabulary every other layer speaks, defined once.

One line per module:

- ``vocabulary``: interface lists, labels, action parts, severities, ``fail_on`` words
- ``qos``: QoS spellings, expansion, named profiles, compatibility
- ``middlewares``: the middlewares (rmw implementations) the QoS rules know, and which one a system runs on
- ``capture``: one process's capture (``Capture``) and the runner's facts about its run (``RunFacts``)
- ``capture_file``: the middleware's capture file: its format, its raw records, reading and checking it (its only reader)
- ``capture_view``: the contract view of a capture: nodes, their six interface lists, actions grouped
- ``capture_notes``: what a report's reader should know about how a capture came about
- ``capture_diagnoses``: why a capture went wrong (it did not settle, a stimulus failed), as the errors say it
- ``types``: type descriptions in captures and contracts
- ``type_hash``: RIHS01 type hashes computed from type descriptions
- ``type_lock``: the package's type-hash lockfile (``rmw-introspect lock``)
- ``parameters``: a node's parameters and lifecycle state, captured and in contracts
- ``portable``: parameter values written portably (an install location as a token), what they point at
- ``option_tables``: the comparison and target options, their front ends and precedence
- ``recording``: rosbag2 recordings (a bag directory, an MCAP or sqlite3 file) read for their topics, QoS and counts
- ``contract``: contract files: load, validate, render, update
- ``contract_kind``: whether a file is a contract and of which kind (node, marker golden, system,
  NoDL), by its content: the one place every command and pytest ask
- ``contract_shapes``: the contract's mappings as ``TypedDict``s: node, entries, QoS, blocks
- ``system_contract``: system contracts (``*.system.yaml``): a launch file's processes
- ``stand_ins``: a system contract's processes not run where it is checked, and what stands in for them
- ``nodl``: NoDL v2 documents as contracts, and contracts written as NoDL
- ``acceptance``: the ``accept:`` entries of a contract
- ``unstable_names``: node names that change every run, and the pattern a contract keys them by
- ``name_patterns``: patterns of names (``*``, a section key's ``**``) matched in linear time
- ``interface_version``: ``interface_version: MAJOR.MINOR.PATCH``: bumps by semantic versioning
- ``locate``: the line of each node and interface entry of a contract file
- ``yaml_blocks``: where a top-level block sits in a YAML text, for updates that keep the rest
- ``untrusted``: reading files people hand us: bounded, typed and fast
- ``versioned_json``: the format and version check of the JSON files the tool writes
- ``paths``: how paths are shown and written
- ``editable_installs``: Python distributions installed editable (``pip install -e .``) and their source trees
- ``ament_index``: the ament index: which install prefixes provide a package (or a NoDL document)
- ``project_urls``: where the project lives on the web: the repository, links to its docs pages
- ``tally``: development accounting: target starts, commands, formats, rules, contract kinds, to a file
  ``RMW_INTROSPECT_TALLY`` names (the test suite's cost and coverage reports; nothing without it)

It may import ``errors`` and nothing else of the package.
"""
