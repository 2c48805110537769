"""waypoint_lab/Waypoints-v0 and its vector form: Gymnasium's rules, the lab's goal set, seeds."""

import math

import gymnasium as gym
from gymnasium.utils.env_checker import check_env
import numpy as np
import pytest
from waypoint_controller.control_law import PlannedLaw
import waypoint_lab.learning  # noqa: F401  (registers the environments)
from waypoint_lab.learning import MAX_EPISODE_STEPS
from waypoint_lab.learning.task import Courses, TaskSettings, WAYPOINT
from waypoint_lab.learning.vector_env import WaypointsVectorEnv
from waypoint_lab.learning.waypoints_env import WaypointsEnv
from waypoint_lab.lifecycle import RunLifecycle, RunRules
from waypoint_lab.waypoints import Waypoint


def test_gymnasiums_checker_passes():
    env = gym.make('waypoint_lab/Waypoints-v0')
    check_env(env.unwrapped, skip_render_check=True)
    assert env.spec.max_episode_steps == MAX_EPISODE_STEPS
    assert env.observation_space.shape == (69,) and env.action_space.shape == (2,)


def test_seeded_resets_repeat_and_seeds_differ():
    env = WaypointsEnv()
    first, info = env.reset(seed=7)
    steps = [env.step(np.array([0.3, 0.5], dtype=np.float32))[0] for _ in range(20)]
    again, info_again = env.reset(seed=7)
    assert np.array_equal(first, again) and np.array_equal(info['pose'], info_again['pose'])
    assert all(np.array_equal(before, env.step(np.array([0.3, 0.5], dtype=np.float32))[0])
               for before in steps)
    other, _ = env.reset(seed=8)
    assert not np.array_equal(first, other)


def test_reward_and_termination_follow_the_goal_set():
    env = WaypointsEnv(waypoints=2, sensor_noise=False)
    start = (5.0, 5.0, 0.0)
    course = [(5.0, 5.0, 0.0), (5.05, 5.0, 0.0)]
    env.reset(seed=0, options={'start': start, 'waypoints': course})
    _, reward, terminated, truncated, info = env.step(np.zeros(2, dtype=np.float32))
    assert info['reached'] and info['waypoint'] == 1 and not terminated
    assert reward == pytest.approx(WAYPOINT - 0.01)
    _, reward, terminated, _, info = env.step(np.array([0.5, 0.0], dtype=np.float32))
    assert info['reached'] and terminated and not truncated
    assert reward == pytest.approx(WAYPOINT - 0.01 + 0.05)


def test_a_turn_short_of_the_heading_is_no_waypoint():
    task = TaskSettings(waypoints=1)
    courses = Courses(np.array([[[0.0, 0.0, math.radians(10.0)]]]), task)
    courses.start(np.zeros((1, 3)))
    reward, reached, finished = courses.update(np.array([[0.05, 0.0, math.radians(4.0)]]),
                                               np.zeros(1, dtype=bool))
    assert not reached[0] and not finished[0]
    assert reward[0] == pytest.approx(-0.05 + 0.5 * math.radians(4.0) - 0.01)
    _, reached, finished = courses.update(np.array([[0.05, 0.0, math.radians(5.5)]]),
                                          np.ones(1, dtype=bool))
    assert reached[0] and finished[0]


def test_our_control_law_solves_the_environment():
    env = gym.make('waypoint_lab/Waypoints-v0', waypoints=3)
    for seed in range(3):
        _, info = env.reset(seed=seed)
        courses = env.unwrapped.arena.courses
        waypoints = [Waypoint(*waypoint) for waypoint in courses.waypoints[0]]
        run = RunLifecycle(waypoints, PlannedLaw(waypoints), RunRules(control_period_ns=10 ** 8))
        terminated = truncated = False
        total, stamp = 0.0, 0
        while not (terminated or truncated):
            outcome = run.observe(stamp, tuple(info['pose']))
            stamp += 10 ** 8
            _, reward, terminated, truncated, info = env.step(
                np.array(outcome.command, dtype=np.float32))
            total += reward
        assert terminated and not truncated, f'seed {seed}: the course was not finished'
        assert total > 3 * WAYPOINT - 5.0


