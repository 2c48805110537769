"""foxglove_live as Foxglove sees it: channels, CDR messages, Teleop commands, refusals, load."""

import math
import time

from bench.foxglove_client import FoxgloveClient
from foxglove_live.foxglove_live import FoxgloveLive
from foxglove_live.live_commands import PER_CLIENT
from geometry_msgs.msg import Twist, Vector3
from nav_msgs.msg import OccupancyGrid, Odometry
import pytest
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from rclpy.serialization import deserialize_message, serialize_message
from ros_helpers import pose_stamped, ServiceCaller, simulator_and_client, spin_until
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import LaserScan
from simple_robot_control.bag import message_definition
from simulation_interfaces.msg import Result
from simulation_interfaces.srv import DeleteEntity, SpawnEntity
from std_msgs.msg import String

LATCHED = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.TRANSIENT_LOCAL)
RUN = ('/map', '/robot0/odom', '/robot0/laser_0', '/robot_status', '/tf_static')
OK = Result.RESULT_OK


@pytest.fixture
def start_live(ros_context, executor):
    """
    Give a function starting (simulator, client node, foxglove_live) in the executor.

    The server is on a free port; options go to FoxgloveLive, the simulator runs at real_time.
    """
    nodes = []

    def start(real_time=1.0, **options):
        simulator, client = simulator_and_client(ros_context, executor,
                                                 real_time_factor=real_time)
        status = client.create_publisher(String, '/robot_status', LATCHED)
        status.publish(String(data='STARTED 1.000 2.000 0.00'))
        node = FoxgloveLive(port=0, context=ros_context, **options)
        nodes.append(node)
        executor.add_node(node)
        return simulator, client, node
    yield start
    for node in nodes:
        node.shut_down()


@pytest.fixture
def live(start_live):
    """Give (simulator, client node, foxglove_live), as Foxglove's users start them."""
    return start_live()


def connected(executor, node, topics=RUN, **options):
    """Give a Foxglove client once the server advertises every one of topics."""
    client = FoxgloveClient(node.live.port, **options)

    def advertised():
        client.poll()
        return set(topics) <= set(client.channels)
    spin_until(executor, advertised, timeout=20.0, what=f'{topics} advertised')
    return client


def received(executor, client, topics, count=1, what='messages'):
    def enough():
        client.poll()
        return all(len(client.messages[topic]) >= count for topic in topics)
    spin_until(executor, enough, timeout=20.0, what=what)


def test_channels_carry_the_bag_writers_schemas_and_the_runs_cdr_messages(live, executor):
    _, _, node = live
    client = connected(executor, node)
    assert client.server_info['capabilities'] == ['clientPublish']
    for topic, kind in (('/map', 'nav_msgs/msg/OccupancyGrid'),
                        ('/robot0/odom', 'nav_msgs/msg/Odometry'),
                        ('/robot0/laser_0', 'sensor_msgs/msg/LaserScan'),
                        ('/robot_status', 'std_msgs/msg/String')):
        channel = client.channels[topic]
        assert (channel['schemaName'], channel['schemaEncoding'], channel['encoding']) == (
            kind, 'ros2msg', 'cdr')
        assert channel['schema'] == message_definition(kind)
    # Hidden topics (an action's) are not offered, as ros2 topic list hides them.
    assert not [topic for topic in client.channels if '/_' in topic]
    client.subscribe(*RUN)
    received(executor, client, RUN, what='a message of every topic subscribed')
    grid = deserialize_message(client.messages['/map'][0][1], OccupancyGrid)
    assert grid.info.width * grid.info.height == len(grid.data) > 0
    scan = deserialize_message(client.messages['/robot0/laser_0'][0][1], LaserScan)
    assert len(scan.ranges) == 667
    odometry = deserialize_message(client.messages['/robot0/odom'][0][1], Odometry)
    assert math.isclose(odometry.pose.pose.position.x, 1.0, abs_tol=0.01)
    assert deserialize_message(client.messages['/robot_status'][0][1], String).data == (
        'STARTED 1.000 2.000 0.00')
    client.close()


