"""
The lab's task for several robots sharing one world, as PettingZoo's Parallel API defines it.

Every robot (agent robot0, robot1, ...) drives a course of its own in one stdr_lite world where
robots meet: each one's laser sees the others and none passes through another, so they must
give way. An agent leaves `agents` when it finishes its course (terminated) or runs out of
steps (truncated); its robot then stands where it stopped, in the others' way. Each agent sees,
acts and is rewarded as in waypoint_lab/Waypoints-v0. reset(seed) seeds agent i with seed + i
(as WaypointsVectorEnv does); options give some agents their start or course:
{'start': {agent: (x, y, theta)}, 'waypoints': {agent: [(x, y, theta), ...]}}. No ROS here.
"""

import functools
import math

from gymnasium import spaces
import numpy as np
from pettingzoo import ParallelEnv
from waypoint_lab.learning import checks, MAX_EPISODE_STEPS
from waypoint_lab.learning.arena import Arena
from waypoint_lab.learning.rendering import ArenaPicture
from waypoint_lab.learning.waypoints_env import spaces_of
from waypoint_lab.rules import (ANGLE_TOLERANCE, DISTANCE_TOLERANCE, MAX_ANGULAR_SPEED,
                                MAX_LINEAR_SPEED, START)

# Robots are made in a row from the lab's start, this far apart (m), before the first reset.
ROW_SPACING = 0.6


class WaypointsParallelEnv(ParallelEnv):
    """num_robots robots of the lab's task in one world (parameters as WaypointsEnv's)."""

    metadata = {'name': 'waypoint_lab_waypoints_v0', 'render_modes': ['rgb_array', 'human'],
                'render_fps': 10, 'is_parallelizable': True}

    def __init__(self, num_robots=4, waypoints=3, distance_tolerance=DISTANCE_TOLERANCE,
                 angle_tolerance=math.degrees(ANGLE_TOLERANCE), laser_rays=64,
                 max_linear_speed=MAX_LINEAR_SPEED, max_angular_speed=MAX_ANGULAR_SPEED,
                 map_name='', robot='', rate_hz=10.0, sensor_noise=True,
                 max_episode_steps=MAX_EPISODE_STEPS, render_mode=None):
        self.task = checks.task(waypoints, distance_tolerance, angle_tolerance, laser_rays,
                                max_linear_speed, max_angular_speed, random_start=True)
        row = [(START[0] + ROW_SPACING * index, START[1], START[2])
               for index in range(checks.count('num_robots', num_robots))]
        self.arena = Arena(num_robots, self.task, map_name, robot, rate_hz, sensor_noise,
                           bodies_meet=True, starts=row)
        self.possible_agents = list(self.arena.names)
        self.agents = []
        self._index = {agent: index for index, agent in enumerate(self.possible_agents)}
        self._spaces = spaces_of(self.task)
        self.max_episode_steps = checks.count('max_episode_steps', max_episode_steps)
        self.render_mode = render_mode
        self._steps = 0
        self._generators = [np.random.default_rng() for _ in self.possible_agents]
        self._picture = None

    @functools.lru_cache(maxsize=None)
    def observation_space(self, agent: str) -> spaces.Box:
        return self._spaces[0]

    @functools.lru_cache(maxsize=None)
    def action_space(self, agent: str) -> spaces.Box:
        return self._spaces[1]

    def reset(self, seed: int | None = None, options: dict | None = None
              ) -> tuple[dict, dict]:
        if seed is not None:
            self._generators = [np.random.default_rng(seed + index)
                                for index in range(len(self.possible_agents))]
        options = checks.per_agent(options, self.possible_agents)
        self.arena.simulation.reset(seed=int(self._generators[0].integers(2 ** 31)))
        for agent, index in self._index.items():
            mine = {key: options[key][agent] for key in ('start', 'waypoints')
                    if agent in options.get(key, {})}
            self.arena.restart(index, self._generators[index], mine)
        self.arena.courses.start(self.arena.poses)
        self.agents = list(self.possible_agents)
        self._steps = 0
        observations = self.arena.observations()
        reached = np.zeros(len(self.possible_agents), dtype=bool)
        return ({agent: observations[self._index[agent]].copy() for agent in self.agents},
                self._infos(reached))

    def step(self, actions: dict) -> tuple[dict, dict, dict, dict, dict]:
        """Step every live agent; an action for an agent that has left is ignored."""
        if not isinstance(actions, dict):
            raise ValueError(f'actions must map agents to actions, got {actions!r}')
        commands = np.zeros((len(self.possible_agents), 2))
        for agent, action in actions.items():
            if agent not in self._index:
                raise ValueError(f'actions: no agent {agent!r}: the agents are '
                                 f'{", ".join(self.possible_agents)}')
            if agent in self.agents:
                commands[self._index[agent]] = checks.numbers(f'actions[{agent!r}]', action,
                                                              (2,))
        self.arena.act(commands)
        reward, reached, finished = self.arena.step()
        self._steps += 1
        observations = self.arena.observations()
        live = self.agents
        truncated = self._steps >= self.max_episode_steps
        result = (
            {agent: observations[self._index[agent]].copy() for agent in live},
            {agent: float(reward[self._index[agent]]) for agent in live},
            {agent: bool(finished[self._index[agent]]) for agent in live},
            {agent: truncated and not finished[self._index[agent]] for agent in live},
            self._infos(reached))
        self.agents = [agent for agent in live
                       if not (finished[self._index[agent]] or truncated)]
        return result

    def _infos(self, reached):
        poses, goals = self.arena.poses, self.arena.courses.next
        return {agent: {'pose': poses[index].copy(), 'waypoint': int(goals[index]),
                        'reached': bool(reached[index])}
                for agent, index in self._index.items() if agent in self.agents}

    def render(self) -> np.ndarray | None:
        if self.render_mode is None:
            return None
        if self._picture is None:
            self._picture = ArenaPicture(self.arena, self.render_mode)
        return self._picture.draw(self.arena.ranges, f'{len(self.agents)} robots driving')

    def close(self) -> None:
        if self._picture is not None:
            self._picture.close()
            self._picture = None
