"""A task that awaits an answer that never comes, spun by a `spin_once` loop (issue 24 item 5):
a 0.5 s timer's coroutine callback cancels the timer and awaits `client.call_async(...)`; no
server exists. Measured: each `rclpy.spin_once(node)` adds and removes the node (two triggers of
the executor's guard condition) and alternately runs the pending task again and waits in
rmw_wait without a timeout, which returns at once on that guard condition - a busy loop that
never blocks (about 25 000 iterations a second here)."""
import rclpy
from rclpy.node import Node
from std_srvs.srv import Trigger


def main():
    rclpy.init()
    node = Node("stuck_task")
    client = node.create_client(Trigger, "nobody_answers")
    done = []

    async def once():
        timer.cancel()
        await client.call_async(Trigger.Request())
        done.append(True)

    timer = node.create_timer(0.5, once)
    while rclpy.ok() and not done:
        rclpy.spin_once(node)


if __name__ == "__main__":
    main()
