"""
Steps per second of the Gymnasium environments, beside IR-SIM and irsim-x on the same scenario.

The scenario: the lab's room (20 m x 15 m, walls round it), the lab's robot (a 0.2 m disc,
unicycle) with a 64-ray laser over +-120 degrees reaching 4.09 m, stepped at 10 Hz with a
random action each step, episodes starting again as they end. waypoint_lab/Waypoints-v0 is made
with gym.make (its wrappers included); the vector with 100 robots with gym.make_vec. IR-SIM
(on PyPI as ir-sim, installed by this benchmark into a virtual environment of its own in the
package's cache folder, never into ours) runs the same room as four wall rectangles and the same
robot and laser, headless; so does irsim-x (IR-SIM with its lidar, collisions and kinematics
in C++; the same `irsim` module and API), in a venv of its own. Figures are the median of
REPEATS runs of STEPS steps each, and the ratio is taken from those medians, measured one right
after the other.
"""

import argparse
import json
import os
from pathlib import Path
import statistics
import subprocess
import sys
import time

import gymnasium as gym
import numpy as np
import waypoint_lab.learning  # noqa: F401  (registers the environments)

STEPS = 3000
VECTOR_STEPS = 300
ROBOTS = 100
REPEATS = 5
IRSIM_STEPS = 300
# Beside the interface builds' cache (scripts/build_interfaces.sh), out of the work tree.
CACHE = Path(os.environ.get('SIMPLE_ROBOT_CONTROL_CACHE') or Path(
    os.environ.get('XDG_CACHE_HOME') or Path.home() / '.cache') / 'simple_robot_control')
# Each peer: (its name, its PyPI package, its venv in the cache).
PEERS = (('IR-SIM', 'ir-sim', CACHE / 'irsim-venv'), ('irsim-x', 'irsim-x', CACHE / 'irsimx-venv'))
IRSIM_WORLD = """
world: {height: 15, width: 20, step_time: 0.1, sample_time: 0.1, offset: [0, 0],
        collision_mode: stop, control_mode: auto}
robot:
  - kinematics: {name: diff}
    shape: {name: circle, radius: 0.2}
    state: [1, 2, 0]
    vel_min: [-0.5, -1.0]
    vel_max: [0.5, 1.0]
    sensors:
      - {type: lidar2d, range_min: 0.06, range_max: 4.09, angle_range: 4.1888, number: 64,
         noise: false}
obstacle:
  - {shape: {name: rectangle, length: 20, width: 0.35}, state: [10, 0.175, 0], kinematics: null}
  - {shape: {name: rectangle, length: 20, width: 0.35}, state: [10, 14.825, 0], kinematics: null}
  - {shape: {name: rectangle, length: 0.35, width: 15}, state: [0.175, 7.5, 0], kinematics: null}
  - {shape: {name: rectangle, length: 0.35, width: 15}, state: [19.825, 7.5, 0], kinematics: null}
"""
IRSIM_RUN = """
import json, sys, time
import numpy as np
import irsim
env = irsim.make(sys.argv[1], display=False, disable_all_plot=True, log_level="WARNING")
rng = np.random.default_rng(0)
rates = []
for _ in range(int(sys.argv[3])):
    start = time.perf_counter()
    for _ in range(int(sys.argv[2])):
        env.step(rng.uniform([-0.5, -1.0], [0.5, 1.0]).reshape(2, 1))
        if env.done():
            env.reset()
    rates.append(int(sys.argv[2]) / (time.perf_counter() - start))
print(json.dumps(rates))
"""


def single_rate(env, rng, steps):
    env.reset(seed=0)
    start = time.perf_counter()
    for _ in range(steps):
        _, _, terminated, truncated, _ = env.step(rng.uniform([-0.5, -1.0], [0.5, 1.0]).astype(
            np.float32))
        if terminated or truncated:
            env.reset()
    return steps / (time.perf_counter() - start)


def vector_rate(env, rng, steps):
    env.reset(seed=0)
    start = time.perf_counter()
    for _ in range(steps):
        env.step(rng.uniform([-0.5, -1.0], [0.5, 1.0], (env.num_envs, 2)).astype(np.float32))
    return env.num_envs * steps / (time.perf_counter() - start)


def peer_rates(name, package, venv):
    """Return a peer's steps per second (REPEATS runs), or None where it does not install."""
    python = venv / 'bin' / 'python'
    try:
        if not python.exists():
            subprocess.run([sys.executable, '-m', 'venv', str(venv)], check=True)
            subprocess.run([str(python), '-m', 'pip', 'install', '--quiet', package],
                           check=True, stderr=subprocess.DEVNULL)
        world = venv / 'lab_room.yaml'
        world.write_text(IRSIM_WORLD)
        result = subprocess.run([str(python), '-c', IRSIM_RUN, str(world), str(IRSIM_STEPS),
                                 str(REPEATS)], capture_output=True, text=True, check=True,
                                env=dict(os.environ, MPLBACKEND='Agg'), timeout=1800)
        return json.loads(result.stdout.strip().splitlines()[-1])
    except (OSError, subprocess.SubprocessError, ValueError, IndexError) as error:
        print(f'{name} not measured: {error}')
        return None


def main(argv=None):
    parser = argparse.ArgumentParser(prog='bench.learning', description=__doc__.split('\n')[1])
    parser.add_argument('--smoke', action='store_true',
                        help='tiny sizes, seconds, no IR-SIM: that it runs and prints its figures')
    args = parser.parse_args(argv)
    steps, vector_steps, robots, repeats = (50, 5, 10, 1) if args.smoke else (
        STEPS, VECTOR_STEPS, ROBOTS, REPEATS)
    rng = np.random.default_rng(0)
    single = gym.make('waypoint_lab/Waypoints-v0')
    single_rate(single, rng, 20 if args.smoke else 200)
    singles = [single_rate(single, rng, steps) for _ in range(repeats)]
    vector = gym.make_vec('waypoint_lab/Waypoints-v0', num_envs=robots,
                          vectorization_mode='vector_entry_point')
    vector_rate(vector, rng, 2 if args.smoke else 20)
    vectors = [vector_rate(vector, rng, vector_steps) for _ in range(repeats)]
    print(f'waypoint_lab/Waypoints-v0, one robot, 64-ray laser: median '
          f'{statistics.median(singles):,.0f} steps/s (runs: '
          f'{", ".join(f"{rate:,.0f}" for rate in singles)})')
    print(f'vector of {robots} robots in one world: median {statistics.median(vectors):,.0f} '
          f'robot-steps/s (runs: {", ".join(f"{rate:,.0f}" for rate in vectors)}): '
          f'{statistics.median(vectors) / statistics.median(singles):.1f}x the single '
          "environment's steps/s")
    if args.smoke:
        print('IR-SIM and irsim-x not measured: smoke run')
        return 0
    for name, package, venv in PEERS:
        rates = peer_rates(name, package, venv)
        if rates:
            print(f'{name}, same room, robot and laser: median {statistics.median(rates):,.1f} '
                  f'steps/s (runs: {", ".join(f"{rate:,.1f}" for rate in rates)})')
            print(f'ratio, stdr_lite single to {name}: '
                  f'{statistics.median(singles) / statistics.median(rates):,.1f}x')
    return 0


if __name__ == '__main__':
    sys.exit(main())
