"""What a lifecycle manager does, for the smoke test (test_nodes_run.py): configure, then
activate the managed node named on the command line, through its ``change_state`` service.

    python3 lifecycle_manager.py /lifecycle_talker

It reads the node's state (``get_state``) before each transition and asks for the one that state
needs, so an answer that never comes costs a retry, not the run: on DDS a response the server
sends before it has matched this client's reader is lost ("failed to send response (timeout)"),
and a transition asked for twice would be refused the second time.
"""

import sys
import time

import rclpy
from lifecycle_msgs.msg import State, Transition
from lifecycle_msgs.srv import ChangeState, GetState

#: how long one request waits for its answer before the manager asks (or reads the state) again
ANSWER_TIMEOUT = 5.0
#: how long the whole bring-up may take (a dozen processes start at once on a small machine)
DEADLINE = 50.0
#: the transition each stable state needs on the way to active
NEXT = {State.PRIMARY_STATE_UNCONFIGURED: (Transition.TRANSITION_CONFIGURE, 'configure'),
        State.PRIMARY_STATE_INACTIVE: (Transition.TRANSITION_ACTIVATE, 'activate')}


def answer(node, client, request):
    """The service's answer, or None when none came within ANSWER_TIMEOUT."""
    future = client.call_async(request)
    rclpy.spin_until_future_complete(node, future, timeout_sec=ANSWER_TIMEOUT)
    if future.done():
        return future.result()
    client.remove_pending_request(future)
    return None


def main():
    managed = sys.argv[1]
    rclpy.init()
    node = rclpy.create_node('smoke_test_lifecycle_manager')
    get_state = node.create_client(GetState, f'{managed}/get_state')
    change_state = node.create_client(ChangeState, f'{managed}/change_state')
    deadline = time.monotonic() + DEADLINE
    try:
        for client in (get_state, change_state):
            if not client.wait_for_service(timeout_sec=max(0.0, deadline - time.monotonic())):
                print(f'{client.srv_name} never appeared', flush=True)
                return 1
        while time.monotonic() < deadline:
            state = answer(node, get_state, GetState.Request())
            if state is None:
                continue  # ask again
            current = state.current_state
            if current.id == State.PRIMARY_STATE_ACTIVE:
                print(f'{managed} is active', flush=True)
                return 0
            if current.id not in NEXT:  # a transition under way: read the state again
                time.sleep(0.1)
                continue
            transition, label = NEXT[current.id]
            result = answer(node, change_state, ChangeState.Request(transition=Transition(id=transition)))
            if result is not None and not result.success:
                print(f'{label} of {managed} failed (it was {current.label})', flush=True)
                return 1
        print(f'{managed} is not active after {DEADLINE:.0f} s', flush=True)
        return 1
    finally:
        node.destroy_node()
        rclpy.try_shutdown()


if __name__ == '__main__':
    sys.exit(main())
