"""
A run of the lab read from a rosbag2 bag in MCAP: the one model plot_run draws, grade_lab judges.

The bag is course_monitor's, record_run's, grade_lab's or any Jazzy `ros2 bag record -s mcap` of
the run, read as bag_reading.py reads any (a killed recording up to its last complete chunk).
The robot's path is one topic of poses: its odometry (what the controller saw) or the
simulator's ground truth (what the grader judges). The course comes from the controller's
/waypoints (transient local, so any recording of the run has it) unless one is given.

Every robot_status message is a report, dated one way: by the stamp of the latest pose of the
path that was sent before it, in the bag's order of sending (publish times: the send time where
the recorder saw it, as grade_lab's and rosbag2's do, else the time it was received; ties in
the order written). A status carries no stamp, so this is the sim time at which the controller
spoke, however late a recorder got it; one sent before any pose is dated by the first.
No ROS here.
"""

from bisect import bisect_right
from collections.abc import Iterable
from dataclasses import dataclass, field
import math
import os
from pathlib import Path

import numpy as np
from simple_robot_control.bag import RUN_METADATA
from simple_robot_control.bag_reading import BagMessages, BagReadError
from simple_robot_control.pose import pose_from_message
from simple_robot_control.validation import Bounds
from waypoint_lab.course import Course
from waypoint_lab.rules import COURSE_TOPIC, STATUS_TOPIC
from waypoint_lab.status import parse_status, Status
from waypoint_lab.waypoints import MAX_WAYPOINTS, POSITION, Waypoint

ODOMETRY, STRING, BOOL, PATH = ('nav_msgs/msg/Odometry', 'std_msgs/msg/String',
                                'std_msgs/msg/Bool', 'nav_msgs/msg/Path')
# What a run may hold: poses on a map (headings within ten turns either way).
POSE = (POSITION, POSITION, Bounds(-20.0 * math.pi, 20.0 * math.pi))


class RunError(ValueError):
    """A bag that holds no run to read; the message is one line naming the file."""


@dataclass(frozen=True)
class Report:
    """A robot_status message: its text, what it says (None if no lab status), and its date."""

    text: str
    status: Status | None
    time: float


@dataclass
class Run:
    """
    A course, the robot's path (stamps in seconds, poses (x, y, theta)), its reports, stalls.

    reports holds every robot_status message in the order sent, lab statuses or not; stalls
    are the steps the simulator said the robot pushed against a wall (ground truth only).
    """

    course: Course
    times: np.ndarray = field(default_factory=lambda: np.zeros(0))
    poses: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    reports: list[Report] = field(default_factory=list)
    stalled_steps: int = 0
    first_stall: float | None = None
    step: float = 0.02
    cut_short: bool = False
    path_topic: str = ''

    @property
    def statuses(self) -> list[Report]:
        """Return the reports that are statuses of the lab, in the order sent."""
        return [report for report in self.reports if report.status is not None]

    @property
    def foreign(self) -> list[Report]:
        """Return the messages on robot_status that are no status of the lab."""
        return [report for report in self.reports if report.status is None]

    @property
    def result(self) -> str | None:
        """Return FINISHED or ABORTED from the last status, or None while the run is unfinished."""
        statuses = self.statuses
        last = statuses[-1].status if statuses else None
        return last.kind if last is not None and last.ends_run else None

    @property
    def duration(self) -> float:
        """Return the sim seconds from the first status to the last."""
        statuses = self.statuses
        return statuses[-1].time - statuses[0].time if len(statuses) > 1 else 0.0

    def reported_poses(self, kind: str) -> list[tuple]:
        """Return the poses (theta in radians) reported by the statuses of one kind."""
        return [report.status.pose for report in self.statuses
                if report.status.kind == kind and report.status.pose is not None]

    def during(self, start: float, end: float) -> np.ndarray:
        """Return the indices of the path's poses stamped within [start, end]."""
        return np.flatnonzero((self.times >= start) & (self.times <= end))

    def pose_at(self, time: float) -> tuple | None:
        """Return the latest pose stamped at or before time (the first one if none is)."""
        if not len(self.times):
            return None
        index = max(int(np.searchsorted(self.times, time, side='right')) - 1, 0)
        return tuple(self.poses[index].tolist())

    def path_length(self, start: float, end: float) -> float:
        """Return the distance the robot drove between two sim times, in metres."""
        points = self.poses[self.during(start, end), :2]
        return float(np.sum(np.hypot(*np.diff(points, axis=0).T))) if len(points) > 1 else 0.0

    @property
    def stalled_seconds(self) -> float:
        return self.stalled_steps * self.step

    @property
    def missing_steps(self) -> int:
        """Count the steps whose pose the bag lacks, between its first and its last."""
        if len(self.times) < 2:
            return 0
        return int(np.sum(np.maximum(np.round(np.diff(self.times) / self.step) - 1, 0)))


