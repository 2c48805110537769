"""record_run as an executable: Ctrl-C leaves a complete bag, a kill keeps its chunks."""

import signal
import time

from mcap.exceptions import McapError
from mcap.reader import make_reader
from mcap.records import Channel, Message
from mcap.stream_reader import StreamReader
from processes import start, start_logged, stop, wait_for_text
from rosbags.highlevel import AnyReader


def test_ctrl_c_leaves_a_complete_bag_of_the_run(tmp_path):
    simulator = start_logged('stdr_lite', '--ros-args', '-p', 'real_time_factor:=5.0',
                             log=tmp_path / 'stdr_lite.log')
    try:
        wait_for_text(tmp_path / 'stdr_lite.log', 'real_time_factor', simulator)
        recorder = start('record_run', '--ros-args', '-p', f'bag:={tmp_path / "run.mcap"}',
                         '--log-level', 'info')
        bag, deadline = tmp_path / 'run.mcap', time.monotonic() + 30.0
        # A first chunk written out: a few seconds of the run.
        while not (bag.exists() and bag.stat().st_size > 100_000):
            assert time.monotonic() < deadline and recorder.poll() is None, 'no chunk written'
            time.sleep(0.1)
        recorder.send_signal(signal.SIGINT)
        _, stderr = recorder.communicate(timeout=15)
        assert recorder.returncode == 0, stderr
        assert 'Traceback' not in stderr
    finally:
        assert stop(simulator, signal.SIGINT)[0] == 0
    with open(tmp_path / 'run.mcap', 'rb') as stream:
        summary = make_reader(stream).get_summary()
    assert summary.statistics.message_count > 100
    with AnyReader([tmp_path / 'run.mcap']) as reader:
        topics = {connection.topic for connection in reader.connections}
        count = sum(1 for _ in reader.messages())
    assert {'/robot0/odom', '/tf', '/tf_static', '/map'} <= topics
    assert count == summary.statistics.message_count
    assert f'{tmp_path / "run.mcap"}: {count} messages of' in stderr


def test_a_killed_recording_keeps_its_chunks(tmp_path):
    simulator = start_logged('stdr_lite', '--ros-args', '-p', 'real_time_factor:=5.0',
                             log=tmp_path / 'stdr_lite.log')
    try:
        wait_for_text(tmp_path / 'stdr_lite.log', 'real_time_factor', simulator)
        recorder = start('record_run', '--ros-args', '-p', f'bag:={tmp_path / "run.mcap"}')
        bag, deadline = tmp_path / 'run.mcap', time.monotonic() + 30.0
        while not (bag.exists() and bag.stat().st_size > 100_000):
            assert time.monotonic() < deadline and recorder.poll() is None, 'no chunk written'
            time.sleep(0.1)
        recorder.kill()
        recorder.communicate(timeout=15)
    finally:
        assert stop(simulator, signal.SIGINT)[0] == 0
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
