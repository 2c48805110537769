"""
The lab's task, for learning: reach a course of goal sets, seen through a laser. No ROS here.

Every function works on N robots at once (numpy arrays, one row a robot), so one environment
and a vector of them share the rules to the last bit; a step's judgement and the observation
are each one compiled pass (numba) over the robots, into arrays allocated once. The goal set is
the lab's (waypoint_lab/course.py). The reward, per step:

    progress   +1 per metre closer to the current waypoint
    turning    +0.5 per radian of heading error removed, once within d of it
    waypoint   +10 on entering its goal set (the lab's WAYPOINT n); the course then goes on
    stall      -0.5 for each step refused by a wall (pushing against it)
    time       -0.01 each step

An episode terminates when the last goal set is reached (the lab's FINISHED).
"""

from dataclasses import dataclass
import math

from numba import njit
import numpy as np
from simple_robot_control.compiled_rules import compiled
from waypoint_lab.course import goal_error, goal_errors
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

    Courses are drawn as course_distribution.py says: legs from none (a turn in place) to
    across the map, revisits, waypoints clearance from the walls or, some, near_wall; the
    start is drawn too unless random_start is False (the lab's START then).
    """

    waypoints: int = 3
    distance_tolerance: float = DISTANCE_TOLERANCE
    angle_tolerance: float = ANGLE_TOLERANCE
    laser_rays: int = 64
    max_linear_speed: float = MAX_LINEAR_SPEED
    max_angular_speed: float = MAX_ANGULAR_SPEED
    clearance: float = 0.4
    near_wall: float = 0.05
    course_step: float = 3.0
    random_start: bool = True


def observe(ranges: np.ndarray, max_range: float, poses: np.ndarray, goals: np.ndarray,
            out: np.ndarray | None = None) -> np.ndarray:
    """
    Return observations, a row per robot: the laser, then the goal as the robot sees it.

    Ranges are taken as a LaserScan carries them (32-bit) and divided by max_range (no
    return, inf, reads 1; closer than min_range, -inf, reads 0); then the goal's distance (m,
    at most FAR), the cosine and sine of its bearing from the robot's heading, and of its
    heading less the robot's. out, if given, is filled (float32, a row per robot) and returned.
    """
    if out is None:
        out = np.empty((len(poses), ranges.shape[1] + GOAL_FEATURES), dtype=np.float32)
    _observe(ranges, float(max_range), poses, goals, out)
    return out


class Courses:
    """
    The courses of N robots: their waypoints (N x K x 3) and which each goes for next.

    update() judges one step: it returns the reward, and which robots entered a goal set and
    which finished their course, in arrays of its own that the next update overwrites.
    """

    def __init__(self, waypoints: np.ndarray, settings: TaskSettings):
        self.waypoints = np.array(waypoints, dtype=float)
        self.settings = settings
        count = len(self.waypoints)
        self.next = np.zeros(count, dtype=np.int64)
        self._rows = np.arange(count)
        # Each robot's distance and heading error as of the last step (NaN before start()).
        self._errors = np.full((count, 2), np.nan)
        self._reward = np.zeros(count)
        self._reached = np.zeros(count, dtype=bool)
        self._finished = np.zeros(count, dtype=bool)
        self._goals = None

    @property
    def goals(self) -> np.ndarray:
        """Return each robot's current waypoint (the last one once it has finished)."""
        if self._goals is None:
            self._goals = self.waypoints[self._rows,
                                         np.minimum(self.next, self.waypoints.shape[1] - 1)]
        return self._goals

    @property
    def finished(self) -> np.ndarray:
        return self.next >= self.waypoints.shape[1]

    def restart(self, robot: int, waypoints: np.ndarray, pose: np.ndarray) -> None:
        """Give one robot a new course, from pose."""
        self.waypoints[robot] = waypoints
        self.next[robot] = 0
        self._goals = None
        self._errors[robot] = goal_error(*pose[:3], *self.waypoints[robot, 0])

    def start(self, poses: np.ndarray) -> None:
        """Note where the robots stand before their first step."""
        distance, heading = goal_errors(poses, self.goals)
        self._errors[:, 0], self._errors[:, 1] = distance, heading

    def update(self, poses: np.ndarray, stalled: np.ndarray) -> tuple:
        """Judge a step to poses; return (reward, reached a waypoint, finished the course)."""
        if _judge(np.ascontiguousarray(poses, dtype=float), np.asarray(stalled, dtype=bool),
                  self.waypoints, self.next, self._errors, self.settings.distance_tolerance,
                  self.settings.angle_tolerance, self._reward, self._reached, self._finished):
            self._goals = None
        return self._reward, self._reached, self._finished


