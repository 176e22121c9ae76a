"""What a lifecycle manager does, for the smoke test (test_nodes_run.py): configure, then
activate the managed node named on the command line, through its ``change_state`` service.

    python3 lifecycle_manager.py /lifecycle_talker
"""

import sys

import rclpy
from lifecycle_msgs.msg import Transition
from lifecycle_msgs.srv import ChangeState


def main():
    managed = sys.argv[1]
    rclpy.init()
    node = rclpy.create_node('smoke_test_lifecycle_manager')
    client = node.create_client(ChangeState, f'{managed}/change_state')
    try:
        if not client.wait_for_service(timeout_sec=50.0):
            print(f'{managed}/change_state never appeared', flush=True)
            return 1
        for transition, label in ((Transition.TRANSITION_CONFIGURE, 'configure'),
                                  (Transition.TRANSITION_ACTIVATE, 'activate')):
            future = client.call_async(ChangeState.Request(transition=Transition(id=transition)))
            rclpy.spin_until_future_complete(node, future, timeout_sec=30.0)
            if not future.done() or not future.result().success:
                print(f'{label} of {managed} failed', flush=True)
                return 1
        print(f'{managed} is active', flush=True)
        return 0
    finally:
        node.destroy_node()
        rclpy.try_shutdown()


if __name__ == '__main__':
    sys.exit(main())
