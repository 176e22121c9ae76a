"""The live check: a running ROS 2 graph read on the real middleware and compared with contracts.

``live.reader`` runs in a process of its own on the middleware the user runs (never on the
recording middleware: ``live.graph`` refuses or strips its activation), joins the graph, waits
until it has been stable for a settle time and writes what it read as a capture document of the
recording middleware's format, so the graph becomes the same :class:`~..model.capture.Capture`
a capture makes. ``live.graph`` starts the reader and reads its answer; ``live.check`` compares
the live capture with node and system contracts through the drift and compatibility rules of
``check``, with the fields the live graph cannot show taken as the contract states them and said
as notes, never as drift (docs/known-limits.md, "The live check").

- ``reader``: the reader process (rclpy on the real middleware): settle, read, print a capture document
- ``graph``: the reader started with the user's environment (never the recording middleware) and its answer read
- ``check``: a live graph compared with node and system contracts (``LiveCheckResult``)
- ``bringup``: a launch file's processes started on the real middleware in a domain of their own
"""

#: the reader's exit status when nothing but itself was in the graph when the time was up
EXIT_EMPTY = 3
#: the reader's exit status when it found itself on the recording middleware
EXIT_WRONG_MIDDLEWARE = 4
#: how long the graph must stay unchanged, at most how long to wait, and how long the nodes'
#: parameter and lifecycle services have (seconds)
DEFAULT_SETTLE = 2.0
DEFAULT_TIMEOUT = 30.0
DEFAULT_PARAMETER_TIMEOUT = 5.0
#: seconds the graph must stay unchanged before a node the contracts name (``LiveSettings.expect``)
#: and the graph does not show counts as absent: a participant missed in the first burst of
#: discovery is found at a later announcement (Fast DDS announces every 3 s; a fresh-clone Kilted
#: CI missed the C talker of a dozen processes at a 1.5 s settle), so three rounds of it
ABSENT_AFTER = 10.0
