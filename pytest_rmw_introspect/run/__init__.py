"""The run layer: starting a target on the recording middleware and reading its capture.

``target`` (what to run and how, as one validated spec), ``ros_env`` (the detected ROS 2
install and the middleware's activation environment), ``middleware`` (finding or building
``librmw_introspect_cpp.so``) and ``runner`` (the process, its endings, the capture). It may
import ``model`` and ``errors``; it never compares.
"""
