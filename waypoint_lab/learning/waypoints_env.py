"""
waypoint_lab/Waypoints-v0: the lab's assignment as a Gymnasium environment.

A robot of the lab (a 0.2 m disc and its laser) starts somewhere free in a world (the lab's
room by default) and must reach a course of waypoints' goal sets in turn, as the lab's
controller must: within d metres, heading within t. task.py gives the observation (the laser,
then the goal as the robot sees it), the action ((linear m/s, angular rad/s) within the speeds
allowed) and the reward; the episode terminates on reaching the last goal set (FINISHED) and is
truncated by the step limit of its registration.
"""

import math

import gymnasium as gym
from gymnasium import spaces
import numpy as np
from waypoint_lab.learning import checks
from waypoint_lab.learning.arena import Arena
from waypoint_lab.learning.rendering import ArenaPicture
from waypoint_lab.learning.task import FAR, GOAL_FEATURES, TaskSettings
from waypoint_lab.rules import (ANGLE_TOLERANCE, DISTANCE_TOLERANCE, MAX_ANGULAR_SPEED,
                                MAX_LINEAR_SPEED)


def spaces_of(task: TaskSettings) -> tuple[spaces.Box, spaces.Box]:
    """Return (observation space, action space) of one robot of a task."""
    low = np.concatenate([np.zeros(task.laser_rays), [0.0, -1.0, -1.0, -1.0, -1.0]])
    high = np.concatenate([np.ones(task.laser_rays), [FAR, 1.0, 1.0, 1.0, 1.0]])
    assert low.size == task.laser_rays + GOAL_FEATURES
    limits = np.array([task.max_linear_speed, task.max_angular_speed], dtype=np.float32)
    return (spaces.Box(low.astype(np.float32), high.astype(np.float32), dtype=np.float32),
            spaces.Box(-limits, limits, dtype=np.float32))


class WaypointsEnv(gym.Env):
    """
    Reach a course of goal sets with a unicycle robot, seeing a laser (see the module).

    Parameters: waypoints per course, distance_tolerance d (m), angle_tolerance t (degrees),
    laser_rays, max_linear_speed, max_angular_speed, map_name (a map_server YAML or a bundled
    map's name), robot (a robot file or a bundled robot's name), rate_hz (one step is 1/rate_hz
    simulated seconds), random_start, sensor_noise. reset(options={'start': (x, y, theta),
    'waypoints': [(x, y, theta), ...]}) sets the start or the course instead of drawing them
    (theta in radians; checks.py says what is refused). info holds 'pose', 'waypoint' (the one
    to reach next, from 0) and 'reached' (a goal set entered this step).
    """

    metadata = {'render_modes': ['rgb_array', 'human'], 'render_fps': 10}

    def __init__(self, waypoints=3, distance_tolerance=DISTANCE_TOLERANCE,
                 angle_tolerance=math.degrees(ANGLE_TOLERANCE), laser_rays=64,
                 max_linear_speed=MAX_LINEAR_SPEED,
                 max_angular_speed=MAX_ANGULAR_SPEED, map_name='', robot='', rate_hz=10.0,
                 random_start=True, sensor_noise=True, render_mode=None):
        self.task = checks.task(waypoints, distance_tolerance, angle_tolerance, laser_rays,
                                max_linear_speed, max_angular_speed, random_start)
        self.arena = Arena(1, self.task, map_name, robot, rate_hz, sensor_noise)
        self.observation_space, self.action_space = spaces_of(self.task)
        if render_mode is not None and render_mode not in self.metadata['render_modes']:
            raise ValueError(f'render_mode must be one of {self.metadata["render_modes"]}, '
                             f'got {render_mode!r}')
        self.render_mode = render_mode
        self._picture = None
        self._status = ''

    def reset(self, *, seed: int | None = None, options: dict | None = None
              ) -> tuple[np.ndarray, dict]:
        options = checks.options(options)
        super().reset(seed=seed)
        self.arena.simulation.reset(seed=int(self.np_random.integers(2 ** 31)))
        self.arena.restart(0, self.np_random, options)
        self.arena.courses.start(self.arena.poses)
        self._status = 'STARTED'
        return self.arena.observations()[0].copy(), self._info(False)

    def step(self, action: np.ndarray) -> tuple[np.ndarray, float, bool, bool, dict]:
        self.arena.act(checks.numbers('action', action, (2,))[None, :])
        reward, reached, finished = self.arena.step()
        if reached[0]:
            number = int(self.arena.courses.next[0])
            self._status = 'FINISHED' if finished[0] else f'WAYPOINT {number}'
        return (self.arena.observations()[0].copy(), float(reward[0]), bool(finished[0]), False,
                self._info(bool(reached[0])))

    def _info(self, reached):
        return {'pose': self.arena.poses[0], 'waypoint': int(self.arena.courses.next[0]),
                'reached': reached}

    def render(self) -> np.ndarray | None:
        if self.render_mode is None:
            gym.logger.warn('render() without a render_mode: give render_mode="rgb_array" or '
                            '"human" to gym.make')
            return None
        if self._picture is None:
            self._picture = ArenaPicture(self.arena, self.render_mode)
        return self._picture.draw(self.arena.ranges, self._status)

    def close(self) -> None:
        if self._picture is not None:
            self._picture.close()
            self._picture = None
