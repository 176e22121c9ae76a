"""Example nodes for interface contract testing with pytest-rmw-introspect.

One module per executable; each defines the node class(es) and a ``main()`` that the
installed executable ``lib/rmw_introspect_examples/<name>`` runs.
"""
