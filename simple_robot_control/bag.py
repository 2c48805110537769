"""
Runs written as rosbag2 bags in MCAP, the way Jazzy's `ros2 bag record` writes them.

One .mcap file that ros2 bag (Jazzy's MCAP storage plugin), Foxglove and rosbags all open: the
ros2 profile (CDR messages, ros2msg schemas with their dependencies), a channel per topic whose
metadata holds the offered QoS profiles in rosbag2's YAML (so transient-local topics replay as
transient local) and the type hash, chunks written out as they fill (a bag cut short stays
readable up to its last chunk), and the summary with its statistics at the end. As rosbag2's
MCAP storage (Jazzy, 0.26.5) does, the header names the C++ mcap library rosbag2 links ("libmcap
1.3.0") and a `rosbag2` metadata record, written at the start and again at the end, holds the bag's
metadata in rosbag2's YAML (version 9: topics, counts, times, ROS_DISTRO), so that `ros2 bag info`
shows the distribution; who really wrote the bag is in that metadata's custom_data. The file
format is mcap's; the message definitions come from rosbags' Jazzy type store, or from the
installed .msg files for the types it lacks. No ROS client here: messages arrive serialised.
"""

from functools import lru_cache
from importlib.metadata import PackageNotFoundError, version
import json
import os
from pathlib import Path
import sys
import time
from typing import BinaryIO

from mcap.writer import CompressionType, Writer
from rosbags.typesys import get_types_from_msg, get_typestore, Stores
from rosbags.typesys.base import TypesysError
import yaml

# What rosbag2 0.26.5 (Jazzy) writes: its header's library (the C++ mcap release it vendors), its
# metadata record's name and the version of the metadata inside.
ROSBAG2_LIBRARY = 'libmcap 1.3.0'
ROSBAG2_METADATA = 'rosbag2'
ROSBAG2_METADATA_VERSION = 9
# The distribution of the ROS 2 wheels this package runs on, where ROS_DISTRO is not set.
ROS_DISTRO = 'jazzy'
# The metadata record naming the run: {'course': the waypoint file's name}.
RUN_METADATA = 'simple_robot_control.run'
# rosbag2's MCAP storage defaults to chunks of about 768 KiB; smaller ones lose less when a
# recording is killed, at a few bytes of index each.
CHUNK_SIZE = 256 << 10
# Bytes reach the disk at least this often (wall seconds), so a killed recording keeps them.
FLUSH_PERIOD = 0.5
# Finishing a bag, measured here: about 60 us a topic (its channel, statistics and metadata
# entries) and tens of us a chunk (its index); the bound given is five times that, plus 0.1 s,
# for a loaded machine.
FINISH_PER_TOPIC = 60e-6
FINISH_PER_CHUNK = 30e-6
FINISH_MARGIN = 5.0
# rmw's infinite duration, as rosbag2 writes it for a policy a publisher leaves unset.
INFINITE = {'sec': 9223372036, 'nsec': 854775807}
# The list of topics in rosbag2's metadata.
TOPICS_KEY = 'topics_with_message_count'
QOS_KEYS = ('history', 'depth', 'reliability', 'durability', 'deadline', 'lifespan',
            'liveliness', 'liveliness_lease_duration', 'avoid_ros_namespace_conventions')
_TYPESTORE = get_typestore(Stores.ROS2_JAZZY)


class _YamlDumper(getattr(yaml, 'CSafeDumper', yaml.SafeDumper)):
    """
    YAML as rosbag2 (yaml-cpp) writes it: no anchors or aliases, a value shared is written out.

    libyaml's emitter where PyYAML has it: the same text as PyYAML's own, sooner.
    """

    def ignore_aliases(self, data):
        return True


class BagError(ValueError):
    """A topic's type cannot be described, or the bag cannot be written."""


def _share_folders():
    prefixes = os.environ.get('AMENT_PREFIX_PATH', '').split(os.pathsep) + [sys.prefix]
    return [Path(prefix) / 'share' for prefix in prefixes if prefix]


def _installed(type_name, suffix):
    """Return the installed interface file of type_name (pkg/msg/Type) with suffix, or None."""
    package, kind, name = type_name.split('/')
    for share in _share_folders():
        path = share / package / kind / f'{name}{suffix}'
        if path.is_file():
            return path
    return None


def message_definition(type_name: str) -> str:
    """Return the ros2msg schema of type_name: its .msg text, then each dependency's."""
    for _ in range(100):
        try:
            return _TYPESTORE.generate_msgdef(type_name, ros_version=2)[0]
        except (TypesysError, KeyError) as error:
            missing = _missing_type(error, type_name)
            path = _installed(missing, '.msg') if missing.count('/') == 2 else None
            if path is None:
                raise BagError(f'{type_name}: no message definition of {missing} found in '
                               'the type store or the installed packages') from None
            _TYPESTORE.register(get_types_from_msg(path.read_text(), missing))
    raise BagError(f'{type_name}: its definition has too many dependencies')


