"""foxglove_live as an executable: its line, a client falling behind, a hostile one, bad input."""

import os
from pathlib import Path
import re
import signal
import socket
import subprocess
import sys
import time

from bench.foxglove_client import FoxgloveClient
from foxglove_live.foxglove_live import connection_line
from foxglove_live.live_view import exposure_line
from mcap.reader import make_reader
from processes import run, start_logged, stop, wait_for_text, wait_until
import pytest
from rclpy.serialization import deserialize_message
from rosgraph_msgs.msg import Clock
from std_msgs.msg import String
import yaml

REPOSITORY = Path(__file__).resolve().parents[2]

LINE = re.compile(r'connect to ws://localhost:(\d+) \(from another machine: '
                  r'ssh -L \1:localhost:\1')


@pytest.fixture
def serve(tmp_path):
    """
    Give a function running stdr_lite and foxglove_live on a free port.

    Its argument is the simulator's real_time_factor (0: as fast as it goes); it gives (port,
    log, foxglove_live's process).
    """
    processes = []

    def start(real_time):
        processes.append(start_logged(
            'stdr_lite', '--ros-args', '-p', f'real_time_factor:={real_time:.1f}',
            '--log-level', 'warn', log=tmp_path / 'stdr_lite.log'))
        log = tmp_path / 'foxglove_live.log'
        processes.append(start_logged('foxglove_live', '--ros-args', '-p', 'port:=0', log=log))
        said = wait_for_text(log, 'connect to ws://', processes[-1])
        return int(LINE.search(said).group(1)), log, processes[-1]
    yield start
    for process in reversed(processes):
        assert stop(process, signal.SIGINT)[0] == 0


def advertised(port, topics, **options):
    client = FoxgloveClient(port, **options)

    def offered():
        client.poll()
        return set(topics) <= set(client.channels)
    wait_until(offered, f'{topics} offered', timeout=60.0)
    return client


def test_a_client_falling_behind_is_said_once_and_served_again(serve):
    port, log, _ = serve(0.0)  # as fast as it goes: much to send
    # Every topic of the run offered, the map and the laser among them: much to send (with
    # /clock alone, 30-byte messages, the socket buffers took minutes to fill on a busy machine).
    slow = advertised(port, ['/clock', '/map', '/robot0/laser_0', '/robot0/odom'],
                      receive_buffer=4096)
    slow.subscribe(*slow.channels)
    # The client reads nothing: what it is sent piles up in the sockets' buffers, then in its
    # queue, whose oldest messages are then dropped.
    wait_until(lambda: 'falling behind' in log.read_text(), 'the client falling behind',
               timeout=60.0)
    # Once it reads again it is served the run as it goes on.
    deadline = time.monotonic() + 3.0
    while time.monotonic() < deadline:
        slow.poll()
    ticks = [deserialize_message(payload, Clock).clock.sec
             for _, payload in slow.messages['/clock']]
    assert len(ticks) > 100 and ticks[-1] > ticks[0]
    text = log.read_text()
    assert text.count('a client is falling behind, its oldest messages are dropped') == 1
    slow.close()


def test_a_hostile_client_gets_answers_and_the_node_one_line_each(serve):
    port, log, _ = serve(1.0)
    hostile = advertised(port, ['/robot0/odom'])
    ids = [channel['id'] for channel in hostile.channels.values()]
    for round_number in range(50):
        subscriptions = [{'id': 1000 * round_number + index, 'channelId': channel}
                         for index, channel in enumerate(ids)]
        hostile.send({'op': 'subscribe', 'subscriptions': subscriptions})
        hostile.unsubscribe(*[subscription['id'] for subscription in subscriptions])
    for _ in range(100):
        hostile.socket.send('{"op": "subscribe", "subscriptions": 7')
        hostile.socket.send('not json at all')
        hostile.socket.send(b'\x07garbage')
        hostile.publish(424242, b'\x00' * 64)
        hostile.send({'op': 'subscribe', 'subscriptions': [{'id': 1, 'channelId': 999999}]})
    watcher = advertised(port, ['/robot0/odom'])
    watcher.subscribe('/robot0/odom')
    wait_until(lambda: watcher.poll() or len(watcher.messages['/robot0/odom']) > 20,
               'odometry for a well-behaved client after the flood', timeout=60.0)
    watcher.close()
    lines = [line for line in log.read_text().splitlines() if 'Foxglove:' in line]
    assert 0 < len(lines) <= 8, lines
    assert 'Traceback' not in log.read_text()