def read_run(path: str | os.PathLike, robot_name: str = 'robot0', path_topic: str = 'odom',
             course: Course | None = None) -> Run:
    """
    Read a run from a bag; RunError says in one line why there is none to read.

    path_topic is the robot's topic of poses (odom or ground_truth). Without a course given,
    the bag's /waypoints is the course, named as its recorder named it in the bag's metadata
    (course_monitor and grade_lab do), with the lab's goal set.
    """
    path = Path(path)
    reading = _Reading(robot_name.strip('/'), path_topic)
    try:
        messages = BagMessages(path, set(reading.topics))
        for order, item in enumerate(messages):
            reading.take(item, order)
    except BagReadError as error:
        raise RunError(str(error)) from None
    if messages.cut_short and reading.course is None and not reading.times:
        raise RunError(f'{path}: the bag ends before its first complete chunk (its recording '
                       'was stopped early, or the disk was full): no run in it')
    if course is None:
        if reading.course is None:
            raise RunError(f'{path}: no /{COURSE_TOPIC} in the bag (recorded before the '
                           'controller published it?): give the course file')
        course = Course(messages.metadata.get(RUN_METADATA, {}).get('course', ''),
                        reading.course)
    return reading.run(course, messages.cut_short)


class _Reading:
    """What has been read of a bag so far."""

    def __init__(self, robot_name, path_topic):
        self.path_topic = f'/{robot_name}/{path_topic}'
        self.stall_topic = f'/{robot_name}/stall'
        self.topics = {self.path_topic: (ODOMETRY, self._pose),
                       self.stall_topic: (BOOL, self._stall),
                       f'/{STATUS_TOPIC}': (STRING, self._status),
                       f'/{COURSE_TOPIC}': (PATH, self._course)}
        self.course = None
        self.times, self.poses, self.sent = [], [], []
        self.stalls, self.statuses = [], []

    def take(self, item, order):
        type_name, take = self.topics[item.topic]
        if item.type_name == type_name:
            take(item.message, (item.publish_time_ns, order))

    def _pose(self, message, sent):
        stamp = message.header.stamp
        self.add_pose(stamp.sec + stamp.nanosec * 1e-9, pose_from_message(message.pose.pose),
                      sent)

    def add_pose(self, time, pose, sent):
        """Take a pose of the path stamped time (sim seconds), sent at sent (wall ns, order)."""
        if (not self.times or time > self.times[-1]) and _on_the_map(pose):
            self.times.append(time)
            self.poses.append(pose)
            self.sent.append(sent)

    def _stall(self, message, sent):
        if message.data:
            self.stalls.append(sent)

    def _status(self, message, sent):
        self.statuses.append((sent, message.data))

    def _course(self, message, _):
        if len(message.poses) > MAX_WAYPOINTS:
            raise RunError(f'/{COURSE_TOPIC}: a course of {len(message.poses):,} waypoints (at '
                           f'most {MAX_WAYPOINTS:,})')
        course = [pose_from_message(stamped.pose) for stamped in message.poses]
        if not all(map(_on_the_map, course)):
            raise RunError(f'/{COURSE_TOPIC}: a waypoint off any map (each of x and y must be '
                           f'{POSE[0].text()})')
        self.course = tuple(Waypoint(*pose) for pose in course)

    def _date(self, sent):
        """Return the stamp of the latest pose sent before sent (the first pose if none was)."""
        if not self.times:
            return 0.0
        return self.times[max(bisect_right(self.sent, sent) - 1, 0)]

    def run(self, course, cut_short):
        stalled = {self._date(sent) for sent in self.stalls}
        # In the order sent: a history replayed to a late reader is written after newer ones.
        reports = [Report(text, parse_status(text), self._date(sent))
                   for sent, text in sorted(self.statuses)]
        times = np.asarray(self.times, dtype=float)
        step = float(np.median(np.diff(times))) if len(times) > 1 else Run.step
        return Run(course, times, np.asarray(self.poses, dtype=float).reshape(-1, 3), reports,
                   len(stalled), min(stalled, default=None), step, cut_short, self.path_topic)


def assemble_run(course: Course, path: Iterable[tuple], statuses: Iterable[tuple[int, str]],
                 robot_name: str = 'robot0') -> Run:
    """
    Build a run from records rather than a bag, dated by the same rules (grade_lab's evidence).

    path holds (sim seconds, (x, y, theta), wall ns sent, stalled) per step, in the order sent;
    statuses (wall ns sent, text) per robot_status message.
    """
    reading = _Reading(robot_name.strip('/'), 'ground_truth')
    for time, pose, sent, stalled in path:
        reading.add_pose(time, pose, (sent, 0))
        if stalled:
            reading.stalls.append((sent, 0))
    for sent, text in statuses:
        reading.statuses.append(((sent, 0), text))
    return reading.run(course, False)


def _on_the_map(pose):
    """Whether a pose is one a run can have: finite, on a map of sensible size."""
    return all(bounds.contains(value) for bounds, value in zip(POSE, pose))
