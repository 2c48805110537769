"""waypoint_controller's parameter table: plain data, light to load (see early_parameters.py)."""

from simple_robot_control.parameter_specs import ParameterSpec
from simple_robot_control.validation import Bounds
from waypoint_controller.config import ControllerConfig
from waypoint_lab.parameters import COURSE_PARAMETERS

SPEED = Bounds(0.0, 10.0, low_open=True)
GAIN = Bounds(0.0, 1000.0)
PROPORTIONAL_GAIN = Bounds(0.0, 1000.0, low_open=True)

DEFAULTS = ControllerConfig()
PARAMETERS = COURSE_PARAMETERS + (
    ParameterSpec('max_linear_speed', DEFAULTS.max_linear_speed, 'speed limit [m/s]', SPEED,
                  tunable=True),
    ParameterSpec('max_angular_speed', DEFAULTS.max_angular_speed, 'turn-rate limit [rad/s]',
                  SPEED, tunable=True),
    ParameterSpec('control_rate_hz', 20.0, 'control loop rate [Hz of odometry stamp time]',
                  Bounds(5.0, 100.0)),
    ParameterSpec('stall_timeout', 10.0, 'abort when no progress towards the current waypoint '
                  'for this long [s of odometry stamp time]', Bounds(0.0, 3600.0, low_open=True)),
    ParameterSpec('heading_kp', DEFAULTS.heading_kp, 'heading PID proportional gain [1/s]',
                  PROPORTIONAL_GAIN, tunable=True),
    ParameterSpec('heading_ki', DEFAULTS.heading_ki, 'heading PID integral gain [1/s^2]', GAIN,
                  tunable=True),
    ParameterSpec('heading_kd', DEFAULTS.heading_kd, 'heading PID derivative gain [-]', GAIN,
                  tunable=True),
    ParameterSpec('distance_kp', DEFAULTS.distance_kp, 'distance PID proportional gain [1/s]',
                  PROPORTIONAL_GAIN, tunable=True),
    ParameterSpec('distance_ki', DEFAULTS.distance_ki, 'distance PID integral gain [1/s^2]',
                  GAIN, tunable=True),
    ParameterSpec('distance_kd', DEFAULTS.distance_kd, 'distance PID derivative gain [-]', GAIN,
                  tunable=True),
    ParameterSpec('robot_radius', 0.2, 'footprint radius kept off the walls of /map, when '
                  'a map is published [m]', Bounds(0.0, 10.0)),
    ParameterSpec('cmd_vel_stamped', False, 'send commands as geometry_msgs/TwistStamped, for a '
                  'simulator (or robot) that takes them so'),
)
