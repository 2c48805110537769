"""
A run read from a rosbag2 bag in MCAP: record_run's, or any Jazzy `ros2 bag record -s mcap`.

The bag is a .mcap file or a bag folder holding .mcap files. Its records are read in the order
they were written, with mcap's stream reader, so a bag whose recording was killed is read up
to its last complete chunk; messages are decoded by rosbags. The course comes from the
controller's /waypoints (nav_msgs/Path, transient local, so any recording of the run has it)
unless one is given; robot_status messages are dated by the odometry, as course_monitor does.
"""

import math
import os
from pathlib import Path

from mcap.exceptions import McapError
from mcap.records import Channel, Message, Schema
from mcap.stream_reader import StreamReader
from rosbags.typesys import get_types_from_msg, get_typestore, Stores
from simple_robot_control.pose import pose_from_message
from waypoint_controller.run_record import RunRecord, RunRecordError, StatusClock
from waypoint_controller.status import parse_status
from waypoint_controller.waypoints import MAX_WAYPOINTS, Waypoint

COURSE_TOPIC = '/waypoints'
STATUS_TOPIC = '/robot_status'
# rosbags separates a schema's dependencies by this line, as rosbag2 writes them.
SEPARATOR = '=' * 80 + '\n'


def is_bag(path: str | os.PathLike) -> bool:
    """Tell whether path names a bag: an .mcap file, or a folder holding one."""
    path = Path(path)
    return path.suffix == '.mcap' or (path.is_dir() and any(path.glob('*.mcap')))


def load_bag(path: str | os.PathLike, robot_name: str = 'robot0', course: list | None = None,
             distance_tolerance: float = 0.1,
             angle_tolerance: float = math.radians(5.0)) -> RunRecord:
    """Read a run from a bag; RunRecordError says in one line what is wrong with it."""
    path = Path(path)
    files = sorted(path.glob('*.mcap')) if path.is_dir() else [path]
    if not files:
        raise RunRecordError(f'{path}: a bag folder with no .mcap file (only MCAP bags are read)')
    reading = _Reading(f'/{robot_name.strip("/")}/odom')
    for file in files:
        reading.read(file)
    waypoints = course if course is not None else reading.course
    if waypoints is None:
        raise RunRecordError(f'{path}: no {COURSE_TOPIC} in the bag (recorded before the '
                             'controller published it?): give the course file')
    if not reading.poses:
        raise RunRecordError(f'{path}: no odometry on {reading.odometry_topic} in the bag')
    record = RunRecord(path.name, waypoints, distance_tolerance, angle_tolerance,
                       reading.times, reading.poses, reading.statuses)
    record.cut_short_line = reading.cut_short
    record.skipped_lines = reading.skipped
    return record


class _Reading:
    """What has been read of a bag so far."""

    def __init__(self, odometry_topic):
        self.odometry_topic = odometry_topic
        self.course = None
        self.times, self.poses, self.statuses, self.skipped = [], [], [], []
        self.cut_short = None
        self._clock = StatusClock()
        self._typestore = get_typestore(Stores.EMPTY)
        self._channels = {}

    def read(self, file):
        try:
            with open(file, 'rb') as stream:
                for number, record in enumerate(StreamReader(stream, emit_chunks=False).records):
                    self._take(record, number)
        except OSError as error:
            raise RunRecordError(f'{file}: cannot read the bag: {error.strerror}') from None
        except (McapError, EOFError, ValueError, KeyError) as error:
            if not self.poses:
                raise RunRecordError(f'{file}: not a readable MCAP bag ({error})') from None
            self.cut_short = len(self.times)

    def _take(self, record, number):
        if isinstance(record, Schema):
            self._register(record)
        elif isinstance(record, Channel):
            self._channels[record.id] = record.topic
        elif isinstance(record, Message):
            topic = self._channels.get(record.channel_id)
            if topic == self.odometry_topic:
                self._odometry(self._decode(record.data, 'nav_msgs/msg/Odometry'))
            elif topic == STATUS_TOPIC:
                self._status(self._decode(record.data, 'std_msgs/msg/String').data, number)
            elif topic == COURSE_TOPIC:
                self._course(self._decode(record.data, 'nav_msgs/msg/Path'))

    def _register(self, schema):
        """Teach the type store the schema's type and its dependencies, as the bag gives them."""
        if schema.encoding != 'ros2msg':
            return
        text = schema.data.decode()
        name, types = schema.name, {}
        for part in text.split(SEPARATOR):
            if part.startswith('MSG: '):
                header, _, part = part.partition('\n')
                name = header[len('MSG: '):].strip()
                if name.count('/') == 1:
                    name = name.replace('/', '/msg/')
            types.update(get_types_from_msg(part, name))
        self._typestore.register(types)

    def _decode(self, data, type_name):
        return self._typestore.deserialize_cdr(bytes(data), type_name)

    def _odometry(self, message):
        stamp = message.header.stamp
        time = stamp.sec + stamp.nanosec * 1e-9
        pose = pose_from_message(message.pose.pose)
        if all(map(math.isfinite, pose)) and self._clock.odometry(time, pose):
            self.times.append(time)
            self.poses.append(pose)

    def _status(self, text, number):
        if parse_status(text) is None:
            self.skipped.append(number)
        else:
            self.statuses.append((self._clock.date(text), text))

    def _course(self, message):
        if len(message.poses) > MAX_WAYPOINTS:
            raise RunRecordError(f'{COURSE_TOPIC}: a course of {len(message.poses):,} waypoints '
                                 f'(at most {MAX_WAYPOINTS:,})')
        self.course = [Waypoint(*pose_from_message(stamped.pose)) for stamped in message.poses]
