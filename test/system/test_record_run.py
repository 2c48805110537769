"""record_run as an executable: Ctrl-C leaves a complete bag, a kill keeps its chunks."""

import os
import signal

from mcap.exceptions import McapError
from mcap.reader import make_reader
from mcap.records import Channel, Message
from mcap.stream_reader import StreamReader
from processes import start, start_logged, stop, wait_for_text, wait_until
import pytest
from rosbags.highlevel import AnyReader
import yaml


@pytest.fixture
def recording(tmp_path):
    """Run stdr_lite and record_run; give (recorder, bag) once the first chunk is written."""
    simulator = start_logged('stdr_lite', '--ros-args', '-p', 'real_time_factor:=5.0',
                             log=tmp_path / 'stdr_lite.log')
    try:
        wait_for_text(tmp_path / 'stdr_lite.log', 'real_time_factor', simulator)
        bag = tmp_path / 'run.mcap'
        recorder = start('record_run', '--ros-args', '-p', f'bag:={bag}', '--log-level', 'info')
        # A first chunk written out: a few seconds of the run.
        wait_until(lambda: bag.exists() and bag.stat().st_size > 100_000, 'a chunk written',
                   recorder, timeout=30.0)
        yield recorder, bag
    finally:
        assert stop(simulator, signal.SIGINT)[0] == 0


def test_ctrl_c_leaves_a_complete_bag_of_the_run(recording):
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
                  for _, _, message in reader.iter_messages()]
    assert summary.statistics.message_count > 100
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
        summary.channels[channel].topic: messages
        for channel, messages in summary.statistics.channel_message_counts.items()}
    # Each message's publish time is when it was sent, before it was received (both wall time).
    assert all(0 < delay < 5 * 10 ** 9 for delay in delays)


def test_a_killed_recording_keeps_its_chunks(recording):
    recorder, bag = recording
    recorder.kill()
    recorder.communicate(timeout=15)
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
    assert messages > 10