def _missing_type(error, type_name):
    """Name the type a type store error is about: a pkg/msg/Type, or the one asked for."""
    for word in str(error).replace('"', ' ').replace("'", ' ').split():
        if word.count('/') == 2 and word not in _TYPESTORE.fielddefs:
            return word
    return type_name


@lru_cache(maxsize=None)
def type_hash(type_name: str) -> str:
    """Return the RIHS01 hash of type_name from its installed type description, or ''."""
    path = _installed(type_name, '.json')
    if path is None:
        return ''
    try:
        hashes = json.loads(path.read_text())['type_hashes']
        return next(entry['hash_string'] for entry in hashes if entry['type_name'] == type_name)
    except (ValueError, KeyError, TypeError, StopIteration):
        return ''


def qos_yaml(profiles: list[dict]) -> str:
    """Write offered QoS profiles as rosbag2 (bag version 9) stores them in a channel."""
    return _qos_yaml(json.dumps(profiles))


@lru_cache(maxsize=256)
def _qos_yaml(profiles_json):
    """qos_yaml of profiles given as JSON: a swarm's thousands of topics offer a few kinds."""
    profiles = json.loads(profiles_json)
    return yaml.dump([{key: profile[key] for key in QOS_KEYS} for profile in profiles],
                     Dumper=_YamlDumper, sort_keys=False,
                     default_flow_style=False).strip() if profiles else ''


class BagWriter:
    """
    Writes one MCAP bag: add_topic once per topic, then write its serialised messages.

    A write the file system refuses (a full disk) raises BagError and ends the bag there: what
    reached the disk before stays readable up to its last complete chunk, and close() then
    only lets the file go. With max_bytes, messages that would take the file beyond it are
    not written (truncated says so), and the bag is finished as usual.
    """

    def __init__(self, path: str | os.PathLike, max_bytes: int | None = None):
        self.path = Path(path)
        self.max_bytes = max_bytes
        self.truncated = ''
        try:
            self._stream: BinaryIO = open(self.path, 'wb')
        except OSError as error:
            raise BagError(f'{path}: cannot write the bag: {error.strerror}') from None
        self._writer = Writer(self._stream, chunk_size=CHUNK_SIZE,
                              compression=CompressionType.NONE)
        self._schemas, self._channels = {}, {}
        # Per channel: its entry of rosbag2's metadata, as YAML, and how many messages it holds.
        self._topic_yaml, self._counts = {}, {}
        self._first_ns = self._last_ns = None
        self._flushed_at = time.monotonic()
        self.message_count = 0
        self.failure = None
        self._guarded(lambda: self._writer.start(profile='ros2', library=ROSBAG2_LIBRARY))
        self._write_rosbag2_metadata()

    def _guarded(self, action):
        """Run action on the file; a refused write ends the bag and raises BagError."""
        if self.failure is not None:
            raise BagError(self.failure)
        try:
            return action()
        except OSError as error:
            self.failure = f'{self.path}: cannot write the bag: {error.strerror or error}'
            self._let_go()
            raise BagError(self.failure) from None

    def _let_go(self):
        """Close the file without finishing the bag; bytes the disk refused are dropped."""
        try:
            self._stream.close()
        except OSError:
            pass

    def add_metadata(self, name: str, data: dict[str, str]) -> None:
        """Write a metadata record (MCAP's own: ros2 bag skips it, Foxglove shows it)."""
        self._guarded(lambda: self._writer.add_metadata(name, data))

    def add_topic(self, topic: str, type_name: str, offered_qos: list[dict]) -> int:
        """Add a topic of type_name (pkg/msg/Type); return its channel id."""
        if topic in self._channels:
            return self._channels[topic]
        if type_name not in self._schemas:
            definition = message_definition(type_name).encode()
            self._schemas[type_name] = self._guarded(lambda: self._writer.register_schema(
                name=type_name, encoding='ros2msg', data=definition))
        channel = self._channels[topic] = self._guarded(lambda: self._writer.register_channel(
            topic=topic, message_encoding='cdr', schema_id=self._schemas[type_name],
            metadata={'offered_qos_profiles': qos_yaml(offered_qos),
                      'topic_type_hash': type_hash(type_name)}))
        self._topic_yaml[channel] = topic_yaml(topic_entry(topic, type_name, offered_qos))
        self._counts[channel] = 0
        return channel

    def write(self, channel: int, log_time_ns: int, data: bytes,
              publish_time_ns: int | None = None) -> None:
        """Write one serialised message of a channel: received at log_time_ns, sent at publish."""
        if self.truncated:
            return
        if self.max_bytes is not None and (
                self._guarded(self._stream.tell) + len(data) > self.max_bytes):
            self.truncated = (f'the bag reached its limit of {self.max_bytes:,} bytes: what '
                              'came after was not recorded')
            return
        self._guarded(lambda: self._writer.add_message(
            channel_id=channel, log_time=log_time_ns, data=data,
            publish_time=log_time_ns if publish_time_ns is None else publish_time_ns))
        self.message_count += 1
        self._counts[channel] += 1
        if self._first_ns is None or log_time_ns < self._first_ns:
            self._first_ns = log_time_ns
        if self._last_ns is None or log_time_ns > self._last_ns:
            self._last_ns = log_time_ns
        if time.monotonic() - self._flushed_at > FLUSH_PERIOD:
            self._guarded(self._stream.flush)
            self._flushed_at = time.monotonic()

    def finish_seconds(self) -> float:
        """Return a generous bound on how long close() would take now (see FINISH_MARGIN)."""
        if self.failure is not None or self._stream.closed:
            return 0.0
        chunks = self._stream.tell() // CHUNK_SIZE + 1
        return FINISH_MARGIN * (0.1 + FINISH_PER_TOPIC * len(self._counts)
                                + FINISH_PER_CHUNK * chunks)

    def close(self) -> None:
        """Finish the bag (the last chunk, the summary, the statistics), unless it has failed."""
        if self.failure is None and not self._stream.closed:
            self._write_rosbag2_metadata()
            self._guarded(self._writer.finish)
            self._guarded(self._stream.close)

    def _write_rosbag2_metadata(self):
        """
        Write rosbag2's metadata record, as its MCAP storage does at a bag's start and end.

        Jazzy's holds the serialised metadata alone; Humble's held ROS_DISTRO beside it, and
        Jazzy's reader still takes that key, so both are written. Each topic's part was written
        as YAML when the topic came; only the counts are added here, so that finishing a bag of
        8,000 topics takes no seconds of YAML.
        """
        metadata = rosbag2_metadata(self.path.name, self._first_ns, self._last_ns,
                                    self.message_count)
        self.add_metadata(ROSBAG2_METADATA, {
            'serialized_metadata': metadata_yaml(metadata, [
                self._topic_yaml[channel] + f'  message_count: {count}\n'
                for channel, count in self._counts.items()]),
            'ROS_DISTRO': metadata['ros_distro']})


