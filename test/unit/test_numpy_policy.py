"""The shipped policy runs with numpy alone, as the training library ran it."""

import numpy as np
import pytest
from waypoint_lab.learning.numpy_policy import (bundled_policy_file, NumpyPolicy,
                                                PolicyFileError, success_rate)
from waypoint_lab.learning.waypoints_env import WaypointsEnv


def test_the_numpy_runner_gives_the_actions_the_training_library_gave():
    policy = NumpyPolicy()
    assert len(policy.check_observations) == 64
    actions = policy(policy.check_observations)
    np.testing.assert_allclose(actions, policy.check_actions, atol=1e-5)
    # One observation alone gives the same action as in a batch.
    np.testing.assert_allclose(policy(policy.check_observations[3]), actions[3], atol=1e-12)


def test_the_policy_fits_the_tasks_spaces():
    env = WaypointsEnv()
    policy = NumpyPolicy()
    assert policy.layers[0][0].shape[1] == env.observation_space.shape[0]
    assert np.array_equal(policy.low, env.action_space.low)
    assert np.array_equal(policy.high, env.action_space.high)
    action = policy(env.reset(seed=0)[0])
    assert env.action_space.contains(action.astype(np.float32))


@pytest.mark.parametrize('content', [b'', b'not a zip', None])
def test_a_file_that_is_no_policy_is_one_line(tmp_path, content):
    path = tmp_path / 'policy.npz'
    if content is None:
        np.savez(path, weight0=np.zeros((2, 3)), bias0=np.zeros(5))
    else:
        path.write_bytes(content)
    with pytest.raises(PolicyFileError, match=rf'^{path}: not a policy file: ') as refused:
        NumpyPolicy(str(path))
    assert '\n' not in str(refused.value)


def test_success_is_the_share_of_courses_finished():
    def stand_still(observations):
        return np.zeros((len(observations), 2))
    assert success_rate(stand_still, courses=4, max_episode_steps=20) == 0.0
    assert bundled_policy_file().endswith('waypoints_ppo.npz')


def _one_layer_file(path, **extra):
    np.savez(path, weight0=np.eye(2), bias0=np.zeros(2), low=np.full(2, -9.0),
             high=np.full(2, 9.0), check_observations=np.zeros((1, 2)),
             check_actions=np.zeros((1, 2)), **extra)
    return str(path)


def test_observations_are_standardized_as_the_file_says(tmp_path):
    path = _one_layer_file(tmp_path / 'policy.npz', observation_mean=np.array([1.0, -2.0]),
                           observation_scale=np.array([2.0, 0.5]), observation_clip=3.0)
    policy = NumpyPolicy(path)
    np.testing.assert_allclose(policy(np.array([5.0, -1.5])), [2.0, 1.0])
    # Beyond clip standard deviations the input is held at the clip, as in training.
    np.testing.assert_allclose(policy(np.array([101.0, -102.0])), [3.0, -3.0])
    assert NumpyPolicy(_one_layer_file(tmp_path / 'plain.npz'))(np.array([5.0, 1.0]))[0] == 5.0


@pytest.mark.parametrize('mean, scale, clip', [
    (np.zeros(3), np.ones(3), 5.0), (np.zeros(2), np.zeros(2), 5.0),
    (np.array([np.nan, 0.0]), np.ones(2), 5.0), (np.zeros(2), np.ones(2), 0.0)])
def test_a_standardization_that_does_not_fit_is_one_line(tmp_path, mean, scale, clip):
    path = _one_layer_file(tmp_path / 'policy.npz', observation_mean=mean,
                           observation_scale=scale, observation_clip=clip)
    with pytest.raises(PolicyFileError, match=rf'^{path}: not a policy file: its observation'):
        NumpyPolicy(path)
