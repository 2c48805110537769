"""
A world built from files: a map_server map and robot files, as the stdr_lite node builds its own.

load_world is the door to the simulation from plain Python (a notebook, a learning loop, a
test of a control law): the node builds its simulation with it too, from its parameters, so a
world made here behaves as the node's does, step for step. No ROS here.
"""

from collections.abc import Iterable
import os

from simple_robot_control.occupancy_map import load_map
from simple_robot_control.share import bundled_files, BUNDLED_MAP, BUNDLED_RESOURCES, shared_file
from stdr_lite.core.entities import SimulationSettings
from stdr_lite.core.robot_description import load_robot, RobotEntry
from stdr_lite.core.setting_values import DEFAULT_POSE
from stdr_lite.core.simulation import Simulation


def map_file(name: str | os.PathLike = '') -> str:
    """Return a map_server YAML: a path as given, a bundled map by name, '' for lab_room."""
    name = os.fspath(name)
    if not name:
        return shared_file(*BUNDLED_MAP)
    return bundled_files('maps').get(name, name)


def robot_file(name: str | os.PathLike = '') -> str:
    """Return a robot file: a path as given, a bundled robot by name, '' for lab_robot."""
    name = os.fspath(name) or 'lab_robot'
    return bundled_files('robots').get(name, name)


def robot_entries(robots: Iterable, search_path: tuple = ()) -> list[RobotEntry]:
    """
    Return RobotEntry objects for robots: entries already, or (name, pose[, robot file]).

    Each robot file is read once however many robots share it.
    """
    loaded, entries = {}, []
    for robot in robots:
        if isinstance(robot, RobotEntry):
            entries.append(robot)
            continue
        name, pose, *file = robot
        path = robot_file(file[0] if file else '')
        if path not in loaded:
            loaded[path] = load_robot(path, tuple(search_path) + (shared_file(
                *BUNDLED_RESOURCES),))
        entries.append(RobotEntry(name, loaded[path], tuple(float(value) for value in pose)))
    return entries


def load_world(map_name: str | os.PathLike = '',
               robots: Iterable = (('robot0', DEFAULT_POSE),),
               settings: SimulationSettings = SimulationSettings(),
               search_path: tuple = ()) -> Simulation:
    """
    Build a simulation from files.

    map_name is a map_server YAML, or a bundled map by name ('' for the lab's lab_room); robots
    are RobotEntry objects or (name, (x, y, theta)[, robot file]) tuples, a robot file in any
    layout stdr_lite reads (STDR's XML and YAML, the flat YAML) or a bundled robot by name
    (lab_robot by default); search_path lists folders where robot files' includes are looked
    for, before the bundled resources. Raises MapError, RobotFileError, PlacementError or
    RequestError with one line naming what is wrong.
    """
    return Simulation(load_map(map_file(map_name)), settings, robot_entries(robots, search_path))
