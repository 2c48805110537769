"""
The Gymnasium environments' speed in CPU time, beside IR-SIM and irsim-x on the same scenario.

The scenario: the lab's room (20 m x 15 m, walls round it), the lab's robot (a 0.2 m disc,
unicycle) with a 64-ray laser over +-120 degrees reaching 4.09 m, stepped at 10 Hz with a
random action each step (drawn before the clock starts, for every party: numpy's draw of one
action costs about 15 us, a tenth of a step), episodes starting again as they end.
waypoint_lab/Waypoints-v0 is made with gym.make (its wrappers included); the vector with 100
robots with gym.make_vec. IR-SIM
and irsim-x (IR-SIM with its lidar, collisions and kinematics in C++; the same `irsim` module),
pinned to the versions in PEERS, run the same room as four wall rectangles and the same robot
and laser, headless, each installed by this benchmark into a virtual environment of its own in
the package's cache folder (never into ours; irsim-x has no wheel for Python 3.11, so pip
compiles its C++: about 3 minutes, once). A peer that cannot be installed is said so.

Every figure is steps per second of the process's CPU time, not of wall time: on a shared
machine wall-clock ratios to the peers moved from 1.0x to 6.0x with the load, CPU time held.
Rounds are interleaved: ours, then each peer in its own long-lived process, round after round,
so a change of load falls on every party alike; a figure is the median of ROUNDS rounds, a
ratio the median of the rounds' ratios, each printed with its range. Where a single step's
CPU time goes is printed too: the world's step, the laser, the task (goal sets, reward,
observation), the commands, and what is left (the environment's own code and Gymnasium's
wrappers).
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
ROUNDS = 7
IRSIM_STEPS = 300
# The targets of the ratios (issue 41): to each peer, and of the vector to the single env.
TARGETS = {'IR-SIM': 8.0, 'irsim-x': 3.0, 'vector': 20.0}
# Beside the interface builds' cache (scripts/build_interfaces.sh), out of the work tree.
CACHE = Path(os.environ.get('SIMPLE_ROBOT_CONTROL_CACHE') or Path(
    os.environ.get('XDG_CACHE_HOME') or Path.home() / '.cache') / 'simple_robot_control')
# Each peer: (its name, its pinned PyPI requirement, its venv in the cache).
PEERS = (('IR-SIM', 'ir-sim==2.12.0', CACHE / 'irsim-venv'),
         ('irsim-x', 'irsim-x==1.1.4', CACHE / 'irsimx-venv'))
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
PEER_RUN = """
import json, sys, time
import numpy as np
import irsim
env = irsim.make(sys.argv[1], display=False, disable_all_plot=True, log_level="WARNING")
rng = np.random.default_rng(0)
for line in sys.stdin:
    steps = int(line)
    actions = rng.uniform([-0.5, -1.0], [0.5, 1.0], (steps, 2))[:, :, None]
    start = time.process_time()
    for action in actions:
        env.step(action)
        if env.done():
            env.reset()
    print("RATE", json.dumps(steps / (time.process_time() - start)), flush=True)
"""


def random_actions(rng, count=None):
    shape = (2,) if count is None else (count, 2)
    return rng.uniform([-0.5, -1.0], [0.5, 1.0], shape).astype(np.float32)


def single_rate(env, rng, steps):
    """Return the single environment's steps per CPU-second over steps steps."""
    actions = random_actions(rng, steps)
    start = time.process_time()
    for action in actions:
        _, _, terminated, truncated, _ = env.step(action)
        if terminated or truncated:
            env.reset()
    return steps / (time.process_time() - start)


def vector_rate(env, rng, steps):
    """Return the vector's robot-steps per CPU-second over steps steps."""
    actions = [random_actions(rng, env.num_envs) for _ in range(steps)]
    start = time.process_time()
    for action in actions:
        env.step(action)
    return env.num_envs * steps / (time.process_time() - start)


class Parts:
    """CPU time spent in named parts of an environment, by timing some of its objects' methods."""

    def __init__(self):
        self.seconds = {}

    def time(self, owner, method, part):
        """Count the CPU time of owner.method (on this object only) towards part."""
        original = getattr(owner, method)
        self.seconds.setdefault(part, 0.0)

        def timed(*args, **kwargs):
            start = time.process_time()
            try:
                return original(*args, **kwargs)
            finally:
                self.seconds[part] += time.process_time() - start
        setattr(owner, method, timed)


def step_costs(rng, steps):
    """Return microseconds of CPU per step of the single environment, by part."""
    env = gym.make('waypoint_lab/Waypoints-v0')
    env.reset(seed=1)
    arena = env.unwrapped.arena
    parts = Parts()
    parts.time(arena.simulation, 'step', 'world')
    parts.time(arena.simulation, 'read_lasers', 'laser')
    parts.time(arena, 'observations', 'observation')
    parts.time(arena.courses, 'update', 'goal sets and reward')
    parts.time(arena, 'act', 'commands')
    total = steps / single_rate(env, rng, steps)
    seconds = dict(parts.seconds)
    seconds['observation'] -= seconds['laser']
    seconds['environment and wrappers'] = total - sum(seconds.values())
    env.close()
    return {part: 1e6 * value / steps for part, value in seconds.items()}, 1e6 * total / steps


