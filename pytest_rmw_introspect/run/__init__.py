"""The run layer: starting a target on the recording middleware and reading its capture.

``target`` (what to run and how, as one validated spec), ``ros_env`` (the detected ROS 2
install and the middleware's activation environment), ``middleware`` (finding or building
``librmw_introspect_cpp.so``), ``process`` (the target's process: its group, output tail and
stop), ``runner`` (the process, its endings, the capture), ``api`` (the library's one-call
``capture``), ``system`` (every process a launch file starts, captured: the one module that
joins ``launch`` and the runner) and the ``warm`` subpackage (warm starts: ``warm.client``,
``warm.server``). It may import ``model``, ``launch`` and ``errors``; it never compares.
"""
