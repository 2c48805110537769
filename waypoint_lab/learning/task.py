"""
The lab's task, for learning: reach a course of goal sets, seen through a laser. No ROS here.

Every function works on N robots at once (numpy arrays, one row a robot), so one environment
and a vector of them share the rules to the last bit. The goal set is the lab's
(waypoint_lab/course.py). The reward, per step:

    progress   +1 per metre closer to the current waypoint
    turning    +0.5 per radian of heading error removed, once within d of it
    waypoint   +10 on entering its goal set (the lab's WAYPOINT n); the course then goes on
    stall      -0.5 for each step refused by a wall (pushing against it)
    time       -0.01 each step

An episode terminates when the last goal set is reached (the lab's FINISHED).
"""

from dataclasses import dataclass
import math

import numpy as np
from waypoint_lab.course import goal_errors, in_goal_set
from waypoint_lab.rules import (ANGLE_TOLERANCE, DISTANCE_TOLERANCE, MAX_ANGULAR_SPEED,
                                MAX_LINEAR_SPEED)

PROGRESS = 1.0
TURNING = 0.5
WAYPOINT = 10.0
STALL = 0.5
TIME = 0.01
# Goal features of an observation: distance (m, up to FAR), bearing and heading error (cos, sin).
FAR = 50.0
GOAL_FEATURES = 5


@dataclass(frozen=True)
class TaskSettings:
    """
    One task: how many waypoints, the goal set, the laser seen, the speeds allowed.

    Waypoints are drawn at least clearance from any wall and at most course_step from the
    previous one (or the start); the start is drawn too unless random_start is False (the
    lab's START then).
    """

    waypoints: int = 3
    distance_tolerance: float = DISTANCE_TOLERANCE
    angle_tolerance: float = ANGLE_TOLERANCE
    laser_rays: int = 64
    max_linear_speed: float = MAX_LINEAR_SPEED
    max_angular_speed: float = MAX_ANGULAR_SPEED
    clearance: float = 0.4
    course_step: float = 3.0
    random_start: bool = True


def observe(ranges: np.ndarray, max_range: float, poses: np.ndarray,
            goals: np.ndarray) -> np.ndarray:
    """
    Return observations, a row per robot: the laser, then the goal as the robot sees it.

    Ranges are taken as a LaserScan carries them (32-bit) and divided by max_range (no
    return, inf, reads 1; closer than min_range, -inf, reads 0); then the goal's distance (m,
    at most FAR), the cosine and sine of its bearing from the robot's heading, and of its
    heading less the robot's.
    """
    rays = ranges.shape[1]
    observation = np.empty((len(poses), rays + GOAL_FEATURES), dtype=np.float32)
    # Ranges as a LaserScan carries them (float32), so that a scan gives the same bits.
    np.clip(ranges.astype(np.float32) / np.float32(max_range), 0.0, 1.0,
            out=observation[:, :rays])
    dx, dy = goals[:, 0] - poses[:, 0], goals[:, 1] - poses[:, 1]
    bearing = np.arctan2(dy, dx) - poses[:, 2]
    turn = goals[:, 2] - poses[:, 2]
    observation[:, rays] = np.minimum(np.hypot(dx, dy), FAR)
    observation[:, rays + 1], observation[:, rays + 2] = np.cos(bearing), np.sin(bearing)
    observation[:, rays + 3], observation[:, rays + 4] = np.cos(turn), np.sin(turn)
    return observation


class Courses:
    """
    The courses of N robots: their waypoints (N x K x 3) and which each goes for next.

    update() judges one step: it returns the reward, and which robots entered a goal set and
    which finished their course.
    """

    def __init__(self, waypoints: np.ndarray, settings: TaskSettings):
        self.waypoints = np.array(waypoints, dtype=float)
        self.settings = settings
        self.next = np.zeros(len(self.waypoints), dtype=np.int64)
        self._rows = np.arange(len(self.waypoints))
        self._errors = self._goals = None

    @property
    def goals(self) -> np.ndarray:
        """Return each robot's current waypoint (the last one once it has finished)."""
        if self._goals is None:
            index = np.minimum(self.next, self.waypoints.shape[1] - 1)
            self._goals = self.waypoints[self._rows, index]
        return self._goals

    @property
    def finished(self) -> np.ndarray:
        return self.next >= self.waypoints.shape[1]

    def restart(self, robot: int, waypoints: np.ndarray, pose: np.ndarray) -> None:
        """Give one robot a new course, from pose."""
        self.waypoints[robot] = waypoints
        self.next[robot] = 0
        self._goals = None
        if self._errors is not None:
            distance, heading = goal_errors(pose[None, :], self.goals[[robot]])
            self._errors[0][robot], self._errors[1][robot] = distance[0], heading[0]

    def start(self, poses: np.ndarray) -> None:
        """Note where the robots stand before their first step."""
        self._errors = goal_errors(poses, self.goals)

    def update(self, poses: np.ndarray, stalled: np.ndarray) -> tuple:
        """Judge a step to poses; return (reward, reached a waypoint, finished the course)."""
        settings = self.settings
        running = self.next < self.waypoints.shape[1]
        before_distance, before_heading = self._errors
        distance, heading = goal_errors(poses, self.goals)
        near = distance <= settings.distance_tolerance
        reward = (PROGRESS * (before_distance - distance)
                  + TURNING * near * (before_heading - heading)
                  - STALL * stalled - TIME)
        reached = running & in_goal_set(poses, self.goals, settings.distance_tolerance,
                                        settings.angle_tolerance)
        reward = np.where(running, reward + WAYPOINT * reached, 0.0)
        self._errors = distance, heading
        if reached.any():
            self.next = self.next + reached
            self._goals = None
            self._errors = goal_errors(poses, self.goals)
        return reward, reached, reached & self.finished


def sample_course(rng: np.random.Generator, is_free, start: tuple, settings: TaskSettings,
                  attempts: int = 10_000) -> np.ndarray:
    """
    Draw a course of settings.waypoints waypoints (K x 3), each within reach of the last.

    is_free(x, y) says whether a footprint of the task's clearance fits at (x, y). A waypoint
    that cannot be placed after many attempts is placed at the previous one (turning there).
    """
    waypoints = []
    x, y = start[0], start[1]
    for _ in range(settings.waypoints):
        for _ in range(attempts):
            angle, reach = rng.uniform(-math.pi, math.pi), rng.uniform(0.5, settings.course_step)
            candidate = (x + reach * math.cos(angle), y + reach * math.sin(angle))
            if is_free(*candidate):
                x, y = candidate
                break
        waypoints.append((x, y, rng.uniform(-math.pi, math.pi)))
    return np.array(waypoints)
