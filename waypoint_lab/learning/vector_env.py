"""
Many robots in one stdr_lite world, each its own episode: Gymnasium's vector API, batched.

One step moves every robot (one world step, every laser cast in one call); the robots do not
meet, so sub-environment i behaves exactly as a WaypointsEnv would, seeded with seed + i (as
Gymnasium's vector environments seed theirs). Episodes reset themselves on the step after they
end (Gymnasium's next-step autoreset): that step's action is ignored for them, and they
return their first observation with no reward. With autoreset_mode SAME_STEP (what
Stable-Baselines3 expects) an episode that ends is reset in the same step: it returns the new
episode's first observation, and info['final_obs'] and info['final_info'] hold the last
one's (masked by info['_final_obs']), as Gymnasium defines.
"""

import math

import gymnasium as gym
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space
import numpy as np
from waypoint_lab.learning import checks, MAX_EPISODE_STEPS
from waypoint_lab.learning.arena import Arena
from waypoint_lab.learning.rendering import ArenaPicture
from waypoint_lab.learning.waypoints_env import spaces_of
from waypoint_lab.rules import (ANGLE_TOLERANCE, DISTANCE_TOLERANCE, MAX_ANGULAR_SPEED,
                                MAX_LINEAR_SPEED)


class WaypointsVectorEnv(VectorEnv):
    """
    num_envs robots of waypoint_lab/Waypoints-v0 in one world (parameters as WaypointsEnv's).

    max_episode_steps truncates each episode, as the single environment's registration does.
    """

    metadata = {'render_modes': ['rgb_array', 'human'], 'render_fps': 10,
                'autoreset_mode': AutoresetMode.NEXT_STEP}

    def __init__(self, num_envs=8, waypoints=3, distance_tolerance=DISTANCE_TOLERANCE,
                 angle_tolerance=math.degrees(ANGLE_TOLERANCE),
                 laser_rays=64, max_linear_speed=MAX_LINEAR_SPEED,
                 max_angular_speed=MAX_ANGULAR_SPEED, map_name='', robot='',
                 rate_hz=10.0, random_start=True, sensor_noise=True,
                 max_episode_steps=MAX_EPISODE_STEPS, render_mode=None,
                 autoreset_mode=AutoresetMode.NEXT_STEP):
        self.task = checks.task(waypoints, distance_tolerance, angle_tolerance, laser_rays,
                                max_linear_speed, max_angular_speed, random_start)
        self.num_envs = num_envs = checks.count('num_envs', num_envs)
        self.arena = Arena(num_envs, self.task, map_name, robot, rate_hz, sensor_noise,
                           bodies_meet=False)
        self.single_observation_space, self.single_action_space = spaces_of(self.task)
        self.observation_space = batch_space(self.single_observation_space, num_envs)
        self.action_space = batch_space(self.single_action_space, num_envs)
        self.render_mode = render_mode
        self.autoreset_mode = AutoresetMode(autoreset_mode)
        if self.autoreset_mode not in (AutoresetMode.NEXT_STEP, AutoresetMode.SAME_STEP):
            raise ValueError(f'autoreset_mode must be NEXT_STEP or SAME_STEP, got '
                             f'{self.autoreset_mode}')
        self.metadata = {**self.metadata, 'autoreset_mode': self.autoreset_mode}
        self.max_episode_steps = checks.count('max_episode_steps', max_episode_steps)
        self._steps = np.zeros(num_envs, dtype=np.int64)
        self._ended = np.zeros(num_envs, dtype=bool)
        self._generators = [np.random.default_rng() for _ in range(num_envs)]
        self._picture = None

    def reset(self, *, seed: int | None = None, options: dict | None = None
              ) -> tuple[np.ndarray, dict]:
        options = checks.options(options)
        if seed is not None:
            seeds = (seed if isinstance(seed, (list, tuple))
                     else [seed + index for index in range(self.num_envs)])
            self._generators = [np.random.default_rng(value) for value in seeds]
            self._np_random_seed = seeds[0]
        # Each draws the seed a WaypointsEnv draws for its world, so that their draws agree.
        world_seeds = [int(generator.integers(2 ** 31)) for generator in self._generators]
        self.arena.simulation.reset(seed=world_seeds[0])
        for robot, generator in enumerate(self._generators):
            self.arena.restart(robot, generator, options)
        self.arena.courses.start(self.arena.poses)
        self._steps[:] = 0
        self._ended[:] = False
        return self.arena.observations().copy(), self._infos()

    def step(self, actions: np.ndarray
             ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, dict]:
        actions = checks.numbers('actions', actions, (self.num_envs, 2))
        restarting = self._ended.copy()
        actions[restarting] = 0.0
        self.arena.act(actions)
        # The arena's arrays are its own, overwritten by its next step: these go to the caller.
        reward, reached, finished = (part.copy() for part in self.arena.step())
        for robot in np.flatnonzero(restarting):
            self._generators[robot].integers(2 ** 31)
            self.arena.restart(robot, self._generators[robot])
        self._steps = np.where(restarting, 0, self._steps + 1)
        truncated = ~finished & (self._steps >= self.max_episode_steps)
        reward[restarting] = 0.0
        finished[restarting] = truncated[restarting] = False
        self._ended = finished | truncated
        infos = self._infos(reached & ~restarting)
        observations = self.arena.observations().copy()
        if self.autoreset_mode is AutoresetMode.SAME_STEP and self._ended.any():
            observations, infos = self._reset_ended(observations, infos)
        return observations, reward, finished, truncated, infos

    def _reset_ended(self, observations, infos):
        """Start anew the episodes that ended; return the observations and infos that say so."""
        ended = self._ended
        final_obs = np.full(self.num_envs, None, dtype=object)
        for robot in np.flatnonzero(ended):
            final_obs[robot] = observations[robot].copy()
            self._generators[robot].integers(2 ** 31)
            self.arena.restart(robot, self._generators[robot])
        self._steps[ended] = 0
        self._ended = np.zeros(self.num_envs, dtype=bool)
        fresh = self._infos(infos['reached'] & ~ended)
        fresh.update({'final_obs': final_obs, '_final_obs': ended.copy(),
                      'final_info': infos, '_final_info': ended.copy()})
        return self.arena.observations().copy(), fresh

    def _infos(self, reached=None):
        reached = np.zeros(self.num_envs, dtype=bool) if reached is None else reached
        return {'pose': self.arena.poses.copy(), 'waypoint': self.arena.courses.next.copy(),
                'reached': reached}

    def render(self) -> np.ndarray | None:
        if self.render_mode is None:
            gym.logger.warn('render() without a render_mode')
            return None
        if self._picture is None:
            self._picture = ArenaPicture(self.arena, self.render_mode)
        return self._picture.draw(self.arena.ranges, f'{self.num_envs} robots')

    def close_extras(self, **kwargs) -> None:
        if self._picture is not None:
            self._picture.close()
            self._picture = None
