"""The launch layer: which processes a launch file starts, read without starting anything.

One line per module:

- ``reader``: XML and YAML launch files, and the entry point for every kind of launch source
- ``entities``: XML and YAML as one entity tree with lines
- ``substitutions``: ``$(...)`` parsing and evaluation
- ``python_file``: Python launch files through ``launch``/``launch_ros``
- ``composition_stand_in``: composition_interfaces' LoadNode request for launch_ros where no such package is installed
- ``python_events``: event handlers of Python launch files, with the meaning a capture gives them
- ``record``: play_launch's ``record.json``
- ``components``: composable nodes as the LoadNode requests launch_ros makes of them
- ``component_loads``: those requests handed to a container's middleware, and what they came to
- ``result``: what a launch file starts, as data (``LaunchResult``, ``LaunchedNode``, ...)

It may import ``model`` and ``errors``; ``run`` runs what it reads (``run.system_capture`` is the
one module that joins the two).
"""
