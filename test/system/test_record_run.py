"""record_run as an executable: Ctrl-C leaves a complete bag, a kill keeps its chunks."""

import os
import signal

from bench.realtime import write_robot_grid
from mcap.exceptions import McapError
from mcap.reader import make_reader
from mcap.records import Channel, Message
from mcap.stream_reader import StreamReader
from processes import start, start_logged, stop, wait_for_text, wait_until
import pytest
from rosbags.highlevel import AnyReader
import yaml


# Transient-local topics: their messages were sent when the simulator started.
LATCHED = ('/map', '/tf_static', '/stdr_lite/robot_markers', '/stdr_lite/obstacle_markers')


@pytest.fixture
def recording(tmp_path, request):
    """
    Run stdr_lite and record_run; give (recorder, bag) once the first chunk is written.

    The simulator runs the lab's robot, or (parametrized indirectly) that many lab robots.
    """
    robots = getattr(request, 'param', None)
    world = ['-p', f'robots_file:={write_robot_grid(tmp_path, robots)}'] if robots else []
    simulator = start_logged('stdr_lite', '--ros-args', '-p', 'real_time_factor:=5.0', *world,
                             log=tmp_path / 'stdr_lite.log')
    try:
        wait_for_text(tmp_path / 'stdr_lite.log', 'real_time_factor', simulator)
        bag = tmp_path / 'run.mcap'
        recorder = start('record_run', '--ros-args', '-p', f'bag:={bag}', '--log-level', 'info')
        # Chunks written out, every robot's odometry among them, and the latched topics (the
        # recorder follows the graph a slice at a time: on a busy machine they may come last).

        def written():
            if not (bag.exists() and bag.stat().st_size > 100_000):
                return False
            topics = written_topics(bag, '')
            return (len([topic for topic in topics if topic.endswith('/odom')]) == (robots or 1)
                    and {'/map', '/tf_static'} <= topics)
        wait_until(written, "chunks with every robot's odometry and the latched topics written",
                   recorder, timeout=60.0)
        yield recorder, bag
    finally:
        assert stop(simulator, signal.SIGINT)[0] == 0


@pytest.mark.parametrize('recording', [50], indirect=True, ids=['50 robots'])
def test_ctrl_c_leaves_a_complete_bag_of_the_run(recording, request):
    recorder, bag = recording
    recorder.send_signal(signal.SIGINT)
    _, stderr = recorder.communicate(timeout=15)
    assert recorder.returncode == 0, stderr
    assert 'Traceback' not in stderr
    with open(bag, 'rb') as stream:
        reader = make_reader(stream)
        summary = reader.get_summary()
        (rosbag2, *_) = [record.metadata for record in reversed(list(reader.iter_metadata()))
                         if record.name == 'rosbag2']
        delays = [message.log_time - message.publish_time
                  for _, channel, message in reader.iter_messages()
                  if channel.topic not in LATCHED]
    assert summary.statistics.message_count > 100
    odometry = [channel for channel in summary.channels.values()
                if channel.topic.endswith('/odom')]
    assert len(odometry) == (request.node.callspec.params['recording'] or 1)
    with AnyReader([bag]) as reader:
        topics = {connection.topic for connection in reader.connections}
        count = sum(1 for _ in reader.messages())
    # The run with the robot's sensors, as Foxglove shows it and ros2 bag info lists it.
    assert {'/robot0/odom', '/tf', '/tf_static', '/map', '/robot0/laser_0',
            '/robot0/sonar_0'} <= topics
    assert count == summary.statistics.message_count
    assert f'{bag}: {count} messages of' in stderr
    metadata = yaml.safe_load(rosbag2['serialized_metadata'])
    assert metadata['ros_distro'] == os.environ.get('ROS_DISTRO', 'jazzy')
    assert metadata['message_count'] == count
    assert {topic['topic_metadata']['name']: topic['message_count']
            for topic in metadata['topics_with_message_count']} == {
        channel.topic: summary.statistics.channel_message_counts.get(channel_id, 0)
        for channel_id, channel in summary.channels.items()}
    # Each message's publish time is when it was sent, before it was received (both wall time);
    # a latched one was sent when the simulator started, however long before the recorder.
    # A failure says how many, of how many, and how far off (ns): seen under load, not alone.
    off = [delay for delay in delays if not 0 < delay < 5 * 10 ** 9]
    assert not off, (len(off), len(delays), min(delays), max(delays), off[:5])


def test_a_killed_recording_keeps_its_chunks(recording):
    recorder, bag = recording
    recorder.kill()
    recorder.communicate(timeout=15)
    assert odometry_messages(bag) > 10


def test_a_second_signal_ends_at_once_keeping_the_chunks(recording):
    recorder, bag = recording
    # Two signals of one kind sent at once may reach a process as one: a Ctrl-C, then SIGTERM.
    recorder.send_signal(signal.SIGINT)
    recorder.send_signal(signal.SIGTERM)
    recorder.communicate(timeout=15)
    assert recorder.returncode == 130
    assert odometry_messages(bag) > 10


def written_topics(bag, ending):
    """Return the topics ending so of the complete chunks written to a bag so far."""
    topics = set()
    with open(bag, 'rb') as stream:
        try:
            for record in StreamReader(stream, emit_chunks=False).records:
                if isinstance(record, Channel) and record.topic.endswith(ending):
                    topics.add(record.topic)
        except McapError:
            pass  # the chunk being written
    return topics


def odometry_messages(bag):
    """Count robot0's odometry in a bag, as far as it can be read."""
    channels, messages = {}, 0
    with open(bag, 'rb') as stream:
        try:
            for record in StreamReader(stream, emit_chunks=False).records:
                if isinstance(record, Channel):
                    channels[record.id] = record.topic
                messages += isinstance(record, Message) and channels[record.channel_id] == (
                    '/robot0/odom')
        except McapError:
            pass  # the record the kill went through
    return messages
