"""Warm starts: Python targets forked from a server that has imported rclpy already.

One line per module:

- ``client``: the runner's side: which commands start warm, the pool of servers, the forked child
- ``server``: the server process: preloads rclpy, forks one child per capture

Only ``run.target`` (which targets start warm), ``run.runner`` (starting them) and
``run.prewarm`` use it; it imports nothing of the package but ``run.process``.
"""
