"""
The lab's course and its goal set: the rules every controller is judged by. No ROS here.

A course is a list of waypoints (x, y, theta) reached in turn from a start pose. The goal set
of a waypoint is every pose within d metres of it whose heading is within t of its heading
(wrapped): the lab's d = 0.1 m and t = 5 degrees (rules.py) unless a course says
otherwise. A controller
reports on the topic robot_status (status.py) and publishes its course on waypoints; a bag
holds both under their absolute names.
"""

from dataclasses import dataclass, field
import math
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike
from simple_robot_control.pose import wrap_angle, wrap_number
from waypoint_lab.rules import (ANGLE_TOLERANCE, DISTANCE_TOLERANCE, START, TIME_LIMIT,
                                WAYPOINTS_TASK)
from waypoint_lab.waypoints import Waypoint


@dataclass(frozen=True)
class Course:
    """
    One course: its waypoints, its world, and how it is graded (SI units, radians).

    map_file and robot_file are empty for the bundled lab_room and lab robot; max_time and
    max_path_length, when set, are graded limits; waypoint_file and settings_file say where the
    course was read from, if from files. task names what the course asks (the lab's waypoints,
    or a coursework's), thresholds that task's limits as (name, value) pairs; map_topic where a
    mapping submission publishes its map ('' for the task's own).
    """

    name: str
    waypoints: tuple[Waypoint, ...]
    start: tuple[float, float, float] = START
    map_file: str = ''
    robot_file: str = ''
    time_limit: float = TIME_LIMIT
    points: float = 1.0
    distance_tolerance: float = DISTANCE_TOLERANCE
    angle_tolerance: float = ANGLE_TOLERANCE
    max_time: float | None = None
    max_path_length: float | None = None
    waypoint_file: Path | None = None
    settings_file: Path | None = field(default=None, compare=False)
    task: str = WAYPOINTS_TASK
    thresholds: tuple[tuple[str, float], ...] = ()
    map_topic: str = ''


def goal_error(x: float, y: float, theta: float, goal_x: float, goal_y: float,
               goal_theta: float) -> tuple[float, float]:
    """
    Return one pose's distance from its goal, and its absolute wrapped heading error.

    Plain Python that numba compiles as it is (the learning task's compiled pass): the rule of
    goal_errors for one pose, to the same bit (tested).
    """
    dx, dy = goal_x - x, goal_y - y
    return math.sqrt(dx * dx + dy * dy), abs(wrap_number(goal_theta - theta))


def goal_errors(poses: ArrayLike, goals: ArrayLike) -> tuple:
    """
    Return the distance of each pose (x, y, theta) from its goal, and its heading error.

    The heading error is absolute and wrapped; poses and goals broadcast (one pose against
    many goals, a row of robots against a row of goals).
    """
    poses, goals = np.asarray(poses, dtype=float), np.asarray(goals, dtype=float)
    # A square root of a sum of squares (not hypot, whose last bit differs between Python,
    # numpy and numba): each step correctly rounded, the same bits in every form of the rule.
    dx, dy = goals[..., 0] - poses[..., 0], goals[..., 1] - poses[..., 1]
    distance = np.sqrt(dx * dx + dy * dy)
    return distance, np.abs(wrap_angle(goals[..., 2] - poses[..., 2]))


def in_goal_set(poses: ArrayLike, goals: ArrayLike,
                distance_tolerance: float = DISTANCE_TOLERANCE,
                angle_tolerance: float = ANGLE_TOLERANCE) -> np.ndarray | np.bool_:
    """Whether each pose lies in its goal's set: within d of it, heading within t of its."""
    distance, heading = goal_errors(poses, goals)
    return (distance <= distance_tolerance) & (heading <= angle_tolerance)
