"""
A run read from a rosbag2 bag in MCAP: record_run's, or any Jazzy `ros2 bag record -s mcap`.

The bag is read as bag_reading.py reads any (a killed recording up to its last complete chunk).
The course comes from the controller's /waypoints (nav_msgs/Path, transient local, so any
recording of the run has it) unless one is given; robot_status messages are dated by the
odometry, as course_monitor does.
"""

import math
import os
from pathlib import Path

from simple_robot_control.bag import RUN_METADATA
from simple_robot_control.bag_reading import BagMessages, BagReadError
from simple_robot_control.pose import pose_from_message
from waypoint_controller.run_record import POSE, RunRecord, RunRecordError, StatusClock
from waypoint_controller.status import parse_status
from waypoint_controller.waypoints import MAX_WAYPOINTS, Waypoint

COURSE_TOPIC = '/waypoints'
STATUS_TOPIC = '/robot_status'


def load_bag(path: str | os.PathLike, robot_name: str = 'robot0', course: list | None = None,
             distance_tolerance: float = 0.1, angle_tolerance: float = math.radians(5.0),
             course_name: str = '') -> RunRecord:
    """
    Read a run from a bag; RunRecordError says in one line what is wrong with it.

    The run's course is named course_name, else as its recorder named it in the bag's
    metadata (course_monitor and grade_lab do), else not at all ('').
    """
    path = Path(path)
    reading = _Reading(f'/{robot_name.strip("/")}/odom')
    try:
        messages = BagMessages(path, {reading.odometry_topic, STATUS_TOPIC, COURSE_TOPIC})
        for number, item in enumerate(messages):
            reading.take(item, number)
    except BagReadError as error:
        raise RunRecordError(str(error)) from None
    if messages.cut_short and reading.course is None and not reading.poses:
        raise RunRecordError(f'{path}: the bag ends before its first complete chunk (its '
                             'recording was stopped early, or the disk was full): no run in it')
    waypoints = course if course is not None else reading.course
    if waypoints is None:
        raise RunRecordError(f'{path}: no {COURSE_TOPIC} in the bag (recorded before the '
                             'controller published it?): give the course file')
    if not reading.poses:
        raise RunRecordError(f'{path}: no odometry on {reading.odometry_topic} in the bag')
    name = course_name or messages.metadata.get(RUN_METADATA, {}).get('course', '')
    record = RunRecord(name, waypoints, distance_tolerance, angle_tolerance,
                       reading.times, reading.poses, reading.statuses)
    record.cut_short_line = len(reading.times) if messages.cut_short else None
    record.skipped_lines = reading.skipped
    return record


class _Reading:
    """What has been read of a bag so far."""

    def __init__(self, odometry_topic):
        self.odometry_topic = odometry_topic
        self.course = None
        self.times, self.poses, self.statuses, self.skipped = [], [], [], []
        self._clock = StatusClock()

    def take(self, item, number):
        if item.topic == self.odometry_topic and item.type_name == 'nav_msgs/msg/Odometry':
            self._odometry(item.message)
        elif item.topic == STATUS_TOPIC and item.type_name == 'std_msgs/msg/String':
            self._status(item.message.data, number)
        elif item.topic == COURSE_TOPIC and item.type_name == 'nav_msgs/msg/Path':
            self._course(item.message)

    def _odometry(self, message):
        stamp = message.header.stamp
        time = stamp.sec + stamp.nanosec * 1e-9
        pose = pose_from_message(message.pose.pose)
        if _on_the_map(pose) and self._clock.odometry(time, pose):
            self.times.append(time)
            self.poses.append(pose)
            self.statuses += self._clock.dated_late()

    def _status(self, text, number):
        if parse_status(text) is None:
            self.skipped.append(number)
            return
        date = self._clock.date(text)  # None before any odometry: dated_late() gives it then
        if date is not None:
            self.statuses.append((date, text))

    def _course(self, message):
        if len(message.poses) > MAX_WAYPOINTS:
            raise RunRecordError(f'{COURSE_TOPIC}: a course of {len(message.poses):,} waypoints '
                                 f'(at most {MAX_WAYPOINTS:,})')
        course = [pose_from_message(stamped.pose) for stamped in message.poses]
        if not all(map(_on_the_map, course)):
            raise RunRecordError(f'{COURSE_TOPIC}: a waypoint off any map (each of x and y must '
                                 f'be {POSE[0].text()})')
        self.course = [Waypoint(*pose) for pose in course]


def _on_the_map(pose):
    """Whether a pose is one a run can have: finite, on a map of sensible size."""
    return all(bounds.contains(value) for bounds, value in zip(POSE, pose))