def test_a_port_in_use_is_one_line_and_exit_code_2():
    with socket.socket() as taken:
        taken.bind(('127.0.0.1', 0))
        taken.listen()
        port = taken.getsockname()[1]
        result = run('foxglove_live', '--ros-args', '-p', f'port:={port}')
    assert result.returncode == 2
    assert result.stderr.startswith(f'foxglove_live: error: cannot serve Foxglove on '
                                    f'127.0.0.1:{port}: ')
    assert len(result.stderr.splitlines()) == 1 and 'Traceback' not in result.stderr


def test_a_port_out_of_range_is_refused():
    result = run('foxglove_live', '--ros-args', '-p', 'port:=70000')
    assert result.returncode == 2
    assert 'port' in result.stderr and len(result.stderr.splitlines()) == 1


@pytest.mark.parametrize('host', ['127.0.0.1', '127.0.0.2', 'localhost', '::1'])
def test_loopback_is_served_quietly(host):
    assert exposure_line(host, 8765) is None


@pytest.mark.parametrize('host', ['0.0.0.0', '192.168.1.20', 'lab-server'])
def test_any_other_address_is_said_to_be_open_to_the_network(host):
    assert exposure_line(host, 8765).startswith(
        f'Foxglove is served on {host}:8765: open to the network')


@pytest.mark.parametrize('host', ['0.0.0.0', '::'])
def test_a_wildcard_address_is_never_printed_as_one_to_connect_to(host):
    line = connection_line(host, 8765)
    assert line.startswith('foxglove_live: open Foxglove and connect to ws://localhost:8765 '
                           f'(from another machine: ws://{socket.gethostname()}:8765)')
    assert host not in line.replace('8765', '')


def test_a_named_address_is_printed_as_a_url_writes_it():
    assert connection_line('192.168.1.20', 8765).endswith('connect to ws://192.168.1.20:8765')
    assert connection_line('fd00::20', 8765).endswith('connect to ws://[fd00::20]:8765')


def free_port():
    with socket.socket() as probe:
        probe.bind(('127.0.0.1', 0))
        return probe.getsockname()[1]


def test_the_demo_with_foxglove_prints_the_line_and_streams_the_run(tmp_path):
    port = free_port()
    demo = subprocess.Popen(
        ['bash', str(REPOSITORY / 'scripts' / 'demo.sh')], stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT, text=True, cwd=tmp_path,
        env=dict(os.environ, VIEWER='foxglove', FOXGLOVE_PORT=str(port),
                 PATH=f'{Path(sys.executable).parent}{os.pathsep}{os.environ["PATH"]}'))
    try:
        first = demo.stdout.readline()
        assert first.startswith(f'foxglove_live: open Foxglove and connect to ws://localhost:'
                                f'{port} (from another machine: ssh -L {port}:localhost:{port}')
        assert 'config/foxglove_lab_layout.json' in demo.stdout.readline()
        client = advertised(port, ['/robot0/odom'])
        wait_until(lambda: client.poll() or '/robot_status' in client.channels,
                   'robot_status offered')
        client.subscribe('/robot0/odom', '/robot_status', '/robot0/laser_0')
        texts = []

        def finished():
            client.poll()
            texts[:] = [deserialize_message(payload, String).data
                        for _, payload in client.messages['/robot_status']]
            return 'FINISHED' in texts
        wait_until(finished, 'the run streamed to its end', timeout=60.0)
        assert texts[0].startswith('STARTED') and len(client.messages['/robot0/laser_0']) > 10
        client.close()
        output, _ = demo.communicate(timeout=30)
    finally:
        demo.kill()
    assert demo.returncode == 0, output
    assert 'Traceback' not in output
    # The demo's bag shows the robot's sensors, and ros2 bag info's ROS Distro.
    with open(tmp_path / 'run.mcap', 'rb') as stream:
        reader = make_reader(stream)
        topics = {channel.topic for channel in reader.get_summary().channels.values()}
        (rosbag2, *_) = [record.metadata for record in reversed(list(reader.iter_metadata()))
                         if record.name == 'rosbag2']
    assert {'/robot0/laser_0', '/robot0/sonar_0', '/robot0/sonar_4', '/robot_status'} <= topics
    assert yaml.safe_load(rosbag2['serialized_metadata'])['ros_distro'] == 'jazzy'
