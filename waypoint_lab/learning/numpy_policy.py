"""
A trained policy run with numpy alone: no training library is needed to drive with it.

The file (.npz) holds a tanh MLP's layers (weight0, bias0, ...: the hidden layers, then the
layer giving the action's mean), the action's bounds, and observations with the actions the
training library gave for them (check_observations, check_actions), so that anyone can check
this runner against it. It may also hold how observations are standardized before the first
layer (observation_mean, observation_scale, observation_clip: the observation less the mean,
divided by the scale, within +-clip), as running statistics of training left them.
scripts/train_policy.py writes such files; the bundled one is
waypoint_lab/learning/policies/waypoints_ppo.npz.
"""

from collections.abc import Callable
from importlib import resources
import zipfile

import numpy as np
from waypoint_lab.learning.vector_env import WaypointsVectorEnv

BUNDLED = 'waypoints_ppo.npz'
LAYOUT = 'weight0, bias0, ..., low, high, check_observations, check_actions'


def bundled_policy_file() -> str:
    """Return the path of the policy trained by `make train` and shipped with the package."""
    return str(resources.files('waypoint_lab.learning') / 'policies' / BUNDLED)


class PolicyFileError(ValueError):
    """A policy file that cannot be run; the message is one line naming the file."""


class NumpyPolicy:
    """observation(s) -> action(s): the deterministic action (the mean), within the bounds."""

    def __init__(self, path: str | None = None):
        path = path or bundled_policy_file()
        try:
            with np.load(path, allow_pickle=False) as data:
                count = sum(1 for key in data.files if key.startswith('weight'))
                self.layers = [(data[f'weight{index}'].astype(np.float64),
                                data[f'bias{index}'].astype(np.float64))
                               for index in range(count)]
                self.low, self.high = data['low'], data['high']
                self.check_observations = data['check_observations']
                self.check_actions = data['check_actions']
                self.standardization = (
                    (data['observation_mean'].astype(np.float64),
                     data['observation_scale'].astype(np.float64),
                     float(data['observation_clip']))
                    if 'observation_mean' in data.files else None)
        except (OSError, EOFError, ValueError, KeyError, zipfile.BadZipFile) as error:
            reason = (error.strerror if isinstance(error, OSError) and error.strerror
                      else f'no numpy .npz of {LAYOUT}')
            raise PolicyFileError(f'{path}: not a policy file: {reason}') from None
        if not self.layers or any(weight.ndim != 2 or bias.shape != weight.shape[:1]
                                  for weight, bias in self.layers):
            raise PolicyFileError(f'{path}: not a policy file: its layers do not fit')
        if self.standardization is not None:
            mean, scale, clip = self.standardization
            inputs = self.layers[0][0].shape[1:]
            if mean.shape != inputs or scale.shape != inputs or not (
                    np.all(scale > 0.0) and np.all(np.isfinite(mean)) and clip > 0.0):
                raise PolicyFileError(f'{path}: not a policy file: its observation '
                                      'standardization does not fit its first layer')

    def __call__(self, observation: np.ndarray) -> np.ndarray:
        values = np.asarray(observation, dtype=np.float64)
        if self.standardization is not None:
            mean, scale, clip = self.standardization
            values = np.clip((values - mean) / scale, -clip, clip)
        for weight, bias in self.layers[:-1]:
            values = np.tanh(values @ weight.T + bias)
        weight, bias = self.layers[-1]
        return np.clip(values @ weight.T + bias, self.low, self.high)


def success_rate(policy: Callable[[np.ndarray], np.ndarray], courses: int = 200,
                 seed: int = 1_000_000, **parameters) -> float:
    """
    Return the share of courses the policy finishes within the step limit.

    The courses are those of a WaypointsVectorEnv of that many robots reset with seed (held out
    from training, which uses small seeds); each robot drives its first episode to its end.
    """
    env = WaypointsVectorEnv(courses, **parameters)
    observations, _ = env.reset(seed=seed)
    finished = np.zeros(courses, dtype=bool)
    ended = np.zeros(courses, dtype=bool)
    while not ended.all():
        observations, _, terminated, truncated, _ = env.step(policy(observations))
        finished |= terminated & ~ended
        ended |= terminated | truncated
    return float(finished.mean())
