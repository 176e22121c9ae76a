"""The comparison layer: what differs and how much it matters.

``options`` (comparison options and their validation), ``drift`` (contract vs capture, or two
contracts: classified drift items), ``system`` (do the nodes of several contracts fit
together) and ``report`` (text and JSON for both). It may import ``model`` and ``errors``;
it never runs anything.
"""