def test_a_client_subscribing_later_gets_the_latched_topics_too(live, executor):
    _, _, node = live
    first = connected(executor, node)
    first.subscribe('/map', '/robot_status')
    received(executor, first, ('/map', '/robot_status'), what="the first client's map")
    second = connected(executor, node)
    second.subscribe('/map', '/robot_status')
    received(executor, second, ('/map', '/robot_status'), what="the second client's map")
    first.close()
    second.close()


def odometry_x(client):
    latest = client.messages['/robot0/odom'][-1][1]
    return deserialize_message(latest, Odometry).pose.pose.position.x


def watching_odometry(executor, node):
    """Give a client subscribed to robot0's odometry, and the x it reads first."""
    client = connected(executor, node)
    client.subscribe('/robot0/odom')
    received(executor, client, ['/robot0/odom'], what='odometry')
    return client, odometry_x(client)


def test_the_teleop_panels_twist_drives_the_robot(live, executor):
    client, start = watching_odometry(executor, live[2])
    channel = client.advertise('/robot0/cmd_vel', 'geometry_msgs/msg/Twist')
    forward = serialize_message(Twist(linear=Vector3(x=0.5)))

    def moved():
        client.publish(channel, forward)
        client.poll()
        return odometry_x(client) > start + 0.2
    spin_until(executor, moved, timeout=20.0, what='the robot driven forward from Foxglove')
    assert not client.statuses
    client.close()


def test_publishing_anything_but_a_command_is_refused(live, executor, capfd):
    node = live[2]
    client, start = watching_odometry(executor, node)
    on_map = client.advertise('/map', 'geometry_msgs/msg/Twist')
    wrong_type = client.advertise('/robot0/cmd_vel', 'std_msgs/msg/String')
    json_command = client.advertise('/robot0/cmd_vel', 'geometry_msgs/msg/Twist', 'json')
    command = client.advertise('/robot0/cmd_vel', 'geometry_msgs/msg/Twist')
    forward = serialize_message(Twist(linear=Vector3(x=0.5)))
    not_finite = serialize_message(Twist(linear=Vector3(x=math.nan)))

    def refused():
        client.poll()
        return len(client.statuses) >= 3
    spin_until(executor, refused, timeout=10.0, what='three refusals')
    texts = [status['message'] for status in client.statuses]
    assert 'cannot publish on /map: only */cmd_vel take messages' in texts[0]
    assert 'std_msgs/msg/String is no geometry_msgs/msg/Twist' in texts[1]
    assert 'its encoding json is not cdr' in texts[2]
    for _ in range(50):
        for channel in (on_map, wrong_type, json_command):
            client.publish(channel, forward)
        client.publish(command, b'\x00\x01\x00\x00garbage')
        client.publish(command, not_finite)
        client.publish(command, forward + bytes(2000))
        client.publish(12345, forward)
    deadline = time.monotonic() + 1.0
    spin_until(executor, lambda: time.monotonic() > deadline, what='the messages handled')
    client.poll()
    assert odometry_x(client) == pytest.approx(start, abs=0.001)
    assert node.count_publishers('/map') == 1
    err = capfd.readouterr().err
    # One line for each kind of refusal, whatever the number of messages.
    assert err.count('cannot publish on /map') == 1
    assert err.count('that is no Twist in CDR (and any more like it)') == 1
    assert err.count('that is not finite') == 1
    assert err.count('bytes (at most 1024)') == 1
    assert err.count('a channel it may not publish on') == 3
    assert 'Traceback' not in err
    client.close()


