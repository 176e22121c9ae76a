"""Talker, listener, service server and client in one process (one context, one executor).

The listener creates `/heard` when its first message arrives and the client `/answered` when
its response arrives: both exist only if the middleware delivers inside the process
(RMW_INTROSPECT_DELIVERY=1). Everything is sent before the executor first waits, so the
process is settled once it has handled what it received."""
import rclpy
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from std_msgs.msg import String
from std_srvs.srv import SetBool


def main():
    rclpy.init()
    talker, listener = Node("talker"), Node("listener")
    server, client_node = Node("server"), Node("client")
    publisher = talker.create_publisher(String, "chatter", 10)
    made = {}

    def heard(msg):
        if "heard" not in made:
            made["heard"] = listener.create_publisher(String, "heard", 10)
            print(f"heard: {msg.data}", flush=True)

    listener.create_subscription(String, "chatter", heard, 10)
    server.create_service(SetBool, "set_flag",
                          lambda req, res: (setattr(res, "success", req.data), res)[1])
    client = client_node.create_client(SetBool, "set_flag")

    def answered(future):
        made["answered"] = client_node.create_publisher(String, "answered", 10)
        print(f"answered: success={future.result().success}", flush=True)

    publisher.publish(String(data="hello in process"))
    client.wait_for_service(timeout_sec=1.0)
    client.call_async(SetBool.Request(data=True)).add_done_callback(answered)
    executor = SingleThreadedExecutor()
    for n in (talker, listener, server, client_node):
        executor.add_node(n)
    executor.spin()


if __name__ == "__main__":
    main()
