"""The task through the libraries learners use: PettingZoo's Parallel API and SB3's VecEnv."""

import math

import numpy as np
from pettingzoo.test import parallel_api_test
import pytest
from waypoint_lab.learning.parallel_env import WaypointsParallelEnv
from waypoint_lab.learning.sb3_vec_env import SB3Steps
from waypoint_lab.learning.vector_env import WaypointsVectorEnv

FAR_COURSE = [(8.0, 6.0, 0.0)]


class OptionsTaken(WaypointsParallelEnv):
    """The env, but for the one option parallel_api_test sends to see that reset takes some."""

    def reset(self, seed=None, options=None):
        if options == {'options': 1}:
            options = None
        return super().reset(seed, options)


def test_pettingzoos_parallel_api_test_passes():
    # Its reset(options={'options': 1}) is refused as any unknown key is (test_learning_checks).
    with pytest.raises(ValueError, match="unknown key 'options'"):
        WaypointsParallelEnv(num_robots=2).reset(options={'options': 1})
    parallel_api_test(OptionsTaken(num_robots=4, max_episode_steps=40), num_cycles=100)


def test_agents_are_seeded_one_by_one_and_repeat():
    env = WaypointsParallelEnv(num_robots=3)
    first, _ = env.reset(seed=5)
    poses = {agent: info['pose'] for agent, info in env.reset(seed=5)[1].items()}
    again, _ = env.reset(seed=5)
    assert all(np.array_equal(first[agent], again[agent]) for agent in env.possible_agents)
    assert len({tuple(np.round(pose, 3)) for pose in poses.values()}) == 3
    other, _ = env.reset(seed=6)
    assert not np.array_equal(first['robot0'], other['robot0'])


def test_robots_see_and_stop_each_other():
    env = WaypointsParallelEnv(num_robots=2, waypoints=1, sensor_noise=False)
    options = {'start': {'robot0': (3.0, 3.0, 0.0), 'robot1': (4.0, 3.0, math.pi)},
               'waypoints': {'robot0': FAR_COURSE, 'robot1': FAR_COURSE}}
    env.reset(seed=1, options=options)
    laser = env.arena.ranges[0]
    middle = laser.size // 2
    # Straight ahead of robot0 (1 m apart, 0.2 m radius each), robot1 rather than the wall.
    assert 0.5 < laser[middle] < 0.85
    for _ in range(40):
        env.step({'robot0': np.array([0.5, 0.0]), 'robot1': np.array([0.0, 0.0])})
    x0, x1 = env.arena.poses[0][0], env.arena.poses[1][0]
    assert x0 < 3.65 and x1 == pytest.approx(4.0, abs=1e-6)
    assert x1 - x0 >= 0.4 - 1e-6


def test_an_agent_that_finishes_leaves_and_stands_still():
    env = WaypointsParallelEnv(num_robots=2, waypoints=1, sensor_noise=False)
    options = {'start': {'robot0': (3.0, 3.0, 0.0), 'robot1': (6.0, 3.0, 0.0)},
               'waypoints': {'robot0': [(3.0, 3.0, 0.0)], 'robot1': FAR_COURSE}}
    env.reset(seed=2, options=options)
    _, rewards, terminated, truncated, _ = env.step({agent: np.array([0.0, 0.0])
                                                    for agent in env.agents})
    assert terminated == {'robot0': True, 'robot1': False} and not any(truncated.values())
    assert env.agents == ['robot1']
    env.step({'robot0': np.array([0.5, 0.0]), 'robot1': np.array([0.0, 0.0])})
    assert env.arena.poses[0][0] == pytest.approx(3.0, abs=1e-9)


def run(env_steps, steps, seed=3):
    """Step an SB3Steps with fixed actions; return each step's (obs, rewards, dones, infos)."""
    env_steps.seed(seed)
    first = env_steps.reset()
    actions = np.tile([0.3, 0.4], (env_steps.num_envs, 1))
    results = []
    for _ in range(steps):
        env_steps.step_async(actions)
        results.append(env_steps.step_wait())
    return first, results


def test_sb3s_contract_shapes_dones_and_terminal_observations():
    env = SB3Steps(4, max_episode_steps=6)
    first, results = run(env, 13)
    assert first.shape == (4, env.observation_space.shape[0])
    assert len(env.reset_infos) == 4 and 'pose' in env.reset_infos[0]
    for step, (observations, rewards, dones, infos) in enumerate(results, 1):
        assert observations.shape == first.shape and rewards.dtype == np.float32
        assert dones.dtype == bool and len(infos) == 4
        # The step limit ends every episode at steps 6 and 12; the next starts at once.
        assert dones.all() == (step % 6 == 0) and (dones.any() == dones.all())
        for index, info in enumerate(infos):
            assert ('terminal_observation' in info) == dones[index]
            if dones[index]:
                assert info['TimeLimit.truncated'] is True
                assert not np.array_equal(info['terminal_observation'], observations[index])


def test_sb3s_terminal_observations_are_the_episodes_last_and_resets_its_first():
    # The same robots stepped alike in next-step autoreset show what SB3's view must hold.
    sb3_first, sb3 = run(SB3Steps(2, max_episode_steps=4), 5)
    plain = WaypointsVectorEnv(2, max_episode_steps=4)
    observations, _ = plain.reset(seed=3)
    assert np.array_equal(observations, sb3_first)
    actions = np.tile([0.3, 0.4], (2, 1))
    history = [plain.step(actions)[0] for _ in range(5)]
    assert np.array_equal(sb3[3][3][0]['terminal_observation'], history[3][0])
    assert np.array_equal(sb3[3][0], history[4])  # next-step autoreset: its first, a step on
    assert np.array_equal(sb3[2][0], history[2])


def test_sb3s_seeds_are_one_per_sub_environment():
    env = SB3Steps(3)
    assert env.seed(10) == [10, 11, 12]
    first = env.reset()
    env.seed(10)
    assert np.array_equal(env.reset(), first)
    assert env.get_attr('num_envs') == [3, 3, 3] and env.env_is_wrapped(object) == [False] * 3
