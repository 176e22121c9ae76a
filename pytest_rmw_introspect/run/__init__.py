"""The run layer: starting a target on the recording middleware and reading its capture.

One line per module:

- ``target``: what to run, as one validated spec (each target option's meaning, the layers merged, its ROS arguments)
- ``executables``: which program a spec names (``ros2 run``'s ament index lookup, console scripts, entry points) and its command line
- ``resolution``: a spec resolved into what the runner starts (command line, environment, warm or cold and why)
- ``ros_env``: the detected ROS 2 install and the middleware's activation environment
- ``editable``: ament_python packages installed with ``pip install -e .``, made into symlink prefixes as colcon would
- ``cache``: where the plugin keeps what it builds and makes (``RMW_INTROSPECT_CACHE``)
- ``middleware``: finding (installed, prebuilt) or building ``librmw_introspect_cpp.so``
- ``progress``: the lines that tell the user what a slow step does (the front end says where they go)
- ``process``: a cold start's process: its group, output tails and stop
- ``deadline``: the runner's overall deadline (the watchdog that reports a wait nobody bounded)
- ``locks``: file locks with a timeout that name their holder (build and golden-write locks)
- ``runner``: start a resolved target (warm or cold), wait, read the capture, classify the ending
- ``failure_hints``: what to do next, for a target that could not import a module or created no node
- ``prewarm``: starting a warm start server ahead of the captures (the plugin's session start)
- ``api``: the library's one-call ``capture``
- ``system_capture``: every process a launch file starts, captured (the one module that reads ``launch``)
- ``warm``: warm starts (subpackage: ``warm.client``, ``warm.server``)

It may import ``model``, ``launch`` and ``errors``; it never compares.
"""
