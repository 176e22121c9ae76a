"""Warm starts: Python targets forked from a server that has imported rclpy already.

One line per module:

- ``plan``: which commands start warm and which server each needs (pure: no process, no socket)
- ``client``: the runner's side: the pool of servers, the forked child
- ``server``: the server process: preloads rclpy, forks one child per capture

Only ``run.target`` (which targets start warm), ``run.runner`` (starting them) and
``run.prewarm`` use it (``client`` names the plan's functions too); it imports nothing of the
package but ``run.process``.
"""
