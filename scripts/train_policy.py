"""
Train PPO (skrl on JAX, CPU) on the lab's task, then save the policy for numpy alone.

Run by `make train` in a venv of its own (JAX and skrl never enter the package's venv; no
CUDA package either: JAX's CPU wheels come from PyPI as they are). It trains on
WaypointsVectorEnv's robots (the task's course distribution: turns in place, revisits, short
legs, legs across the map, waypoints near walls) for a wall-clock budget, saves the policy
network's weights with observations and the actions JAX gave for them (numpy_policy.py runs
them; a test checks that it gives the same actions), and reports the success rate of that
numpy policy on held-out seeded courses.

    python scripts/train_policy.py [--minutes 20] [--output policy.npz] [--robots 256]
"""

import argparse
import os
import sys
import tempfile
import time

# Before JAX loads: the CPU, and compiled programs kept across runs beside the venv.
os.environ.setdefault('JAX_PLATFORMS', 'cpu')
os.environ.setdefault('JAX_COMPILATION_CACHE_DIR', os.path.join(sys.prefix, 'jax-cache'))

from gymnasium.vector import AutoresetMode  # noqa: E402
import jax  # noqa: E402
import numpy as np  # noqa: E402
from skrl import config  # noqa: E402
from skrl.agents.jax.ppo import PPO  # noqa: E402
from skrl.envs.wrappers.jax import wrap_env  # noqa: E402
from skrl.memories.jax import RandomMemory  # noqa: E402
from skrl.resources.preprocessors.jax import RunningStandardScaler  # noqa: E402
from skrl.trainers.jax.sequential import SequentialTrainerCfg  # noqa: E402
from skrl.utils import set_seed  # noqa: E402
from skrl.utils.model_instantiators.jax import deterministic_model, gaussian_model  # noqa: E402
from waypoint_lab.learning.numpy_policy import NumpyPolicy, success_rate  # noqa: E402
from waypoint_lab.learning.vector_env import WaypointsVectorEnv  # noqa: E402

ROLLOUTS = 32
MINIBATCH = 2048
HIDDEN = [64, 64]
CHECKED_OBSERVATIONS = 64
EVALUATION_SEED = 1_000_000


def initialize(model, output_gain: float) -> None:
    """
    Give model's layers PPO's usual start, orthogonal weights and zero biases.

    Gain sqrt(2) within, output_gain at the output: skrl's default start gave actions near the
    bounds at once, so the robots drove into the walls and learned nothing in 10 million steps.
    """
    params = model.state_dict.params
    layers = params['params']['net_container']
    names = sorted(layers, key=lambda name: int(name.split('_')[1]))
    key = jax.random.PRNGKey(0)
    started = {}
    for index, name in enumerate(names):
        gain = output_gain if index == len(names) - 1 else np.sqrt(2.0)
        shape = layers[name]['kernel'].shape
        started[name] = {'kernel': jax.nn.initializers.orthogonal(gain)(
                             jax.random.fold_in(key, index), shape),
                         'bias': jax.numpy.zeros_like(layers[name]['bias'])}
    model.state_dict = model.state_dict.replace(
        params={**params, 'params': {**params['params'], 'net_container': started}})