def test_the_vector_equals_single_environments_stepped_alike():
    vector = WaypointsVectorEnv(num_envs=3, sensor_noise=False, max_episode_steps=30)
    singles = [gym.make('waypoint_lab/Waypoints-v0', sensor_noise=False, max_episode_steps=30)
               for _ in range(3)]
    observations, _ = vector.reset(seed=11)
    for index, env in enumerate(singles):
        single, _ = env.reset(seed=11 + index)
        assert np.array_equal(single, observations[index])
    rng = np.random.default_rng(0)
    ended = [False] * 3
    restarts = 0
    for _ in range(40):
        actions = rng.uniform([-0.5, -1.0], [0.5, 1.0], (3, 2)).astype(np.float32)
        observations, rewards, terminated, truncated, _ = vector.step(actions)
        for index, env in enumerate(singles):
            if ended[index]:
                restarts += 1
                single, _ = env.reset()
                reward, done, cut = 0.0, False, False
            else:
                single, reward, done, cut, _ = env.step(actions[index])
            assert np.array_equal(single, observations[index])
            assert (reward, done, cut) == (rewards[index], terminated[index], truncated[index])
            ended[index] = done or cut
    assert restarts == 3, 'every episode was cut at 30 steps and started again'


def test_with_noise_the_vector_differs_from_single_environments_in_the_laser_noise_alone():
    vector = WaypointsVectorEnv(num_envs=3, max_episode_steps=30)
    singles = [gym.make('waypoint_lab/Waypoints-v0', max_episode_steps=30) for _ in range(3)]
    observations, _ = vector.reset(seed=11)
    firsts = [env.reset(seed=11 + index)[0] for index, env in enumerate(singles)]
    rng = np.random.default_rng(0)
    for _ in range(20):
        actions = rng.uniform([-0.5, -1.0], [0.5, 1.0], (3, 2)).astype(np.float32)
        observations, rewards, terminated, truncated, infos = vector.step(actions)
        for index, env in enumerate(singles):
            single, reward, done, cut, info = env.step(actions[index])
            assert np.array_equal(info['pose'], infos['pose'][index])
            assert np.array_equal(single[-5:], observations[index][-5:])
            assert (reward, done, cut) == (rewards[index], terminated[index], truncated[index])
            # The world's noise is one stream for every robot, a single env's its robot's alone.
            assert np.abs(single[:-5] - observations[index][:-5]).max() < 0.05
    assert not np.array_equal(firsts[1], observations[1])


def test_pictures_are_the_viewers_scene(monkeypatch):
    monkeypatch.setenv('SDL_VIDEODRIVER', 'dummy')
    window = gym.make('waypoint_lab/Waypoints-v0', render_mode='human')
    window.reset(seed=0)
    assert window.render() is None
    window.close()
    env = gym.make('waypoint_lab/Waypoints-v0', render_mode='rgb_array')
    env.reset(seed=0)
    frame = env.render()
    assert frame.shape == (450, 600, 3) and frame.dtype == np.uint8
    walls, free = (frame == 0).all(axis=2).sum(), (frame == 255).all(axis=2).sum()
    # The viewer's colours: walls black, free space white (the lab room is mostly free).
    assert 0 < walls < free, (walls, free)
    assert ((frame[:, :, 0] > 200) & (frame[:, :, 1] < 60)).any(), 'the red laser'
    vector = gym.make_vec('waypoint_lab/Waypoints-v0', num_envs=4,
                          vectorization_mode='vector_entry_point', render_mode='rgb_array')
    vector.reset(seed=0)
    assert vector.render().shape == (450, 600, 3)
    env.close()
    vector.close()
