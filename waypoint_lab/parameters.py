"""
The parameter tables of the lab's nodes: plain data, light to load.

The course's parameters are declared with the same meaning by every node that follows or
watches a course (waypoint_controller, course_monitor, policy_controller); each executable's
command line is judged against its table before the node's code loads (early_parameters.py).
"""

import dataclasses
import math

from simple_robot_control.parameter_specs import ParameterSpec
from simple_robot_control.validation import Bounds
from waypoint_lab.rules import (ANGLE_TOLERANCE, BUNDLED_COURSE, COURSE_TOPIC,
                                DISTANCE_TOLERANCE, MAX_ANGULAR_SPEED, MAX_LINEAR_SPEED,
                                STATUS_TOPIC)

COURSE_PARAMETERS = (
    ParameterSpec('waypoint_file', '', 'waypoint file (x y theta triples: m, m, degrees); '
                  'empty: the command-line argument, or else the bundled '
                  f'{BUNDLED_COURSE[-1]}'),
    ParameterSpec('robot_name', 'robot0', 'the robot of the run: topics <name>/odom and '
                  '<name>/cmd_vel', ros_name=True),
    ParameterSpec('distance_tolerance', DISTANCE_TOLERANCE, 'goal set radius d [m]',
                  Bounds(0.0, 10.0, low_open=True), tunable=True),
    ParameterSpec('angle_tolerance_deg', math.degrees(ANGLE_TOLERANCE),
                  'goal set heading tolerance t [degrees, as in the lab]',
                  Bounds(0.0, 180.0, low_open=True), tunable=True),
)

SPEED = Bounds(0.0, 10.0, low_open=True)

# What every controller of the lab takes (runner.py): the course, the speed limits it is held
# to, its pace and when it gives up.
RUNNER_PARAMETERS = COURSE_PARAMETERS + (
    ParameterSpec('max_linear_speed', MAX_LINEAR_SPEED, 'speed limit [m/s]', SPEED,
                  tunable=True),
    ParameterSpec('max_angular_speed', MAX_ANGULAR_SPEED, 'turn-rate limit [rad/s]', SPEED,
                  tunable=True),
    ParameterSpec('control_rate_hz', 20.0, 'control loop rate [Hz of odometry stamp time]',
                  Bounds(5.0, 100.0)),
    ParameterSpec('stall_timeout', 10.0, 'abort when no progress towards the current waypoint '
                  'for this long [s of odometry stamp time]', Bounds(0.0, 3600.0, low_open=True)),
    ParameterSpec('cmd_vel_stamped', False, 'send commands as geometry_msgs/TwistStamped, for a '
                  'simulator (or robot) that takes them so'),
)

# What makes a run of the lab: the controller's reports and course, every robot's odometry,
# ground truth and sensors (named laser_N and sonar_N, as STDR's robot files name them), the
# frames, the map and the time.
RUN_TOPICS = (f'/{STATUS_TOPIC}', f'/{COURSE_TOPIC}', '/tf', '/tf_static', '/map', '/clock',
              '*/odom', '*/ground_truth', '*/laser_*', '*/sonar_*')

RECORD_RUN_PARAMETERS = (
    ParameterSpec('bag', 'run.mcap', 'the bag to write, an .mcap file (replaced if it exists)'),
    ParameterSpec('topics', RUN_TOPICS, 'the topics to record: full names or patterns (* and ?, '
                  "as in shell globs: '*/odom' is every robot's odometry)"),
)

# The monitor only describes the run: the controller's tunable values are fixed here.
COURSE_MONITOR_PARAMETERS = tuple(dataclasses.replace(spec, tunable=False)
                                  for spec in COURSE_PARAMETERS) + (
    ParameterSpec('bag', '', "record the run's topics (robot_status, the course, odometry, "
                  'ground truth, TF, map, clock) into this rosbag2 bag in MCAP, for plot_run, '
                  'ros2 bag and Foxglove; empty: no record'),
    ParameterSpec('map_topic', '', "record a coursework's map published here too (a mapper's "
                  'nav_msgs/OccupancyGrid, for make scenario to judge); empty: none', topic=True),
)

# A policy acts at the rate and speeds it learned with: those are its task's, not parameters.
POLICY_CONTROLLER_PARAMETERS = tuple(
    spec for spec in RUNNER_PARAMETERS
    if spec.name not in ('max_linear_speed', 'max_angular_speed', 'control_rate_hz')) + (
    ParameterSpec('policy', '', 'the policy to drive with: an .npz file as scripts/'
                  "train_policy.py writes it; '' is the bundled one, trained by make train"),
)
