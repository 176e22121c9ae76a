"""The check layer: the pipeline from a contract file to an outcome, and the one writer.

``pipeline`` (contract → layered target and options → capture → drift → result; diff and
compatibility checks over files), ``outcome`` (the pure decision: pass, warn, fail, write, error) and
``golden`` (every contract write: atomic, locked, CI-aware). It may import ``compare``, ``run``,
``model`` and ``errors``; the front ends (``plugin``, ``cli``) sit on top of it.
"""
