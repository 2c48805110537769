"""Bags in MCAP as Jazzy's rosbag2 writes them, read back by independent readers."""

import json
import time

from full_disk import fill_up_after
from mcap.exceptions import McapError
from mcap.reader import make_reader
from mcap.records import Message
from mcap.stream_reader import StreamReader
import pytest
from rosbags.highlevel import AnyReader
from simple_robot_control.bag import (BagError, BagWriter, CHUNK_SIZE, INFINITE,
                                      message_definition, metadata_yaml, qos_yaml,
                                      ROSBAG2_METADATA, rosbag2_metadata, topic_entry,
                                      topic_yaml, type_hash)
from simple_robot_control.bag_reading import BagMessages
import yaml

LATCHED = {'history': 'keep_last', 'depth': 1, 'reliability': 'reliable',
           'durability': 'transient_local', 'deadline': INFINITE, 'lifespan': INFINITE,
           'liveliness': 'automatic', 'liveliness_lease_duration': INFINITE,
           'avoid_ros_namespace_conventions': False}
# std_msgs/String 'WAYPOINT 1', serialised: CDR header, length with the NUL, text, NUL.
STATUS = b'\x00\x01\x00\x00' + (11).to_bytes(4, 'little') + b'WAYPOINT 1\x00'


def write_bag(path, count=3):
    bag = BagWriter(path)
    channel = bag.add_topic('/robot_status', 'std_msgs/msg/String', [LATCHED])
    for index in range(count):
        bag.write(channel, 1_000_000_000 + index, STATUS)
    return bag


def test_the_channel_holds_what_rosbag2s_mcap_storage_reads(tmp_path):
    write_bag(tmp_path / 'run.mcap').close()
    with open(tmp_path / 'run.mcap', 'rb') as stream:
        reader = make_reader(stream)
        summary = reader.get_summary()
        header = reader.get_header()
    assert (header.profile, header.library) == ('ros2', 'libmcap 1.3.0')
    (channel,) = summary.channels.values()
    schema = summary.schemas[channel.schema_id]
    assert (channel.topic, channel.message_encoding) == ('/robot_status', 'cdr')
    assert (schema.name, schema.encoding) == ('std_msgs/msg/String', 'ros2msg')
    assert schema.data.decode() == 'string data\n'
    assert channel.metadata['topic_type_hash'] == type_hash('std_msgs/msg/String')
    assert channel.metadata['topic_type_hash'].startswith('RIHS01_')
    (profile,) = yaml.safe_load(channel.metadata['offered_qos_profiles'])
    assert list(profile) == ['history', 'depth', 'reliability', 'durability', 'deadline',
                             'lifespan', 'liveliness', 'liveliness_lease_duration',
                             'avoid_ros_namespace_conventions']
    assert profile['durability'] == 'transient_local'
    assert profile['deadline'] == {'sec': 9223372036, 'nsec': 854775807}
    assert summary.statistics.message_count == 3
    assert summary.statistics.channel_message_counts == {channel.id: 3}


def rosbag2_records(path):
    """Return the bag's rosbag2 metadata records, each parsed as rosbag2's YAML, in file order."""
    with open(path, 'rb') as stream:
        return [yaml.load(record.metadata['serialized_metadata'], Loader=yaml.CSafeLoader)
                for record in make_reader(stream).iter_metadata()
                if record.name == ROSBAG2_METADATA]


def test_rosbag2s_metadata_record_is_written_at_the_start_and_the_end(tmp_path, monkeypatch):
    monkeypatch.delenv('ROS_DISTRO', raising=False)
    write_bag(tmp_path / 'run.mcap').close()
    opening, closing = rosbag2_records(tmp_path / 'run.mcap')
    assert (opening['message_count'], opening['topics_with_message_count']) == (0, [])
    assert opening['starting_time'] == {'nanoseconds_since_epoch': 2 ** 63 - 1}
    assert closing['version'] == 9 and closing['ros_distro'] == 'jazzy'
    assert closing['storage_identifier'] == 'mcap'
    assert closing['message_count'] == 3
    assert closing['starting_time'] == {'nanoseconds_since_epoch': 1_000_000_000}
    assert closing['duration'] == {'nanoseconds': 2}
    assert closing['relative_file_paths'] == ['run.mcap']
    assert closing['files'] == [{'path': 'run.mcap', 'message_count': 3,
                                 'starting_time': {'nanoseconds_since_epoch': 1_000_000_000},
                                 'duration': {'nanoseconds': 2}}]
    (topic,) = closing['topics_with_message_count']
    assert topic == {'message_count': 3, 'topic_metadata': {
        'name': '/robot_status', 'type': 'std_msgs/msg/String', 'serialization_format': 'cdr',
        'offered_qos_profiles': [LATCHED],
        'type_description_hash': type_hash('std_msgs/msg/String')}}
    assert closing['custom_data']['writer'].startswith('simple_robot_control ')


def test_the_metadata_put_together_topic_by_topic_is_the_yaml_of_the_whole():
    topics = [('/robot_status', 'std_msgs/msg/String', [LATCHED], 3),
              ('/robot0/odom', 'nav_msgs/msg/Odometry', [LATCHED, LATCHED], 0),
              ("/a: '-' #b", 'std_msgs/msg/String', [], 12)]
    metadata = rosbag2_metadata('run.mcap', 5, 9, 15)
    # Written out (LATCHED shares INFINITE), as rosbag2 writes it: no anchors.
    whole = json.loads(json.dumps(dict(metadata, topics_with_message_count=[
        dict(topic_entry(topic, kind, profiles), message_count=count)
        for topic, kind, profiles, count in topics])))
    pieces = [topic_yaml(topic_entry(topic, kind, profiles)) + f'  message_count: {count}\n'
              for topic, kind, profiles, count in topics]
    assert metadata_yaml(metadata, pieces) == yaml.safe_dump(whole, sort_keys=False)
    assert metadata_yaml(metadata, []) == yaml.safe_dump(metadata, sort_keys=False)


