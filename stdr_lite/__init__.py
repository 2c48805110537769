"""
stdr_lite: a small STDR-equivalent simulator for unicycle robots, in ROS 2 and in plain Python.

The simulation itself has no ROS in it, and is this package's Python API: the node runs the
same Simulation on STDR's topics.

    from stdr_lite import load_world
    world = load_world('lab_room', robots=[('robot0', (1.0, 2.0, 0.0), 'lab_robot')])
    world.command('robot0', 0.5, 0.2)   # linear m/s, angular rad/s, held until the next
    world.step()                          # one step of 1/rate_hz simulated seconds
    world.pose('robot0')                  # (x, y, theta) in the map frame

waypoint_lab.learning holds the Gymnasium environments built on it.
"""

import importlib

# The Python API is imported on first use (PEP 562): the tools that only talk to a running
# node (stdr_ctl, move_robot, grade_lab) then start without the simulation's numba and scipy,
# 0.6 s of every start.
_HOMES = {'load_world': 'stdr_lite.core.loading', 'OdometryNoise': 'stdr_lite.core.setting_values',
          'PlacementError': 'stdr_lite.core.bodies', 'RequestError': 'stdr_lite.core.entities',
          'RobotEntry': 'stdr_lite.core.robot_description',
          'Simulation': 'stdr_lite.core.simulation',
          'SimulationSettings': 'stdr_lite.core.entities'}

__all__ = sorted(_HOMES)


def __getattr__(name: str):
    if name not in _HOMES:
        raise AttributeError(f'module {__name__!r} has no attribute {name!r}')
    return getattr(importlib.import_module(_HOMES[name]), name)


def __dir__() -> list:
    return sorted(set(globals()) | set(_HOMES))
