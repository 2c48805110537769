"""
The ROS-free doors in a Python without ROS 2: the API, the environments, the policy, the judges.

ROS 2's modules are hidden from the programs started here (a finder first on sys.meta_path,
from a sitecustomize on PYTHONPATH, refuses them as if they were not installed), as on a Mac
or Windows machine where `pip install .` gives no ROS wheels.
"""

import os
from pathlib import Path
import subprocess
import sys

from installed_executables import EXECUTABLES
from processes import executable
import pytest
from run_bags import write_run
from simple_robot_control.executables import ROS_MODULE

# ROS 2's modules as the executables tell them (simple_robot_control.executables.ROS_MODULE).
HIDE_ROS = f"""
import importlib.abc
import re
import sys

ROS = re.compile({ROS_MODULE.pattern!r})


class HiddenRos(importlib.abc.MetaPathFinder):
    def find_spec(self, name, path, target=None):
        if ROS.match(name):
            raise ModuleNotFoundError(f'No module named {{name!r}}', name=name)
        return None


sys.meta_path.insert(0, HiddenRos())
"""

DOORS = """
import sys

import gymnasium as gym
import numpy as np

from courseworks.grids import Grid
from courseworks.mapping import judge_map, Laser, seen_along
from simple_robot_control.occupancy_map import FREE, OCCUPIED
from stdr_lite import load_world, SimulationSettings
import waypoint_lab.learning
from waypoint_lab.learning.numpy_policy import NumpyPolicy
from waypoint_lab.learning.parallel_env import WaypointsParallelEnv

try:
    import rclpy
except ModuleNotFoundError:
    pass
else:
    sys.exit('rclpy is not hidden')

world = load_world('lab_room', robots=[('robot0', (1.0, 2.0, 0.0), 'lab_robot')],
                   settings=SimulationSettings(rate_hz=50.0, sensor_seed=1))
world.command('robot0', 0.5, 0.0)
for _ in range(50):
    world.step()
assert world.pose('robot0')[0] > 1.4, world.pose('robot0')
assert len(world.sensor_readings('robot0')) > 0

env = gym.make('waypoint_lab/Waypoints-v0')
observation, _ = env.reset(seed=0)
policy = NumpyPolicy()
for _ in range(20):
    observation, *_ = env.step(policy(observation))

robots = WaypointsParallelEnv(num_robots=3)
seen, _ = robots.reset(seed=0)
robots.step({agent: robots.action_space(agent).sample() for agent in robots.agents})

walls = np.zeros((40, 40), dtype=bool)
walls[0, :] = walls[-1, :] = walls[:, 0] = walls[:, -1] = True
sight = seen_along(Grid(walls, 0.1, (0.0, 0.0)), [(2.0, 2.0, 0.0)], Laser(-3.1, 3.1, 360, 4.0))
assert judge_map(sight, np.where(walls, OCCUPIED, FREE)).passed
print('doors open')
"""


@pytest.fixture(scope='module')
def without_ros(tmp_path_factory):
    """Give the environment of a program whose Python has no ROS 2."""
    folder = tmp_path_factory.mktemp('without_ros')
    (folder / 'sitecustomize.py').write_text(HIDE_ROS)
    path = os.environ.get('PYTHONPATH', '')
    return dict(os.environ, PYTHONPATH=f'{folder}{os.pathsep}{path}' if path else str(folder))


def test_the_api_environments_policy_and_judges_need_no_ros(without_ros, tmp_path):
    result = subprocess.run([sys.executable, '-c', DOORS], capture_output=True, text=True,
                            timeout=120, env=without_ros, cwd=tmp_path)
    assert result.returncode == 0 and 'doors open' in result.stdout, result.stderr


def test_plot_run_draws_a_bag_without_ros(without_ros, tmp_path):
    write_run(tmp_path / 'run.mcap').close()
    result = subprocess.run([executable('plot_run'), str(tmp_path / 'run.mcap')],
                            capture_output=True, text=True, timeout=60, env=without_ros)
    assert result.returncode == 0, result.stderr
    assert Path(tmp_path / 'run.png').stat().st_size > 10000


@pytest.mark.parametrize('name', sorted(name for name, declared in EXECUTABLES.items()
                                        if declared.ros))
def test_a_ros_executable_says_in_one_line_that_it_needs_ros(without_ros, name):
    result = subprocess.run([executable(name)], capture_output=True, text=True, timeout=30,
                            env=without_ros)
    assert result.returncode == 1
    assert result.stderr.startswith(f'{name}: error: needs ROS 2, and this Python has no module '
                                    "'rclpy': `make install` gives .venv the ROS 2 Jazzy wheels")
    assert len(result.stderr.splitlines()) == 1, result.stderr
