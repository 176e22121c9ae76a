"""Warm starts: Python targets forked from a server that has imported rclpy already.

``client`` (the runner's side: the pool of servers, spawning a child, its endings) and
``server`` (the server process that preloads rclpy and forks one child per capture). Only
``run.runner`` uses it; it imports nothing of the package but ``run.process``.
"""
