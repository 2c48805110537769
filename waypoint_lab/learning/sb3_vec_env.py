"""
The robots of WaypointsVectorEnv as Stable-Baselines3's vector environment, each a sub-env.

SB3 trains on a vector API of its own: reset() gives the observations alone (their infos in
reset_infos); step_async() then step_wait() give observations, rewards, dones and a list of
infos, a sub-environment that ended having reset itself, with its last observation in
info['terminal_observation'] and info['TimeLimit.truncated'] saying whether the step limit ended
it. SB3Steps is that contract over the vector environment's same-step autoreset, with no SB3
import, so it is tested where SB3 is not installed; sb3_vec_env() makes one an instance of SB3's
VecEnv (SB3 checks the class) where SB3 is.
"""

from typing import TYPE_CHECKING

import numpy as np
from waypoint_lab.learning.vector_env import WaypointsVectorEnv

if TYPE_CHECKING:  # stable-baselines3 is optional: imported only to make one
    from stable_baselines3.common.vec_env import VecEnv


class SB3Steps:
    """SB3's VecEnv contract over a WaypointsVectorEnv of num_envs robots (its parameters)."""

    def __init__(self, num_envs: int = 8, **parameters):
        self.env = WaypointsVectorEnv(num_envs, autoreset_mode='SameStep', **parameters)
        self.num_envs = num_envs
        self.observation_space = self.env.single_observation_space
        self.action_space = self.env.single_action_space
        self.reset_infos = [{} for _ in range(num_envs)]
        self._seed = None
        self._actions = None

    def seed(self, seed: int | None = None) -> list:
        """Seed sub-environment i with seed + i at the next reset, as SB3's VecEnvs do."""
        self._seed = seed
        return [None if seed is None else seed + index for index in range(self.num_envs)]

    def reset(self) -> np.ndarray:
        observations, infos = self.env.reset(seed=self._seed)
        self._seed = None
        self.reset_infos = self._split(infos)
        return observations

    def step_async(self, actions: np.ndarray) -> None:
        self._actions = np.asarray(actions)

    def step_wait(self) -> tuple:
        observations, rewards, terminated, truncated, infos = self.env.step(self._actions)
        dones = terminated | truncated
        listed = self._split(infos)
        for index in np.flatnonzero(dones):
            listed[index]['terminal_observation'] = infos['final_obs'][index]
            listed[index]['TimeLimit.truncated'] = bool(truncated[index]
                                                        and not terminated[index])
        return observations, rewards.astype(np.float32), dones, listed

    def _split(self, infos: dict) -> list[dict]:
        """Turn the vector's batched infos (pose, waypoint, reached) into one dict per robot."""
        return [{key: infos[key][index] for key in ('pose', 'waypoint', 'reached')}
                for index in range(self.num_envs)]

    def close(self) -> None:
        self.env.close()

    def _indices(self, indices):
        if indices is None:
            return range(self.num_envs)
        return [indices] if isinstance(indices, int) else indices

    def get_attr(self, attr_name: str, indices: object = None) -> list:
        """Return the attribute of each sub-environment asked for: the vector's, shared."""
        return [getattr(self.env, attr_name) for _ in self._indices(indices)]

    def set_attr(self, attr_name: str, value: object, indices: object = None) -> None:
        setattr(self.env, attr_name, value)

    def env_method(self, method_name: str, *method_args, indices: object = None,
                   **method_kwargs) -> list:
        result = getattr(self.env, method_name)(*method_args, **method_kwargs)
        return [result for _ in self._indices(indices)]

    def env_is_wrapped(self, wrapper_class: type, indices: object = None) -> list:
        return [False for _ in self._indices(indices)]


def sb3_vec_env(num_envs: int = 8, **parameters) -> 'VecEnv':
    """Return SB3Steps as a stable_baselines3 VecEnv (needs stable-baselines3 installed)."""
    from stable_baselines3.common.vec_env import VecEnv

    class WaypointsSB3VecEnv(SB3Steps, VecEnv):
        # SB3Steps' methods come first: its seed() and reset() replace VecEnv's.
        def __init__(self):
            SB3Steps.__init__(self, num_envs, **parameters)
            VecEnv.__init__(self, num_envs, self.observation_space, self.action_space)

    return WaypointsSB3VecEnv()