def compile_task() -> None:
    """Compile the task's passes into numba's cache (make install), not in a learner's run."""
    courses = Courses(np.zeros((1, 1, 3)), TaskSettings(waypoints=1))
    courses.start(np.zeros((1, 3)))
    courses.update(np.zeros((1, 3)), np.zeros(1, dtype=bool))
    observe(np.zeros((1, 4)), 1.0, np.zeros((1, 3)), courses.goals)


_goal_error = compiled(goal_error)


@njit(cache=True)
def _observe(ranges, max_range, poses, goals, out):
    rays = ranges.shape[1]
    scale = np.float32(max_range)
    for robot in range(poses.shape[0]):
        for ray in range(rays):
            # As a LaserScan carries it (float32), so that a scan gives the same bits.
            value = np.float32(ranges[robot, ray]) / scale
            out[robot, ray] = value if value != value else min(max(value, 0.0), 1.0)
        x, y, theta = poses[robot, 0], poses[robot, 1], poses[robot, 2]
        dx, dy = goals[robot, 0] - x, goals[robot, 1] - y
        bearing = math.atan2(dy, dx) - theta
        turn = goals[robot, 2] - theta
        out[robot, rays] = min(math.hypot(dx, dy), FAR)
        out[robot, rays + 1], out[robot, rays + 2] = math.cos(bearing), math.sin(bearing)
        out[robot, rays + 3], out[robot, rays + 4] = math.cos(turn), math.sin(turn)


@njit(cache=True)
def _judge(poses, stalled, waypoints, next_waypoint, errors, distance_tolerance,
           angle_tolerance, reward, reached, finished):
    """
    Judge every robot's step to poses (see the module): its reward, its goal set entered.

    A robot that enters its goal set goes on to its next waypoint, whose errors are noted;
    a robot past its last waypoint earns nothing more. Returns how many went on.
    """
    last = waypoints.shape[1] - 1
    went_on = 0
    for robot in range(poses.shape[0]):
        x, y, theta = poses[robot, 0], poses[robot, 1], poses[robot, 2]
        running = next_waypoint[robot] <= last
        goal = waypoints[robot, min(next_waypoint[robot], last)]
        distance, heading = _goal_error(x, y, theta, goal[0], goal[1], goal[2])
        near = 1.0 if distance <= distance_tolerance else 0.0
        gain = (PROGRESS * (errors[robot, 0] - distance)
                + TURNING * near * (errors[robot, 1] - heading)
                - STALL * stalled[robot] - TIME)
        hit = running and distance <= distance_tolerance and heading <= angle_tolerance
        reward[robot] = gain + WAYPOINT * hit if running else 0.0
        reached[robot] = hit
        errors[robot, 0], errors[robot, 1] = distance, heading
        if hit:
            went_on += 1
            next_waypoint[robot] += 1
            goal = waypoints[robot, min(next_waypoint[robot], last)]
            errors[robot, 0], errors[robot, 1] = _goal_error(x, y, theta, goal[0], goal[1],
                                                             goal[2])
        finished[robot] = hit and next_waypoint[robot] > last
    return went_on
