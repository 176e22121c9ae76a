"""Interface contracts of every node of this package, checked with the pytest plugin.

Each test names its golden contract (in ../contracts/, which also says how to run the node);
the plugin runs the executable on the recording middleware, hands the capture to the test
through the ``interfaces`` fixture and, after the test body, fails the test with a drift
report if the capture no longer matches the contract. Accept a deliberate change with
``pytest --update-golden``.

The assertions in the bodies are examples of what a test can check beyond the contract.
"""

import pytest


@pytest.mark.interfaces('../contracts/talker.interfaces.yaml')
def test_talker(interfaces):
    (chatter,) = interfaces['/talker'].publishers
    assert (chatter.name, chatter.type) == ('/chatter', 'std_msgs/msg/String')


@pytest.mark.interfaces('../contracts/listener.interfaces.yaml')
def test_listener(interfaces):
    assert [s.name for s in interfaces['/listener'].subscriptions] == ['/chatter']


@pytest.mark.interfaces('../contracts/laser_driver.interfaces.yaml')
def test_laser_driver_publishes_with_system_defaults(interfaces):
    # REP-2003: sensor drivers publish with the system default QoS
    (scan,) = interfaces['/laser_driver'].publishers
    assert scan.qos['reliability'] == 'SYSTEM_DEFAULT'


@pytest.mark.interfaces('../contracts/scan_consumer.interfaces.yaml')
def test_scan_consumer_subscribes_with_sensor_data(interfaces):
    # REP-2003: consumers subscribe with the sensor data profile
    (scan,) = interfaces['/scan_consumer'].subscriptions
    assert scan.qos == {'history': 'KEEP_LAST', 'depth': 5,
                        'reliability': 'BEST_EFFORT', 'durability': 'VOLATILE'}


@pytest.mark.interfaces('../contracts/map_server.interfaces.yaml')
def test_map_server_latches_the_map(interfaces):
    (map_pub,) = interfaces['/map_server'].publishers
    assert map_pub.qos['durability'] == 'TRANSIENT_LOCAL'
    assert map_pub.qos['depth'] == 1


@pytest.mark.interfaces('../contracts/motor_enable_server.interfaces.yaml')
def test_motor_enable_server(interfaces):
    assert [s.type for s in interfaces['/motor_enable_server'].service_servers] == ['std_srvs/srv/SetBool']


@pytest.mark.interfaces('../contracts/motor_enable_client.interfaces.yaml')
def test_motor_enable_client(interfaces):
    assert [c.name for c in interfaces['/motor_enable_client'].service_clients] == ['/enable_motors']


@pytest.mark.interfaces('../contracts/fibonacci_server.interfaces.yaml')
def test_fibonacci_action_server(interfaces):
    (action,) = interfaces['/fibonacci_server'].action_servers
    assert (action.name, action.type) == ('/fibonacci', 'test_msgs/action/Fibonacci')


@pytest.mark.interfaces('../contracts/fibonacci_client.interfaces.yaml')
def test_fibonacci_action_client(interfaces):
    assert [a.name for a in interfaces['/fibonacci_client'].action_clients] == ['/fibonacci']


@pytest.mark.interfaces('../contracts/lifecycle_talker.interfaces.yaml')
def test_lifecycle_talker_once_active(interfaces):
    # the publisher only exists after on_configure: the middleware configured and activated it
    node = interfaces['/lifecycle_talker']
    assert node.lifecycle_state == 'active'
    assert [(p.name, p.created_in) for p in node.publishers] == [('/lifecycle_chatter', 'configure')]


@pytest.mark.interfaces('../contracts/relay.interfaces.yaml')
def test_two_nodes_in_one_process(interfaces):
    assert sorted(interfaces.nodes) == ['/relay_publisher', '/relay_subscriber']


@pytest.mark.interfaces('../contracts/c_talker.interfaces.yaml')
def test_c_node_on_rcl(interfaces):
    node = interfaces['/c_talker']
    assert [p.name for p in node.publishers] == ['/chatter']
    assert [s.name for s in node.subscriptions] == ['/c_talker/enable']


# ---------------------------------------------------------------- virtual time
# Interfaces that appear seconds after start, and programs that end by themselves: the
# middleware's virtual time (target option `horizon`, 10 s by default) makes a node's first
# seconds pass at once, so these are captured with the default options, in milliseconds.


@pytest.mark.interfaces('../contracts/battery_monitor.interfaces.yaml')
def test_battery_monitor_publisher_created_by_a_timer_after_3_s(interfaces):
    (battery,) = interfaces['/battery_monitor'].publishers
    assert battery.name == '/battery_state'
    (raw,) = battery.endpoints
    assert raw.created_virtual_ms >= 3000  # created 3 s into the node's (virtual) life


@pytest.mark.interfaces('../contracts/watchdog.interfaces.yaml')
def test_watchdog_subscribes_on_its_fifth_tick(interfaces):
    (heartbeat,) = interfaces['/watchdog'].subscriptions
    assert heartbeat.endpoints[0].created_virtual_ms >= 5000


@pytest.mark.interfaces('../contracts/old_school_talker.interfaces.yaml')
def test_old_school_loop_settles_without_an_executor(interfaces):
    # No executor: it settles while it sleeps after a publish, and virtual time steps its
    # time.sleep(0.5) calls like a timer up to the horizon.
    assert interfaces.settled_by == 'sleep'
    assert interfaces.virtual_time.horizon_reached
    assert [p.name for p in interfaces['/old_school_talker'].publishers] == ['/chatter']


@pytest.mark.interfaces('../contracts/self_test.interfaces.yaml')
def test_self_test_ends_by_itself(interfaces):
    assert interfaces.ended_by_itself
    assert [p.name for p in interfaces['/self_test'].publishers] == ['/self_test/report']


@pytest.mark.interfaces('../contracts/motor_deadline_client.interfaces.yaml')
def test_motor_deadline_client_gives_up_after_settling(interfaces):
    assert interfaces.returncode == 1  # gave up: its 5 s deadline passed at once in virtual time
    assert [c.name for c in interfaces['/motor_deadline_client'].service_clients] == ['/enable_motors']


# The whole robot: every process launch/robot.launch.xml starts, checked as one system (the
# contract's nodes, and every connection between them: types, QoS, peers, node names).
@pytest.mark.system_contract('../contracts/robot.system.yaml')
def test_robot_system(system_capture):
    lidar = next(p for p in system_capture.processes if p.launched.executable == 'laser_driver')
    assert lidar.node_names == ['/robot1/lidar']
    assert any(a.endswith('config/robot_params.yaml') for a in lidar.capture.command)