class Peer:
    """A peer simulator in a process of its own, stepping the scenario when asked."""

    def __init__(self, name, requirement, venv):
        self.name, self.requirement, self.venv = name, requirement, venv
        self.process = None

    def start(self):
        """Install the peer if needed and start it; return why it cannot run, or None."""
        python = self.venv / 'bin' / 'python'
        stamp = self.venv / 'installed.txt'
        if not (stamp.exists() and stamp.read_text() == self.requirement):
            subprocess.run([sys.executable, '-m', 'venv', '--clear', str(self.venv)],
                           check=True)
            result = subprocess.run([str(python), '-m', 'pip', 'install', '--quiet',
                                     self.requirement], capture_output=True, text=True)
            if result.returncode != 0:
                lines = (result.stderr or result.stdout).strip().splitlines() or ['no output']
                return f'could not be installed ({self.requirement}): {lines[-1]}'
            stamp.write_text(self.requirement)
        world = self.venv / 'lab_room.yaml'
        world.write_text(IRSIM_WORLD)
        self.process = subprocess.Popen([str(python), '-c', PEER_RUN, str(world)],
                                        stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                        text=True, env=dict(os.environ, MPLBACKEND='Agg'))
        return None

    def rate(self, steps):
        """Return the peer's steps per CPU-second over steps steps (its other output skipped)."""
        self.process.stdin.write(f'{steps}\n')
        self.process.stdin.flush()
        while True:
            line = self.process.stdout.readline()
            if not line:
                raise OSError(f'it ended (exit code {self.process.wait()})')
            if line.startswith('RATE '):
                return json.loads(line.split(' ', 1)[1])

    def warm_up(self):
        """Take a few steps before measuring; return why the peer cannot run, or None."""
        try:
            self.rate(IRSIM_STEPS // 10)
        except OSError as error:
            return str(error)
        return None

    def stop(self):
        if self.process is not None:
            self.process.stdin.close()
            self.process.wait(timeout=60)


def spread(values, digits=0):
    return f'{min(values):,.{digits}f} to {max(values):,.{digits}f}'


def verdict(ratio, target):
    return f'target >= {target:g}x: {"met" if ratio >= target else "missed"}'


def main(argv=None):
    parser = argparse.ArgumentParser(prog='bench.learning', description=__doc__.split('\n')[1])
    parser.add_argument('--smoke', action='store_true',
                        help='tiny sizes, seconds, no IR-SIM: that it runs and prints its figures')
    args = parser.parse_args(argv)
    steps, vector_steps, robots, rounds = (50, 5, 10, 2) if args.smoke else (
        STEPS, VECTOR_STEPS, ROBOTS, ROUNDS)
    rng = np.random.default_rng(0)
    single = gym.make('waypoint_lab/Waypoints-v0')
    single.reset(seed=0)
    single_rate(single, rng, 20 if args.smoke else 200)
    vector = gym.make_vec('waypoint_lab/Waypoints-v0', num_envs=robots,
                          vectorization_mode='vector_entry_point')
    vector.reset(seed=0)
    vector_rate(vector, rng, 2 if args.smoke else 20)
    peers = []
    for name, requirement, venv in ([] if args.smoke else PEERS):
        peer = Peer(name, requirement, venv)
        problem = peer.start()
        if problem is None:
            problem = peer.warm_up()
        if problem is None:
            peers.append(peer)
        else:
            print(f'{name} not measured: {problem}')
    rates = {'single': [], 'vector': [], **{peer.name: [] for peer in peers}}
    try:
        for _ in range(rounds):
            rates['single'].append(single_rate(single, rng, steps))
            rates['vector'].append(vector_rate(vector, rng, vector_steps))
            for peer in list(peers):
                try:
                    rates[peer.name].append(peer.rate(IRSIM_STEPS))
                except OSError as error:
                    print(f'{peer.name} not measured: {error}')
                    peers.remove(peer)
    finally:
        for peer in peers:
            peer.stop()
    singles = rates['single']
    print(f'waypoint_lab/Waypoints-v0, one robot, 64-ray laser: median '
          f'{statistics.median(singles):,.0f} steps per CPU-second (rounds: {spread(singles)})')
    ratios = [v / s for v, s in zip(rates['vector'], singles)]
    print(f'vector of {robots} robots in one world: median '
          f'{statistics.median(rates["vector"]):,.0f} robot-steps per CPU-second (rounds: '
          f'{spread(rates["vector"])}): {statistics.median(ratios):.1f}x the single '
          f"environment's steps/s (rounds: {spread(ratios, 1)}; "
          f'{verdict(statistics.median(ratios), TARGETS["vector"])})')
    costs, total = step_costs(rng, steps)
    print(f'a step of the single environment, {total:.0f} us of CPU: ' + ', '.join(
        f'{part} {cost:.0f}' for part, cost in costs.items()))
    if args.smoke:
        print('IR-SIM and irsim-x not measured: smoke run')
        return 0
    for peer in peers:
        ratios = [s / p for s, p in zip(singles, rates[peer.name])]
        print(f'{peer.name} ({peer.requirement}), same room, robot and laser: median '
              f'{statistics.median(rates[peer.name]):,.0f} steps per CPU-second (rounds: '
              f'{spread(rates[peer.name])})')
        median = statistics.median(ratios)
        print(f'ratio, stdr_lite single to {peer.name}: {median:.1f}x (rounds: '
              f'{spread(ratios, 1)}; {verdict(median, TARGETS[peer.name])})')
    return 0


if __name__ == '__main__':
    sys.exit(main())
