"""The reference coursework nodes' parameter tables: plain data, light to load."""

from courseworks.names import SUBMITTED_MAP_TOPIC
from simple_robot_control.parameter_specs import ParameterSpec
from simple_robot_control.validation import Bounds
from waypoint_lab.parameters import RUNNER_PARAMETERS

DISTANCE = Bounds(0.0, 10.0)

OCCUPANCY_MAPPER_PARAMETERS = (
    ParameterSpec('robot_name', 'robot0', 'the robot whose laser and odometry make the map: '
                  'topics <name>/<laser> and <name>/odom', ros_name=True),
    ParameterSpec('laser', 'laser_0', "the laser's topic under the robot (STDR's laser_N)",
                  ros_name=True),
    ParameterSpec('laser_pose', [0.0, 0.0, 0.0], "the laser's pose on the robot [m, m, rad] "
                  "(the small laser robot's is at its centre)"),
    ParameterSpec('map_topic', SUBMITTED_MAP_TOPIC, 'where the map goes, as nav_msgs/'
                  'OccupancyGrid (transient local): the mapping task judges this topic',
                  topic=True),
    ParameterSpec('publish_every', 10, 'publish the map every this many scans (and on exit)',
                  Bounds(1.0, 10000.0)),
)

PLANNER_CONTROLLER_PARAMETERS = RUNNER_PARAMETERS + (
    ParameterSpec('robot_radius', 0.1, "the robot's footprint radius, kept off the walls (the "
                  "courseworks' small laser robot's) [m]", DISTANCE),
    ParameterSpec('wall_margin', 0.15, 'clearance kept beyond the radius where the map leaves '
                  'room for it, for the control error [m]', DISTANCE),
    ParameterSpec('map_topic', '/map', 'the nav_msgs/OccupancyGrid planned on (transient local): '
                  "the simulator's /map, or a mapper's growing map (unknown cells are tried)",
                  topic=True),
    ParameterSpec('explore_for', 0.0, "explore the map's frontiers first, nearest first, for "
                  'at most this long, then drive the goals (the exploration coursework); 0: '
                  'drive the goals at once [s of odometry time]', Bounds(0.0, 86400.0)),
    ParameterSpec('max_map_age', 0.0, "for a mapper's map: act on a pose only once a map "
                  'stamped at most this long before it is in (in lockstep the robot then never '
                  'outruns its mapper); 0: never wait (a map of no time) [s]',
                  Bounds(0.0, 60.0)),
)
