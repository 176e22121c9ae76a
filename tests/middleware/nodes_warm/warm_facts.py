"""Facts about its own process, read at import time and published as topic names, so that a
capture shows them: a warm start must give exactly what a cold start gives.

Run as a script, as ``-m warm_facts`` (from this directory) or through an executable with a
``#!`` line. ``WARM_FACT`` (environment) and the first argument show up as facts too.
"""

import hashlib
import os
import re
import signal
import sys
import threading

import rclpy
from rclpy.node import Node
from std_msgs.msg import Empty


def _open_fds():
    return sorted(int(fd) for fd in os.listdir("/proc/self/fd") if int(fd) > 2)


_FDS = _open_fds()  # the listing's own fd is gone again: what the process holds
_UMASK = os.umask(0o022)
os.umask(_UMASK)
_main = sys.modules["__main__"]

FACTS = {
    "argc": len(sys.argv),
    "argv0": os.path.basename(sys.argv[0]),
    "argv1": sys.argv[1] if len(sys.argv) > 1 else "none",
    "orig_argv0": os.path.basename(sys.orig_argv[0]),
    "orig_argc": len(sys.orig_argv),
    "executable": sys.executable,
    "name": __name__,
    "file": __file__,
    "path0_script_dir": sys.path[0] == os.path.dirname(os.path.realpath(__file__)),
    "path0_cwd": sys.path[0] == os.getcwd(),
    "path_tail": hashlib.sha256("\0".join(sys.path[1:]).encode()).hexdigest()[:16],
    "main_is_this": _main.__dict__ is globals(),
    "spec": type(__spec__).__name__,
    "loader": type(__loader__).__name__,
    "cached": type(globals().get("__cached__")).__name__,
    "package": str(__package__),
    "builtins": type(__builtins__).__name__,
    "annotations": "__annotations__" in globals(),
    "env": os.environ.get("WARM_FACT", "unset"),
    "blas_threads_env": os.environ.get("OPENBLAS_NUM_THREADS", "unset"),  # the server's own setting stays its own
    "rmw_vars": sorted(k for k in os.environ if k.startswith("RMW_INTROSPECT_") and k != "RMW_INTROSPECT_OUTPUT"),
    "cwd": os.getcwd(),
    "stdin": os.readlink("/proc/self/fd/0"),
    "stdout": os.readlink("/proc/self/fd/1").split(":")[0],
    "stderr": os.readlink("/proc/self/fd/2").split(":")[0],
    "fds": len(_FDS),
    "group_leader": os.getpgrp() == os.getpid(),
    "session_leader": os.getsid(0) == os.getpid(),
    "sigint": signal.getsignal(signal.SIGINT) is signal.default_int_handler,
    "sigterm": signal.getsignal(signal.SIGTERM),
    "sigchld": signal.getsignal(signal.SIGCHLD),
    "sigpipe": signal.getsignal(signal.SIGPIPE),
    "sighup": signal.getsignal(signal.SIGHUP),
    "blocked": sorted(int(s) for s in signal.pthread_sigmask(signal.SIG_BLOCK, [])),
    "umask": oct(_UMASK),
    "python_threads": threading.active_count(),
    "write_through": sys.stdout.write_through,
    "line_buffering": sys.stdout.line_buffering,
    "encoding": sys.stdout.encoding,
    "flags": "_".join(str(int(v)) for v in sys.flags),
    "recursion_limit": sys.getrecursionlimit(),
}


def topic(key, value):
    text = re.sub(r"[^A-Za-z0-9_]", "_", str(value))[:200]
    return f"/facts/{key}/v_{text}"


def main():
    rclpy.init()
    node = Node("warm_facts")
    for key, value in FACTS.items():
        node.create_publisher(Empty, topic(key, value), 1)
    try:
        rclpy.spin(node)
    except KeyboardInterrupt:
        pass


if __name__ == "__main__":
    main()
