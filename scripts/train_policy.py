"""
Train PPO (Stable-Baselines3) on the lab's task, then save the policy for numpy alone.

Run by `make train` in a venv of its own (torch and Stable-Baselines3 never enter the package's
venv). It trains on WaypointsVectorEnv's robots through the SB3 adapter for a wall-clock budget,
saves the policy network's weights with observations and the actions torch gave for them
(numpy_policy.py runs them; a test checks that it gives the same actions), and reports the
success rate of that numpy policy on held-out seeded courses.

    python scripts/train_policy.py [--minutes 15] [--output policy.npz]
"""

import argparse
import time

import numpy as np
from stable_baselines3 import PPO
from stable_baselines3.common.callbacks import BaseCallback
from stable_baselines3.common.vec_env import VecMonitor
import torch
from waypoint_lab.learning.numpy_policy import NumpyPolicy, success_rate
from waypoint_lab.learning.sb3_vec_env import sb3_vec_env

ROBOTS = 32
CHECKED_OBSERVATIONS = 64
EVALUATION_SEED = 1_000_000


class WallClockBudget(BaseCallback):
    """Stops training once its minutes are spent, printing progress every minute."""

    def __init__(self, minutes):
        super().__init__()
        self._end = time.monotonic() + 60.0 * minutes
        self._shown = time.monotonic()

    def _on_step(self):
        if time.monotonic() - self._shown > 60.0:
            self._shown = time.monotonic()
            episodes = self.model.ep_info_buffer
            print(f'  {self.num_timesteps:,} steps; last {len(episodes)} episodes: return '
                  f'{np.mean([episode["r"] for episode in episodes]):.1f}, length '
                  f'{np.mean([episode["l"] for episode in episodes]):.0f} steps', flush=True)
        return time.monotonic() < self._end


def export(model, env, path):
    """Save the policy's layers (tanh MLP, then the action mean) and a check of them."""
    policy = model.policy
    layers = [module for module in policy.mlp_extractor.policy_net if hasattr(module, 'weight')]
    layers.append(policy.action_net)
    # Observations the policy meets driving: a reset's, then its first steps'.
    observations = [env.reset()]
    while sum(map(len, observations)) < CHECKED_OBSERVATIONS:
        env.step_async(model.predict(observations[-1], deterministic=True)[0])
        observations.append(env.step_wait()[0])
    observations = np.concatenate(observations)[:CHECKED_OBSERVATIONS]
    actions = model.predict(observations, deterministic=True)[0]
    arrays = {f'weight{index}': layer.weight.detach().numpy() for index, layer in
              enumerate(layers)}
    arrays.update({f'bias{index}': layer.bias.detach().numpy() for index, layer in
                   enumerate(layers)})
    np.savez_compressed(path, **arrays, low=env.action_space.low, high=env.action_space.high,
                        check_observations=observations.astype(np.float32),
                        check_actions=actions.astype(np.float32))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[1])
    parser.add_argument('--minutes', type=float, default=15.0)
    parser.add_argument('--output', default='policy.npz')
    parser.add_argument('--courses', type=int, default=200)
    options = parser.parse_args()
    torch.set_num_threads(1)
    env = VecMonitor(sb3_vec_env(ROBOTS))
    env.seed(0)
    model = PPO('MlpPolicy', env, n_steps=256, batch_size=2048, n_epochs=5, learning_rate=3e-4,
                gamma=0.99, gae_lambda=0.95, clip_range=0.2, ent_coef=0.0,
                policy_kwargs={'net_arch': [64, 64], 'log_std_init': -0.5}, seed=0, verbose=0,
                device='cpu')
    started = time.monotonic()
    print(f'Training PPO on {ROBOTS} robots for {options.minutes:g} min', flush=True)
    model.learn(total_timesteps=10 ** 9, callback=WallClockBudget(options.minutes))
    print(f'trained: {model.num_timesteps:,} steps in {time.monotonic() - started:.0f} s',
          flush=True)
    export(model, env, options.output)
    policy = NumpyPolicy(options.output)
    rate = success_rate(policy, options.courses, EVALUATION_SEED)
    print(f'success (FINISHED within the step limit) on {options.courses} held-out courses: '
          f'{rate:.1%}; policy written to {options.output}', flush=True)


if __name__ == '__main__':
    main()
