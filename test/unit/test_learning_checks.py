"""The learning environments check what they are given: one ValueError naming key and value."""

import math

import numpy as np
import pytest
from waypoint_lab.learning.parallel_env import WaypointsParallelEnv
from waypoint_lab.learning.vector_env import WaypointsVectorEnv
from waypoint_lab.learning.waypoints_env import WaypointsEnv

# A course of the default three waypoints, free in the lab's room.
COURSE = [(2.0, 2.0, 0.0), (3.0, 2.0, 1.0), (3.0, 3.0, -1.0)]


@pytest.fixture(scope='module')
def env():
    return WaypointsEnv(sensor_noise=False)


@pytest.fixture(scope='module')
def vector():
    return WaypointsVectorEnv(num_envs=4, sensor_noise=False)


@pytest.fixture(scope='module')
def robots():
    return WaypointsParallelEnv(num_robots=2, sensor_noise=False)


@pytest.mark.parametrize('options, said', [
    ({'waypoints': [(math.nan, 1.0, 0.0)] + COURSE[1:]}, 'robot0: waypoints must be finite'),
    ({'waypoints': COURSE[:2]}, 'robot0: waypoints must have shape (3, 3), got (2, 3)'),
    ({'waypoints': [(2.0, 2.0, 1e300)] + COURSE[1:]}, 'waypoints: a heading is in radians'),
    ({'waypoints': [(2.0, 2.0, 90.0)] + COURSE[1:]}, 'robot0: waypoints: a heading is in radians'),
    ({'waypoints': [(500.0, 2.0, 0.0)] + COURSE[1:]}, 'waypoint 1 (500, 2) is off the map'),
    ({'waypoints': COURSE[:2] + [(0.05, 0.05, 0.0)]},
     "waypoint 3 (0.05, 0.05) is off the map or where the robot's disc touches a wall"),
    ({'waypoints': 'three'}, 'robot0: waypoints must be numbers of shape (3, 3)'),
    ({'start': (1.0, math.inf, 0.0)}, 'robot0: start must be finite'),
    ({'start': (1.0, 2.0)}, 'robot0: start must have shape (3,)'),
    ({'start': (0.05, 0.05, 0.0)}, 'robot0 cannot start at (0.05, 0.05, 0): a footprint'),
    ({'goal': (1.0, 2.0, 0.0)}, "options: unknown key 'goal': the keys are start, waypoints"),
    ([(1.0, 2.0, 0.0)], 'options must be a dict'),
])
def test_bad_reset_options_are_refused_by_name(env, options, said):
    with pytest.raises(ValueError) as error:
        env.reset(seed=0, options=options)
    assert said in str(error.value)
    env.reset(seed=0, options={'waypoints': COURSE})  # and the env goes on


@pytest.mark.parametrize('action, said', [
    ([0.1, math.nan], 'action must be finite'),
    ([0.1, 0.2, 0.3], 'action must have shape (2,), got (3,)'),
    ('fast', 'action must be numbers of shape (2,)'),
])
def test_bad_actions_are_refused_by_name(env, action, said):
    env.reset(seed=0)
    with pytest.raises(ValueError, match=None) as error:
        env.step(action)
    assert said in str(error.value)


def test_the_vector_takes_only_one_action_per_robot(vector):
    vector.reset(seed=0)
    with pytest.raises(ValueError, match=r'actions must have shape \(4, 2\), got \(2, 4\)'):
        vector.step(np.zeros((2, 4)))
    with pytest.raises(ValueError, match='options: unknown key'):
        vector.reset(options={'start': (1.0, 2.0, 0.0), 'seed': 3})
    observations, *_ = vector.step(np.zeros((4, 2)))
    assert observations.shape == (4, 69) and np.isfinite(observations).all()


def test_agents_and_their_options_are_known_ones(robots):
    with pytest.raises(ValueError, match="options\\['start'\\]: no agent 'robot7'"):
        robots.reset(options={'start': {'robot7': (1.0, 2.0, 0.0)}})
    with pytest.raises(ValueError, match="options\\['waypoints'\\] must map agents"):
        robots.reset(options={'waypoints': COURSE})
    robots.reset(seed=0)
    with pytest.raises(ValueError, match="actions: no agent 'robot9'"):
        robots.step({'robot9': (0.1, 0.0)})
    with pytest.raises(ValueError, match=r"actions\['robot0'\] must have shape \(2,\)"):
        robots.step({'robot0': (0.1, 0.0, 0.0)})


@pytest.mark.parametrize('parameters, said', [
    ({'rate_hz': 0}, 'rate_hz must be a finite number above 0, got 0'),
    ({'rate_hz': math.nan}, 'rate_hz must be a finite number above 0'),
    ({'waypoints': 0}, 'waypoints must be a whole number of at least 1, got 0'),
    ({'waypoints': 2.5}, 'waypoints must be a whole number'),
    ({'laser_rays': -3}, 'laser_rays must be a whole number of at least 1'),
    ({'distance_tolerance': -0.1}, 'distance_tolerance must be a finite number above 0'),
    ({'angle_tolerance': 400}, 'angle_tolerance must be a finite number above 0 and at most 180'),
    ({'max_linear_speed': math.inf}, 'max_linear_speed must be a finite number above 0'),
])
def test_bad_parameters_are_refused_by_name(parameters, said):
    with pytest.raises(ValueError) as error:
        WaypointsEnv(**parameters)
    assert said in str(error.value)


def test_bad_counts_of_robots_and_steps_are_refused():
    with pytest.raises(ValueError, match='num_envs must be a whole number of at least 1'):
        WaypointsVectorEnv(num_envs=0)
    with pytest.raises(ValueError, match='max_episode_steps must be a whole number'):
        WaypointsVectorEnv(num_envs=2, max_episode_steps=-1)
    with pytest.raises(ValueError, match='num_robots must be a whole number of at least 1'):
        WaypointsParallelEnv(num_robots=True)
