"""The reference coursework nodes' parameter tables: plain data, light to load."""

from simple_robot_control.parameter_specs import ParameterSpec
from simple_robot_control.validation import Bounds
from waypoint_lab.parameters import RUNNER_PARAMETERS

DISTANCE = Bounds(0.0, 10.0)

PLANNER_CONTROLLER_PARAMETERS = RUNNER_PARAMETERS + (
    ParameterSpec('robot_radius', 0.1, "the robot's footprint radius, kept off the walls (the "
                  "courseworks' small laser robot's) [m]", DISTANCE),
    ParameterSpec('wall_margin', 0.15, 'clearance kept beyond the radius where the map leaves '
                  'room for it, for the control error [m]', DISTANCE),
    ParameterSpec('map_topic', '/map', 'the nav_msgs/OccupancyGrid planned on (transient local): '
                  "the simulator's /map, or a mapper's growing map (unknown cells are tried)",
                  topic=True),
)