def test_a_slow_then_vanished_client_never_holds_the_simulator_up(start_live, executor, capfd):
    simulator, sim_client, node = start_live(real_time=4.0, backlog=16)
    beats, scans = [], []
    sim_client.create_subscription(
        Clock, '/clock', lambda message: beats.append(time.monotonic()), 1000)
    # The simulator's first laser reading (a new tree's ray caster compiles then) comes first.
    sim_client.create_subscription(LaserScan, '/robot0/laser_0', scans.append, 10)
    spin_until(executor, lambda: scans, timeout=30.0, what='a laser scan')
    slow = connected(executor, node, receive_buffer=4096)
    slow.subscribe(*slow.channels)
    # From here: the client connected (its handshake blocks this thread, which spins the
    # simulator too, so the beats before it say nothing about the server).
    beats.clear()
    # The slow client reads nothing for four seconds, then is gone without a word.
    deadline = time.monotonic() + 4.0
    spin_until(executor, lambda: time.monotonic() > deadline, what='four seconds')
    slow.vanish()
    deadline = time.monotonic() + 1.0
    spin_until(executor, lambda: time.monotonic() > deadline, what='a second more')
    gaps = [later - earlier for earlier, later in zip(beats, beats[1:])]
    # /clock at up to 200 Hz of wall time: an executor held up by a blocked send would leave a
    # gap of seconds (the client reads nothing for four); a loaded machine leaves tenths.
    assert len(beats) > 200 and max(gaps) < 1.0, (len(beats), max(gaps))
    healthy = connected(executor, node)
    healthy.subscribe('/robot0/odom')
    received(executor, healthy, ['/robot0/odom'], count=10, what='a new client served')
    healthy.close()
    assert 'Traceback' not in capfd.readouterr().err


def test_spawned_robots_appear_and_deleted_ones_go(live, executor):
    _, sim_client, node = live
    call = ServiceCaller(executor, sim_client)
    client = connected(executor, node)
    answer = call(SpawnEntity, 'spawn_entity', name='scout', uri='lab_robot',
                  initial_pose=pose_stamped(5.0, 5.0, 0.5))
    assert answer.result.result == OK

    def offered(topics, present=True):
        def check():
            client.poll()
            return all((topic in client.channels) == present for topic in topics)
        return check
    scout = ('/scout/odom', '/scout/laser_0', '/scout/sonar_0')
    spin_until(executor, offered(scout), timeout=20.0, what='the spawned robot offered')
    assert call(DeleteEntity, 'delete_entity', entity='scout').result.result == OK
    spin_until(executor, offered(scout, present=False), timeout=20.0,
               what='the deleted robot withdrawn')
    assert '/robot0/odom' in client.channels
    client.close()


def test_command_channels_are_bounded_kept_to_robots_that_exist_and_let_go(live, executor):
    _, sim_client, node = live
    client = connected(executor, node)
    channel = client.advertise('/robot0/cmd_vel', 'geometry_msgs/msg/Twist')
    spin_until(executor, lambda: node.live.commands.publishers() == 1, what="robot0's publisher")

    def refused(count):
        def enough():
            client.poll()
            return len(client.statuses) >= count
        return enough
    for index in range(200):
        client.advertise(f'/ghost{index}/cmd_vel', 'geometry_msgs/msg/Twist')
    # Refused at once, in order: once it is said, every ghost has been claimed or refused (as
    # ghosts are let go, later ones take their places; the cap's refusal is said only once).
    client.advertise('/marker', 'geometry_msgs/msg/Twist')
    spin_until(executor, refused(3), what='the ghosts refused, then the marker')
    spin_until(executor, lambda: node.live.commands.claimed() == 1, what='the ghosts let go')
    client.advertise('/robot0/cmd_vel', 'geometry_msgs/msg/TwistStamped')
    spin_until(executor, refused(4), what='a TwistStamped refused where a Twist is subscribed')
    said = ' | '.join(status['message'] for status in client.statuses)
    assert len(client.statuses) == 4, said
    assert f'/ghost{PER_CLIENT - 1}/cmd_vel: a client may publish on {PER_CLIENT} channels at ' \
        'most (and any more like it)' in said
    assert '/ghost0/cmd_vel: nothing subscribes to it as geometry_msgs/msg/Twist (no such ' \
        'robot) (and any more like it)' in said
    assert '/robot0/cmd_vel: nothing subscribes to it as geometry_msgs/msg/TwistStamped' in said
    assert '/marker: only */cmd_vel take messages from Foxglove' in said
    assert node.live.commands.publishers() == 1
    assert not sim_client.get_publishers_info_by_topic('/ghost0/cmd_vel')
    client.publish(channel, serialize_message(Twist(linear=Vector3(x=0.1))))
    client.close()
    # The client gone, its publisher goes: a controller may then publish on the robot's cmd_vel.
    spin_until(executor, lambda: not node.count_publishers('/robot0/cmd_vel'),
               what='the publisher of the client that left destroyed')
    assert node.live.commands.publishers() == 0
