"""
The messages of chosen topics read back from a rosbag2 bag in MCAP, in the order they were written.

The bag is a .mcap file or a bag folder holding .mcap files: record_run's, course_monitor's,
grade_lab's, or any Jazzy `ros2 bag record -s mcap`. Records are read with mcap's stream reader,
so a bag whose recording was killed is read up to its last complete chunk; messages are decoded
by rosbags with the definitions the bag itself carries. No ROS client here.
"""

from dataclasses import dataclass
import os
from pathlib import Path
import struct
from typing import Iterator

from mcap.exceptions import McapError
from mcap.records import Channel, Message, Metadata, Schema
from mcap.stream_reader import StreamReader
from rosbags.typesys import get_types_from_msg, get_typestore, Stores

# rosbags separates a schema's dependencies by this line, as rosbag2 writes them.
SEPARATOR = '=' * 80 + '\n'


class BagReadError(ValueError):
    """A bag that cannot be read at all; the message is one line naming the file."""


def is_bag(path: str | os.PathLike) -> bool:
    """Tell whether path names a bag: an .mcap file, or a folder holding one."""
    path = Path(path)
    return path.suffix == '.mcap' or (path.is_dir() and any(path.glob('*.mcap')))


def bag_files(path: str | os.PathLike) -> list[Path]:
    """Return the .mcap files of a bag (a file, or a folder of them in name order)."""
    path = Path(path)
    files = sorted(path.glob('*.mcap')) if path.is_dir() else [path]
    if not files:
        raise BagReadError(f'{path}: a bag folder with no .mcap file (only MCAP bags are read)')
    return files


@dataclass(frozen=True)
class BagMessage:
    """One message of a bag: its topic and type, when it was received and sent, its fields."""

    topic: str
    type_name: str
    log_time_ns: int
    publish_time_ns: int
    message: object


class BagMessages:
    """
    Iterate over the messages of the topics wanted in a bag, in the order they were written.

    Messages of other topics are skipped undecoded. A bag that ends short of its summary (a
    killed recording) ends the iteration at its last complete chunk and sets cut_short; one
    whose very first records cannot be read raises BagReadError.
    """

    def __init__(self, path: str | os.PathLike, topics: set[str] | frozenset[str]):
        self.files = bag_files(path)
        self._topics = frozenset(topics)
        self.cut_short = False
        # The bag's metadata records by name, as read so far.
        self.metadata = {}
        self._typestore = get_typestore(Stores.EMPTY)
        self._channels = {}
        self._schemas = {}

    def __iter__(self) -> Iterator[BagMessage]:
        for file in self.files:
            yield from self._read(file)

    def _read(self, file):
        read_any = False
        try:
            with open(file, 'rb') as stream:
                for record in StreamReader(stream, emit_chunks=False).records:
                    read_any = True
                    message = self._take(record)
                    if message is not None:
                        yield message
        except OSError as error:
            raise BagReadError(f'{file}: cannot read the bag: {error.strerror}') from None
        except (McapError, EOFError, ValueError, KeyError, struct.error) as error:
            if not read_any:
                raise BagReadError(f'{file}: not a readable MCAP bag ({error})') from None
            self.cut_short = True

    def _take(self, record):
        if isinstance(record, Metadata):
            self.metadata[record.name] = dict(record.metadata)
        elif isinstance(record, Schema):
            self._schemas[record.id] = self._register(record)
        elif isinstance(record, Channel) and record.topic in self._topics:
            self._channels[record.id] = (record.topic, self._schemas.get(record.schema_id))
        elif isinstance(record, Message) and record.channel_id in self._channels:
            topic, type_name = self._channels[record.channel_id]
            if type_name is not None:
                return BagMessage(topic, type_name, record.log_time, record.publish_time,
                                  self._typestore.deserialize_cdr(bytes(record.data), type_name))
        return None

    def _register(self, schema):
        """Teach the type store a schema's type and its dependencies; return the type's name."""
        if schema.encoding != 'ros2msg':
            return None
        name, types = schema.name, {}
        for part in schema.data.decode().split(SEPARATOR):
            if part.startswith('MSG: '):
                header, _, part = part.partition('\n')
                name = header[len('MSG: '):].strip()
                if name.count('/') == 1:
                    name = name.replace('/', '/msg/')
            types.update(get_types_from_msg(part, name))
        self._typestore.register(types)
        return schema.name
