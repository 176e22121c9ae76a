"""A task that awaits an answer that never comes, spun by a `spin_once` loop (issue 24): a 0.5 s
timer's coroutine callback cancels the timer and awaits `client.call_async(...)`; no server
exists, so rclpy's executor yields that task again on every `spin_once` without ever waiting -
a busy loop that makes no call into the middleware at all."""
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
