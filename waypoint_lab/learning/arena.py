"""
Robots driving courses in one stdr_lite world: what every environment of the task shares.

The world is the simulator's own (load_world), stepped as the node steps it; each robot
carries the robot file's first laser, with the task's number of rays over the same span and
range, and nothing else the observation does not use. Robots that do not meet pass through
each other unseen, so each drives its course as if alone: a vector of them is a vector of
independent episodes, computed together. Robots that meet see each other with their lasers and
cannot pass through each other; each starts clear of the others. No ROS here.
"""

from dataclasses import replace
import math

import numpy as np
from stdr_lite.core.bodies import PlacementError
from stdr_lite.core.entities import SimulationSettings
from stdr_lite.core.loading import load_world, robot_entries, robot_file
from stdr_lite.core.robot_description import RobotDescription, RobotEntry
from waypoint_lab.learning import checks
from waypoint_lab.learning.course_distribution import sample_course, sample_position
from waypoint_lab.learning.task import Courses, GOAL_FEATURES, observe, TaskSettings
from waypoint_lab.rules import START


def laser_robot(robot: str, rays: int) -> RobotDescription:
    """Return a robot's description with its first laser alone, cast with rays rays."""
    [entry] = robot_entries([('robot', START, robot_file(robot))])
    description = entry.description
    if not description.lasers:
        raise ValueError(f'{robot or "lab_robot"}: a robot without a laser cannot be observed')
    laser = replace(description.lasers[0], num_rays=rays)
    return replace(description, lasers=(laser,), sonars=())


class Arena:
    """
    count robots in one world, each with a course; rows of every array are robots, in order.

    rate_hz is the control rate: one step of the environment is one step of the simulation.
    """

    def __init__(self, count: int, task: TaskSettings = TaskSettings(), map_name: str = '',
                 robot: str = '', rate_hz: float = 10.0, sensor_noise: bool = True,
                 bodies_meet: bool = True, starts=None):
        self.task = task
        self.bodies_meet = bodies_meet
        count = checks.count('the number of robots', count)
        description = laser_robot(robot, task.laser_rays)
        settings = SimulationSettings(rate_hz=checks.positive('rate_hz', rate_hz),
                                      sensor_noise='auto' if sensor_noise else 'none',
                                      bodies_meet=bodies_meet)
        starts = [START] * count if starts is None else starts
        self.simulation = load_world(map_name, [
            RobotEntry(f'robot{index}', description, tuple(start))
            for index, start in enumerate(starts)], settings)
        self.names = self.simulation.robot_names
        # The laser as the world reads it: without its noise where none is applied.
        self.laser = self.simulation.robot(self.names[0]).sensors[0].spec
        self.courses = Courses(np.zeros((count, task.waypoints, 3)), task)
        self._radius = description.radius
        self._clearance = task.clearance + description.radius
        self.ranges = np.full((count, task.laser_rays), np.inf)
        self._limits = np.array([task.max_linear_speed, task.max_angular_speed])
        self._observations = np.zeros((count, task.laser_rays + GOAL_FEATURES), dtype=np.float32)
        self._poses = None

    @property
    def poses(self) -> np.ndarray:
        """Return the robots' poses, as of the last step or restart."""
        if self._poses is None:
            self._poses = self.simulation.robot_poses()
        return self._poses

    @property
    def bounds(self) -> tuple:
        """Return the map's bounding box in the world: (x_min, y_min, x_max, y_max)."""
        grid = self.simulation.occupancy_map
        width, height = grid.extent
        x, y, yaw = grid.origin
        corners = [(x + u * math.cos(yaw) - v * math.sin(yaw), y + u * math.sin(yaw)
                    + v * math.cos(yaw)) for u in (0.0, width) for v in (0.0, height)]
        xs, ys = zip(*corners)
        return min(xs), min(ys), max(xs), max(ys)

    def is_free(self, x: float, y: float, clearance: float | None = None) -> bool:
        """Whether a waypoint (or a start) at (x, y) keeps clearance (the task's) from walls."""
        clearance = self._clearance if clearance is None else clearance
        extent_x, extent_y = self.simulation.occupancy_map.extent
        map_x, map_y = self.simulation.bodies.checker.to_map_frame(x, y)
        return (0.0 <= map_x < extent_x and 0.0 <= map_y < extent_y
                and not self.simulation.bodies.checker.touches(x, y, clearance))

    def _clear_of_others(self, robot: int):
        """Return is_free for robot's start: clear of walls and, if bodies meet, other robots."""
        others = np.delete(self.poses[:, :2], robot, axis=0) if self.bodies_meet else None

        def free(x, y, clearance):
            return self.is_free(x, y, clearance) and (
                others is None or not len(others)
                or np.hypot(others[:, 0] - x, others[:, 1] - y).min() > 2 * self._clearance)
        return free

    def restart(self, robot: int, rng: np.random.Generator,
                options: dict | None = None) -> None:
        """
        Put a robot at a new start with a new course: from rng, unless options give them.

        options ({'start': pose, 'waypoints': course}, checked by the environment for their
        keys) are checked whole: a start the robot cannot take (a wall, another robot, off the
        map) and a course not of the task's length, not finite, or with a waypoint where the
        robot does not fit raise ValueError.
        """
        name = self.names[robot]
        options = options or {}
        start = options.get('start')
        if start is None:
            start = START
            if self.task.random_start:
                x, y = sample_position(rng, self._clear_of_others(robot), self.bounds,
                                       self._clearance, START[:2])
                start = (x, y, rng.uniform(-math.pi, math.pi))
        else:
            start = checks.poses(f'{name}: start', start)
        start = np.asarray(start, dtype=float)
        waypoints = options.get('waypoints')
        if waypoints is None:
            waypoints = sample_course(rng, self.is_free, start, self.task, self.bounds,
                                      self._radius)
        else:
            waypoints = checks.poses(f'{name}: waypoints', waypoints, rows=self.task.waypoints)
            for number, (x, y, _) in enumerate(waypoints, 1):
                if not self.is_free(x, y, self._radius):
                    raise ValueError(f'{name}: waypoint {number} ({x:g}, {y:g}) is off the map '
                                     "or where the robot's disc touches a wall")
        try:
            self.simulation.teleport(name, tuple(start))
        except PlacementError as error:
            place = ', '.join(f'{value:g}' for value in start)
            raise ValueError(f'{name} cannot start at ({place}): {error}') from None
        self.simulation.command(name, 0.0, 0.0)
        self._poses = None
        self.courses.restart(robot, waypoints, start)

    def act(self, actions: np.ndarray) -> None:
        """
        Hold each robot's (linear m/s, angular rad/s), clipped to the task's speeds.

        actions (a row a robot) were checked by the environment that took them.
        """
        actions = np.minimum(np.maximum(actions, -self._limits), self._limits)
        self.simulation.command_robots(actions[:, 0], actions[:, 1])

    def step(self) -> tuple:
        """
        Step the world once; return (reward, reached a waypoint, finished) per robot.

        The arrays are the courses' own, overwritten by the next step: keep a copy.
        """
        self.simulation.step()
        self._poses = self.simulation.robot_poses()
        return self.courses.update(self._poses, self.simulation.robots_stalled())

    def observations(self) -> np.ndarray:
        """
        Return every robot's observation (see task.observe).

        The array is the arena's own, overwritten by the next call: keep a copy.
        """
        self.ranges = self.simulation.read_lasers(self.names, self.laser)
        return observe(self.ranges, self.laser.max_range, self.poses, self.courses.goals,
                       self._observations)