def test_a_bag_of_thousands_of_topics_finishes_within_a_second(tmp_path):
    # Its whole metadata as YAML at the end took 5.1 s of CPU at 2,424 topics (0.13 s now).
    bag = BagWriter(tmp_path / 'swarm.mcap')
    channels = [bag.add_topic(f'/robot{index}/odom', 'nav_msgs/msg/Odometry', [LATCHED])
                for index in range(2000)]
    for channel in channels:
        bag.write(channel, 1_000_000_000, STATUS)
    started = time.process_time()
    bag.close()
    assert time.process_time() - started < 1.0
    (_, closing) = rosbag2_records(tmp_path / 'swarm.mcap')
    assert len(closing['topics_with_message_count']) == 2000


def test_the_ros_distro_is_the_environments_where_set(tmp_path, monkeypatch):
    monkeypatch.setenv('ROS_DISTRO', 'rolling')
    write_bag(tmp_path / 'run.mcap').close()
    assert rosbag2_records(tmp_path / 'run.mcap')[-1]['ros_distro'] == 'rolling'
    with open(tmp_path / 'run.mcap', 'rb') as stream:
        records = [record.metadata for record in make_reader(stream).iter_metadata()]
    assert {record['ROS_DISTRO'] for record in records} == {'rolling'}


def test_rosbags_reads_every_message_in_order_with_its_qos(tmp_path):
    write_bag(tmp_path / 'run.mcap').close()
    with AnyReader([tmp_path / 'run.mcap']) as reader:
        (connection,) = reader.connections
        assert connection.ext.offered_qos_profiles[0].durability.name == 'TRANSIENT_LOCAL'
        messages = [(stamp, reader.deserialize(data, connection.msgtype).data)
                    for connection, stamp, data in reader.messages()]
    assert messages == [(1_000_000_000 + index, 'WAYPOINT 1') for index in range(3)]


def test_a_bag_cut_short_keeps_its_complete_chunks(tmp_path):
    bag = write_bag(tmp_path / 'cut.mcap', count=40_000)
    bag._stream.flush()  # what FLUSH_PERIOD does while running; then the process is killed
    stamps = []
    with open(tmp_path / 'cut.mcap', 'rb') as stream:
        try:
            for record in StreamReader(stream, emit_chunks=False).records:
                if isinstance(record, Message):
                    stamps.append(record.log_time)
        except McapError:
            pass  # the record the cut went through
    # Whole chunks of about CHUNK_SIZE bytes each (50 bytes a message), from the first on.
    assert CHUNK_SIZE // 50 < len(stamps) < 40_000
    assert stamps == [1_000_000_000 + index for index in range(len(stamps))]


def test_a_full_disk_ends_the_bag_readable_up_to_its_last_complete_chunk(tmp_path, monkeypatch):
    limit = 2 * CHUNK_SIZE + CHUNK_SIZE // 2
    fill_up_after(monkeypatch, limit)
    path = tmp_path / 'full.mcap'
    bag = BagWriter(path)
    channel = bag.add_topic('/robot_status', 'std_msgs/msg/String', [LATCHED])
    with pytest.raises(BagError) as refused:
        for index in range(100_000):
            bag.write(channel, 1_000_000_000 + index, STATUS)
    assert str(refused.value) == f'{path}: cannot write the bag: No space left on device'
    with pytest.raises(BagError):
        bag.write(channel, 0, STATUS)
    bag.close()  # lets the file go, no summary to write
    assert path.stat().st_size <= limit
    messages = BagMessages(path, {'/robot_status'})
    stamps = [message.log_time_ns for message in messages]
    # Two whole chunks of about CHUNK_SIZE bytes each (50-odd bytes a message); not the third.
    assert messages.cut_short and 2 * (CHUNK_SIZE // 60) < len(stamps) <= index + 1
    assert stamps == [1_000_000_000 + index for index in range(len(stamps))]


def test_a_bag_at_its_size_limit_records_no_more_and_is_finished_whole(tmp_path):
    path = tmp_path / 'capped.mcap'
    bag = BagWriter(path, max_bytes=3 * CHUNK_SIZE)
    channel = bag.add_topic('/robot_status', 'std_msgs/msg/String', [LATCHED])
    for index in range(100_000):
        bag.write(channel, 1_000_000_000 + index, STATUS)
    bag.close()
    assert bag.truncated == ('the bag reached its limit of 786,432 bytes: what came after was '
                             'not recorded')
    messages = BagMessages(path, {'/robot_status'})
    stamps = [message.log_time_ns for message in messages]
    assert not messages.cut_short and 0 < len(stamps) < 100_000
    assert stamps == [1_000_000_000 + index for index in range(len(stamps))]
    assert path.stat().st_size <= 4 * CHUNK_SIZE


def test_a_dependency_outside_the_type_store_comes_from_its_installed_msg():
    text = message_definition('simulation_interfaces/msg/EntityState')
    assert text.startswith('std_msgs/Header header\n')
    assert '\nMSG: geometry_msgs/Accel\n' in text
    assert '=' * 80 + '\nMSG: builtin_interfaces/Time\n' in text


def test_an_unknown_type_is_named():
    with pytest.raises(BagError, match='no_such_msgs/msg/Thing'):
        message_definition('no_such_msgs/msg/Thing')


def test_no_profile_no_yaml():
    assert qos_yaml([]) == ''
