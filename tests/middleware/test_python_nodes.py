"""Real rclpy nodes run on the recording middleware: the exact capture of each."""


import rmwi_helpers as h
from rmwi_helpers import ep, node, qos
from rmwi_helpers import rclpy_node_infrastructure as infra


def test_talker(run):
    result = run(h.python_node("talker.py"))
    h.assert_settled_process(result)
    h.assert_capture(
        result.capture, [node("talker")],
        infra("/talker") + [ep("publisher", "/talker", "/chatter", "std_msgs/msg/String")])
    assert result.capture["argv"][-1].endswith("talker.py")
    assert result.capture["pid"] == result.pid
    assert result.capture["settle_ms"] == 10


def test_listener(run):
    result = run(h.python_node("listener.py"))
    h.assert_settled_process(result)
    h.assert_capture(
        result.capture, [node("listener")],
        infra("/listener") + [ep("subscription", "/listener", "/chatter", "std_msgs/msg/String")])


def test_qos_profiles(run):
    result = run(h.python_node("qos_node.py"))
    h.assert_settled_process(result)
    n = "/qos_node"
    h.assert_capture(result.capture, [node("qos_node")], infra(n) + [
        ep("publisher", n, "/scan", "sensor_msgs/msg/LaserScan", h.QOS_SENSOR),
        ep("subscription", n, "/scan_in", "sensor_msgs/msg/LaserScan", h.QOS_SENSOR),
        ep("publisher", n, "/map", "nav_msgs/msg/OccupancyGrid", qos(depth=1, durability="TRANSIENT_LOCAL")),
        ep("subscription", n, "/events", "std_msgs/msg/String", qos(history="KEEP_ALL")),
        ep("publisher", n, "/heartbeat", "std_msgs/msg/Header",
           qos(depth=5, liveliness="MANUAL_BY_TOPIC", deadline_ns=1_500_000_000,
               lifespan_ns=2_000_000_000, lease_ns=3_000_000_000)),
    ])


def test_service_server(run):
    result = run(h.python_node("service_server.py"))
    h.assert_settled_process(result)
    n = "/flag_server"
    h.assert_capture(result.capture, [node("flag_server")],
                     infra(n) + [ep("service", n, "/set_flag", "std_srvs/srv/SetBool", h.QOS_SERVICES)])


def test_service_client(run):
    result = run(h.python_node("service_client.py"))
    h.assert_settled_process(result)
    n = "/flag_client"
    h.assert_capture(result.capture, [node("flag_client")], infra(n) + [
        ep("client", n, "/set_flag", "std_srvs/srv/SetBool", h.QOS_SERVICES),
        ep("subscription", n, "/flag_status", "std_msgs/msg/String"),
    ])


def _action_endpoints(n, action, server: bool):
    a = f"{action}/_action"
    svc_kind, topic_kind = ("service", "publisher") if server else ("client", "subscription")
    return [
        ep(svc_kind, n, f"{a}/send_goal", "test_msgs/action/Fibonacci_SendGoal", h.QOS_SERVICES),
        ep(svc_kind, n, f"{a}/cancel_goal", "action_msgs/srv/CancelGoal", h.QOS_SERVICES),
        ep(svc_kind, n, f"{a}/get_result", "test_msgs/action/Fibonacci_GetResult", h.QOS_SERVICES),
        ep(topic_kind, n, f"{a}/feedback", "test_msgs/action/Fibonacci_FeedbackMessage"),
        ep(topic_kind, n, f"{a}/status", "action_msgs/msg/GoalStatusArray", h.QOS_ACTION_STATUS),
    ]


def test_action_server(run):
    result = run(h.python_node("action_server.py"))
    h.assert_settled_process(result)
    n = "/fibonacci_server"
    h.assert_capture(result.capture, [node("fibonacci_server")],
                     infra(n) + _action_endpoints(n, "/fibonacci", server=True))


def test_action_client(run):
    result = run(h.python_node("action_client.py"))
    h.assert_settled_process(result)
    n = "/fibonacci_client"
    h.assert_capture(result.capture, [node("fibonacci_client")],
                     infra(n) + _action_endpoints(n, "/fibonacci", server=False))


def test_lifecycle_node(run):
    result = run(h.python_node("lifecycle_node.py"))
    h.assert_settled_process(result)
    n = "/lc_node"
    lifecycle = h.lifecycle_infrastructure(n)
    h.assert_capture(result.capture, [node("lc_node")], infra(n) + lifecycle + [
        ep("publisher", n, "/lc_chatter", "std_msgs/msg/String"),
        # created in on_configure, destroyed in on_activate: kept, flagged
        ep("publisher", n, "/scratch", "std_msgs/msg/String", destroyed=True),
    ])


def test_two_nodes_multithreaded_executor(run):
    result = run(h.python_node("two_nodes_mt.py"))
    h.assert_settled_process(result)
    a, b = "/alpha", "/team/beta"
    h.assert_capture(result.capture, [node("alpha"), node("beta", "/team")], infra(a) + infra(b) + [
        ep("publisher", a, "/numbers", "std_msgs/msg/Int32"),
        ep("subscription", b, "/numbers", "std_msgs/msg/Int32"),
        ep("publisher", b, "/team/report", "std_msgs/msg/String"),
    ])


def test_remapped_talker(run):
    result = run(h.python_node(
        "talker.py", "--ros-args", "-r", "__ns:=/robot", "-r", "__node:=renamed",
        "-r", "chatter:=talk", "-p", "x:=1"))
    h.assert_settled_process(result)
    n = "/robot/renamed"
    h.assert_capture(result.capture, [node("renamed", "/robot")],
                     infra(n) + [ep("publisher", n, "/robot/talk", "std_msgs/msg/String")])


def test_publisher_created_by_a_timer_after_startup(run):
    # The publisher comes 0.5 s after spin() starts: a settle time longer than that sees it.
    result = run(h.python_node("timer_publisher.py"), settle_ms=1500)
    h.assert_settled_process(result)
    n = "/late_starter"
    h.assert_capture(result.capture, [node("late_starter")],
                     infra(n) + [ep("publisher", n, "/late", "std_msgs/msg/String")])
    assert result.capture["settle_ms"] == 1500
    if result.capture["quiescence"]["window"]:
        assert result.capture["time_to_settle_ms"] >= 2000 - 100  # 0.5 s + 1.5 s quiet
    else:  # idle once the timer created it and waits again (its next one is after the window)
        assert result.capture["time_to_settle_ms"] >= 500 - 100


def test_node_raising_before_spin(run):
    result = run(h.python_node("raiser.py"))
    assert result.returncode not in (0, None), str(result)
    assert "failing before spin" in result.stderr
    # Never waited, so never settled: the capture written at exit has what was created,
    # and the interpreter's teardown does not count as destroying it.
    h.assert_capture(result.capture, [node("raiser")],
                     infra("/raiser") + [ep("publisher", "/raiser", "/doomed", "std_msgs/msg/String")],
                     state="exit")
    assert result.capture["time_to_settle_ms"] is None