def topic_entry(topic: str, type_name: str, profiles: list[dict]) -> dict:
    """Return a topic's entry of rosbag2's metadata (BagMetadata, version 9), count aside."""
    return {'topic_metadata': {
        'name': topic, 'type': type_name, 'serialization_format': 'cdr',
        'offered_qos_profiles': [{key: profile[key] for key in QOS_KEYS} for profile in profiles],
        'type_description_hash': type_hash(type_name)}}


def topic_yaml(entry: dict) -> str:
    """Return a topic's entry as an item of the metadata's topic list, its count to follow."""
    return yaml.dump([entry], Dumper=_YamlDumper, sort_keys=False)


def metadata_yaml(metadata: dict, topic_items: list[str]) -> str:
    """Return the metadata as YAML, with the topic items (topic_yaml, then a count) in its list."""
    text = yaml.dump(metadata, Dumper=_YamlDumper, sort_keys=False)
    if not topic_items:
        return text
    return text.replace(f'{TOPICS_KEY}: []\n', f'{TOPICS_KEY}:\n' + ''.join(topic_items), 1)


def rosbag2_metadata(file_name: str, first_ns: int | None, last_ns: int | None,
                     message_count: int) -> dict:
    """
    Return a bag's metadata as rosbag2 serialises it (BagMetadata, version 9), topics aside.

    Its topic list is left empty, for metadata_yaml to fill; first_ns and last_ns are the first
    and last log times, None before any message (rosbag2 then writes the largest time as the
    start, and no duration).
    """
    start = (2 ** 63 - 1) if first_ns is None else first_ns
    duration = 0 if first_ns is None else last_ns - first_ns
    return {
        'version': ROSBAG2_METADATA_VERSION, 'storage_identifier': 'mcap',
        'duration': {'nanoseconds': duration}, 'starting_time': {'nanoseconds_since_epoch': start},
        'message_count': message_count, TOPICS_KEY: [],
        'compression_format': '', 'compression_mode': '',
        'relative_file_paths': [file_name],
        'files': [{'path': file_name, 'starting_time': {'nanoseconds_since_epoch': start},
                   'duration': {'nanoseconds': duration}, 'message_count': message_count}],
        'custom_data': {'writer': _writer_name()},
        'ros_distro': os.environ.get('ROS_DISTRO') or ROS_DISTRO,
    }


def _writer_name():
    """Name what wrote the bag (the header names the library rosbag2 writes with)."""
    def release(distribution):
        try:
            return version(distribution)
        except PackageNotFoundError:
            return 'unknown'
    return (f'simple_robot_control {release("simple_robot_control")} with mcap (Python) '
            f'{release("mcap")}')
