"""The run layer: starting a target on the recording middleware and reading its capture.

One line per module:

- ``target``: what to run and how, as one validated spec
- ``ros_env``: the detected ROS 2 install and the middleware's activation environment
- ``middleware``: finding or building ``librmw_introspect_cpp.so``
- ``process``: a cold start's process: its group, output tails and stop
- ``runner``: start (warm or cold), wait, read the capture, classify the ending
- ``api``: the library's one-call ``capture``
- ``system_capture``: every process a launch file starts, captured (the one module that reads ``launch``)
- ``warm``: warm starts (subpackage: ``warm.client``, ``warm.server``)

It may import ``model``, ``launch`` and ``errors``; it never compares.
"""
