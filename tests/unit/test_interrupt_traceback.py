"""The traceback a Python target prints when the runner's own SIGINT stops it is not shown as
the target's stderr (it reads like the node's crash); everything else the target printed is."""

from pytest_rmw_introspect.errors import TargetTimeout, without_our_interrupt

SPIN_INTERRUPTED = """\
[INFO] [1764000000.0] [talker]: Publishing: "hello 3"
Traceback (most recent call last):
  File "/venv/bin/talker", line 8, in <module>
    sys.exit(main())
  File "/pkg/talker.py", line 30, in main
    rclpy.spin(node)
KeyboardInterrupt
"""

CHAINED = """\
warming up
Traceback (most recent call last):
  File "/pkg/node.py", line 10, in main
    rclpy.spin(node)
KeyboardInterrupt

During handling of the above exception, another exception occurred:

Traceback (most recent call last):
  File "/pkg/node.py", line 12, in main
    node.destroy_node()
KeyboardInterrupt
"""

OWN_CRASH_THEN_INTERRUPT = """\
Traceback (most recent call last):
  File "/pkg/node.py", line 5, in on_timer
    1 / 0
ZeroDivisionError: division by zero
still running
Traceback (most recent call last):
  File "/pkg/node.py", line 20, in main
    rclpy.spin(node)
KeyboardInterrupt
"""


def test_the_interrupt_traceback_at_the_end_is_left_out_and_the_log_stays():
    text, left_out = without_our_interrupt(SPIN_INTERRUPTED)
    assert left_out and text == '[INFO] [1764000000.0] [talker]: Publishing: "hello 3"'


def test_a_chained_interrupt_traceback_goes_whole():
    text, left_out = without_our_interrupt(CHAINED)
    assert left_out and text == "warming up"


def test_the_nodes_own_earlier_traceback_stays():
    text, left_out = without_our_interrupt(OWN_CRASH_THEN_INTERRUPT)
    assert left_out
    assert text.endswith("ZeroDivisionError: division by zero\nstill running")


def test_stderr_that_does_not_end_in_our_interrupt_is_unchanged():
    crash = "Traceback (most recent call last):\n  File \"x\", line 1\nValueError: bad\n"
    assert without_our_interrupt(crash) == (crash, False)
    assert without_our_interrupt("") == ("", False)
    assert without_our_interrupt("KeyboardInterrupt\n") == ("KeyboardInterrupt\n", False)  # no traceback


def test_a_timeout_message_says_the_tool_stopped_the_target():
    message = str(TargetTimeout("talker", 2.0, stderr_tail=SPIN_INTERRUPTED, argv=["/venv/bin/talker"]))
    assert "Publishing" in message and "Traceback" not in message
    assert "The tool stopped it with SIGINT" in message
    assert "Command: /venv/bin/talker" in message
    plain = str(TargetTimeout("talker", 2.0, stderr_tail="just a log line\n"))
    assert "The tool stopped it" not in plain
