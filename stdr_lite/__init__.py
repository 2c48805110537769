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

from stdr_lite.core.entities import RequestError, SimulationSettings
from stdr_lite.core.loading import load_world
from stdr_lite.core.odometry import OdometryNoise
from stdr_lite.core.robot_description import RobotEntry
from stdr_lite.core.simulation import Simulation
from stdr_lite.core.world import PlacementError

__all__ = ['load_world', 'OdometryNoise', 'PlacementError', 'RequestError', 'RobotEntry',
           'Simulation', 'SimulationSettings']
