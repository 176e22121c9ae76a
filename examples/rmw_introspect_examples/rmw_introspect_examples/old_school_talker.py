"""old_school_talker: a publisher in a plain loop, no executor (the "old school" rclpy style).

Interface: publisher ``chatter`` (std_msgs/msg/String) with the default QoS.

``while rclpy.ok(): publish(); time.sleep(0.5)`` never calls an executor, so no thread ever
waits in the middleware. The recording middleware still sees the node settle: it used the
middleware (``publish``) after its last new interface and sleeps, which is what a steady loop
looks like; in the warp each ``time.sleep`` jumps virtual time like a timer (the preloaded
middleware defines the process's sleeps).
"""

import time

import rclpy
from rclpy.executors import ExternalShutdownException
from std_msgs.msg import String


def main(args=None):
    rclpy.init(args=args)
    # The whole body is inside the try: on Ctrl-C, rclpy's own handler shuts the context down
    # (ending the loop) and Python raises KeyboardInterrupt at whatever line runs next.
    try:
        node = rclpy.create_node('old_school_talker')
        publisher = node.create_publisher(String, 'chatter', 10)
        count = 0
        while rclpy.ok():
            msg = String(data=f'Old school hello: {count}')
            count += 1
            node.get_logger().info(f'Publishing: "{msg.data}"')
            publisher.publish(msg)
            time.sleep(0.5)
        node.destroy_node()
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    except RuntimeError:
        # SIGINT shut the context down (rclpy's handler) while no KeyboardInterrupt came first:
        # a node started with SIGINT ignored (`cmd &` in a script) gets none at all, and the
        # next publish() fails ("publisher's context is invalid", an RCLError). Shut down is
        # shut down; anything else is a real error.
        if rclpy.ok():
            raise
    finally:
        try:
            rclpy.try_shutdown()
        except RuntimeError:
            # On Ctrl-C rclpy's handler shuts the context down from a thread of its own while
            # this thread, woken from time.sleep, does it too: the loser's check-then-shutdown
            # fails with "rcl_shutdown already called" (ros2/rclpy#1352; rclpy 7.1.6 here).
            # The context is down either way; anything else is a real error.
            if rclpy.ok():
                raise