def build(robots, folder):
    """
    Return (env, agent): PPO with tanh MLPs; skrl writes in folder.

    Observations and values are standardized by running statistics (a goal's distance runs to
    24 m beside laser ranges of 0 to 1), values are clipped as policies are, and a step limit
    is no terminal state (its value is bootstrapped).
    """
    config.jax.backend = 'jax'
    set_seed(0)
    env = wrap_env(WaypointsVectorEnv(robots, autoreset_mode=AutoresetMode.SAME_STEP),
                   wrapper='gymnasium')
    network = [{'name': 'net', 'input': 'OBSERVATIONS', 'layers': HIDDEN,
                'activations': 'tanh'}]
    spaces = {'observation_space': env.observation_space, 'action_space': env.action_space}
    # Actions are not clipped here (the environment clips them): skrl would take the
    # log-probability of the clipped action, not of the one drawn.
    policy = gaussian_model(**spaces, clip_actions=False, initial_log_std=-0.5,
                            network=network, output='ACTIONS')
    value = deterministic_model(**spaces, network=network, output='ONE')
    policy.init_state_dict(role='policy')
    value.init_state_dict(role='value')
    initialize(policy, 0.01)
    initialize(value, 1.0)
    agent = PPO(models={'policy': policy, 'value': value},
                memory=RandomMemory(memory_size=ROLLOUTS, num_envs=env.num_envs), **spaces,
                cfg={'rollouts': ROLLOUTS, 'learning_epochs': 5,
                     'mini_batches': max(1, ROLLOUTS * robots // MINIBATCH),
                     'learning_rate': 3e-4,
                     'observation_preprocessor': RunningStandardScaler,
                     'observation_preprocessor_kwargs': {'size': env.observation_space},
                     'value_preprocessor': RunningStandardScaler,
                     'value_preprocessor_kwargs': {'size': 1},
                     'discount_factor': 0.99, 'gae_lambda': 0.95, 'ratio_clip': 0.2,
                     'value_clip': 0.2, 'value_loss_scale': 0.5, 'grad_norm_clip': 0.5,
                     'entropy_loss_scale': 0.0, 'time_limit_bootstrap': True,
                     'experiment': {'directory': folder, 'write_interval': 0,
                                    'checkpoint_interval': 0}})
    return env, agent


def policy_mean(agent, observations):
    """Return the policy's deterministic action (its mean) for observations, within bounds."""
    policy = agent.models['policy']
    standardized = agent.checkpoint_modules['observation_preprocessor'](observations)
    mean, _ = policy.apply(policy.state_dict.params, {'observations': standardized}, 'policy')
    space = policy.action_space
    return np.clip(np.asarray(mean), space.low, space.high)


def export(agent, env, path):
    """Save the observations' scaling, the policy's layers and a check of them."""
    layers = agent.models['policy'].state_dict.params['params']['net_container']
    names = sorted(layers, key=lambda name: int(name.split('_')[1]))
    scaler = agent.checkpoint_modules['observation_preprocessor']
    arrays = {'observation_mean': np.asarray(scaler.running_mean),
              'observation_scale': np.sqrt(np.asarray(scaler.running_variance)) + scaler.epsilon,
              'observation_clip': np.float32(scaler.clip_threshold)}
    for index, name in enumerate(names):
        arrays[f'weight{index}'] = np.asarray(layers[name]['kernel']).T
        arrays[f'bias{index}'] = np.asarray(layers[name]['bias'])
    observations, _ = env.reset()
    observations = np.asarray(observations)[:CHECKED_OBSERVATIONS]
    space = agent.models['policy'].action_space
    np.savez_compressed(path, **arrays, low=space.low, high=space.high,
                        check_observations=observations.astype(np.float32),
                        check_actions=policy_mean(agent, observations).astype(np.float32))


def train(env, agent, minutes):
    """Step and learn until the budget is spent; print progress every minute; return steps."""
    agent.init(trainer_cfg=SequentialTrainerCfg(timesteps=10 ** 9, headless=True))
    agent.enable_training_mode(True)
    observations, _ = env.reset()
    end = time.monotonic() + 60.0 * minutes
    shown, step, returns, finished = time.monotonic(), 0, [], 0
    episode_return = np.zeros(env.num_envs)
    while time.monotonic() < end:
        agent.pre_interaction(timestep=step, timesteps=10 ** 9)
        actions = agent.act(observations, None, timestep=step, timesteps=10 ** 9)[0]
        next_observations, rewards, terminated, truncated, infos = env.step(actions)
        agent.record_transition(observations=observations, states=None, actions=actions,
                                rewards=rewards, next_observations=next_observations,
                                next_states=None, terminated=terminated, truncated=truncated,
                                infos=infos, timestep=step, timesteps=10 ** 9)
        agent.post_interaction(timestep=step, timesteps=10 ** 9)
        observations = next_observations
        episode_return += np.asarray(rewards).ravel()
        done = np.asarray(terminated).ravel().astype(bool)
        ended = done | np.asarray(truncated).ravel().astype(bool)
        finished += int(done.sum())
        returns += episode_return[ended].tolist()
        episode_return[ended] = 0.0
        step += 1
        if time.monotonic() - shown > 60.0:
            shown = time.monotonic()
            print(f'  {step * env.num_envs:,} steps; {len(returns)} episodes since last: '
                  f'return {np.mean(returns) if returns else float("nan"):.1f}, '
                  f'{finished / max(len(returns), 1):.0%} finished', flush=True)
            returns, finished = [], 0
    return step * env.num_envs


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[1])
    parser.add_argument('--minutes', type=float, default=20.0)
    parser.add_argument('--output', default='policy.npz')
    parser.add_argument('--courses', type=int, default=200)
    parser.add_argument('--robots', type=int, default=256)
    options = parser.parse_args()
    folder = tempfile.TemporaryDirectory(prefix='train_policy-')
    env, agent = build(options.robots, folder.name)
    print(f'Training PPO (skrl, JAX {jax.__version__} on the CPU) on {options.robots} robots '
          f'for {options.minutes:g} min', flush=True)
    started, cpu = time.monotonic(), time.process_time()
    steps = train(env, agent, options.minutes)
    wall, cpu = time.monotonic() - started, time.process_time() - cpu
    print(f'trained: {steps:,} steps in {wall:.0f} s ({steps / wall:,.0f} steps a second, '
          f'{steps / cpu:,.0f} per CPU-second)', flush=True)
    export(agent, env, options.output)
    folder.cleanup()
    policy = NumpyPolicy(options.output)
    rate = success_rate(policy, options.courses, EVALUATION_SEED)
    print(f'success (FINISHED within the step limit) on {options.courses} held-out courses: '
          f'{rate:.1%}; policy written to {options.output}', flush=True)


if __name__ == '__main__':
    main()
