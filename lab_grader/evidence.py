"""
What a graded run's bag shows: the robot's true path, its stalls, and each robot_status.

The grader's recorder keeps the robot's ground truth (every step, stamped with sim time), its
stall flag and robot_status in one bag, each with the wall time at which it was sent (its
publish time, the middleware's source timestamp). A status message carries no stamp, so it is
dated by the latest true pose the simulator had sent before it was sent: the sim time at which
the controller spoke, however late the recorder got to it. No ROS here.
"""

from dataclasses import dataclass, field
import math
import os

import numpy as np
from simple_robot_control.bag_reading import BagMessages
from simple_robot_control.pose import pose_from_message
from waypoint_controller.run_bag import STATUS_TOPIC
from waypoint_controller.status import parse_status, Status

STRING = 'std_msgs/msg/String'
ODOMETRY = 'nav_msgs/msg/Odometry'
BOOL = 'std_msgs/msg/Bool'


@dataclass(frozen=True)
class Report:
    """A robot_status message: its text, what it says (None if no lab status), when heard."""

    text: str
    status: Status | None
    time: float


@dataclass
class RunEvidence:
    """The true path (stamps in seconds, poses (x, y, theta)), the reports and the stalls."""

    times: np.ndarray = field(default_factory=lambda: np.zeros(0))
    poses: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    reports: list[Report] = field(default_factory=list)
    stalled_steps: int = 0
    first_stall: float | None = None
    step: float = 0.02
    cut_short: bool = False

    def during(self, start: float, end: float) -> np.ndarray:
        """Return the indices of the true poses stamped within [start, end]."""
        return np.flatnonzero((self.times >= start) & (self.times <= end))

    def pose_at(self, time: float) -> tuple | None:
        """Return the latest true pose stamped at or before time (the first one if none is)."""
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
        """Count the steps whose true pose the bag lacks, between its first and its last."""
        if len(self.times) < 2:
            return 0
        return int(np.sum(np.maximum(np.round(np.diff(self.times) / self.step) - 1, 0)))


def read_evidence(path: str | os.PathLike, robot_name: str = 'robot0') -> RunEvidence:
    """Read a graded run's bag; BagReadError if it cannot be read at all."""
    truth_topic, stall_topic = f'/{robot_name}/ground_truth', f'/{robot_name}/stall'
    messages = BagMessages(path, {STATUS_TOPIC, truth_topic, stall_topic})
    times, poses, sent, stalls, statuses = [], [], [], [], []
    for item in messages:
        if item.topic == truth_topic and item.type_name == ODOMETRY:
            stamp = item.message.header.stamp
            time = stamp.sec + stamp.nanosec * 1e-9
            pose = pose_from_message(item.message.pose.pose)
            if (not times or time > times[-1]) and all(map(math.isfinite, pose)):
                times.append(time)
                poses.append(pose)
                sent.append(item.publish_time_ns)
        elif item.topic == stall_topic and item.type_name == BOOL and item.message.data:
            stalls.append(item.publish_time_ns)
        elif item.topic == STATUS_TOPIC and item.type_name == STRING:
            statuses.append((item.message.data, item.publish_time_ns))
    times = np.asarray(times, dtype=float)

    def when(publish_time_ns):
        """Return the stamp of the latest true pose sent before publish_time_ns."""
        if not len(times):
            return 0.0
        return float(times[max(int(np.searchsorted(sent, publish_time_ns, 'right')) - 1, 0)])
    stalled = {when(publish_time) for publish_time in stalls}
    # In the order they were sent: a history replayed to a late reader comes after newer ones.
    statuses.sort(key=lambda status: status[1])
    evidence = RunEvidence(times, np.asarray(poses, dtype=float).reshape(-1, 3),
                           [Report(text, parse_status(text), when(publish_time))
                            for text, publish_time in statuses],
                           len(stalled), min(stalled, default=None),
                           cut_short=messages.cut_short)
    if len(times) > 1:
        evidence.step = float(np.median(np.diff(times)))
    return evidence
